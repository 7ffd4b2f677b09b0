//! Printing that a closed pipe cannot turn into a panic.
//!
//! `println!` panics ("failed printing to stdout: Broken pipe") when stdout is a pipe whose
//! reader has gone (`sinsbench gate ... | head -1`). Every line of this binary goes through
//! [`say!`] instead: once the reader has closed the pipe, further lines are dropped quietly and
//! the command carries on, so that it still writes all its files and exits with its own code.
//! Any other write error (a full disk behind a redirection) is returned, naming stdout.
//! Messages for stderr go through [`note!`], which never fails: there is nowhere left to report
//! a failure to write to stderr.

use anyhow::{Context, Result};
use std::io::{ErrorKind, Write};
use std::sync::atomic::{AtomicBool, Ordering};

/// Set once a write to stdout found the pipe closed.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Print one line on stdout, like `println!`; evaluates to `anyhow::Result<()>`. A closed pipe
/// is not an error (the line is dropped).
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::out::stdout_line(format_args!($($arg)*))
    };
}

/// Print one line on stderr, like `eprintln!`, ignoring any write error.
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::out::stderr_line(format_args!($($arg)*))
    };
}

pub(crate) use {note, say};

/// Write `line` and a newline to stdout (see [`say!`]).
pub fn stdout_line(line: std::fmt::Arguments<'_>) -> Result<()> {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        return Ok(());
    }
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{line}").and_then(|()| out.flush()) {
        Err(e) if e.kind() == ErrorKind::BrokenPipe => {
            STDOUT_CLOSED.store(true, Ordering::Relaxed);
            Ok(())
        }
        r => r.context("cannot write to standard output"),
    }
}

/// Write `line` and a newline to stderr (see [`note!`]).
pub fn stderr_line(line: std::fmt::Arguments<'_>) {
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}
