//! One writer per output directory: an advisory lock ([`std::fs::File::try_lock`], `flock` on
//! Unix) on a lock file in the directory that receives an output set, taken by every command
//! that writes one and held until the process ends.
//!
//! The lock file ([`LOCK_FILE`], or `.NAME.sinsbench.lock` for an output directory `NAME` that
//! is replaced whole by a rename, such as a report) holds the holder's process id and command
//! line, so that a second writer is refused at once with a message naming them. The kernel
//! releases the lock when the holder exits, however it exits (SIGKILL included): a lock file
//! left behind by a killed run blocks nothing. A holder removes its lock file when it ends
//! normally or on SIGINT/SIGTERM ([`release_all`]); a process that locked a file that was removed
//! in the meantime notices it (the path no longer leads to the file it locked) and starts again.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The lock file of an output directory.
pub const LOCK_FILE: &str = ".sinsbench.lock";

/// Locks held by this process: lock path and the open, locked file.
static HELD: Mutex<Vec<(PathBuf, File)>> = Mutex::new(Vec::new());

fn held() -> MutexGuard<'static, Vec<(PathBuf, File)>> {
    HELD.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Why an output directory could not be locked.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another process holds the lock.
    #[error(
        "{dir}: another sinsbench process is writing its output there ({holder}); wait for it to \
         end, or choose another output directory (lock file {lock})"
    )]
    Held {
        /// The output directory.
        dir: PathBuf,
        /// The lock file.
        lock: PathBuf,
        /// The holder as its lock file names it (`pid N: command line`).
        holder: String,
    },
    /// The lock file cannot be created or locked.
    #[error("{path}: cannot lock the output directory: {source}")]
    Io {
        /// The lock file.
        path: PathBuf,
        /// The error.
        #[source]
        source: std::io::Error,
    },
}

/// Whether `name` is the name of a lock file ([`LOCK_FILE`] or `.NAME.sinsbench.lock`), which is
/// not a temporary and not a leftover.
pub fn is_lock_file(name: &str) -> bool {
    name == LOCK_FILE || (name.starts_with('.') && name.ends_with(".sinsbench.lock"))
}

/// The lock file for the output set `set` in `dir`: `dir/.sinsbench.lock` for the directory
/// itself (`None`), `dir/.SET.sinsbench.lock` for an output directory `dir/SET` that is replaced
/// whole.
pub fn lock_path(dir: &Path, set: Option<&str>) -> PathBuf {
    match set {
        None => dir.join(LOCK_FILE),
        Some(name) => dir.join(format!(".{name}.sinsbench.lock")),
    }
}

/// Takes the lock of the output set `set` in `dir` (see [`lock_path`]) for the rest of this
/// process, creating `dir` if needed, and writes this process's id and command line into the
/// lock file. Taking a lock this process already holds does nothing. Refuses at once, naming the
/// holder, when another process holds it.
pub fn lock_output(dir: &Path, set: Option<&str>) -> Result<(), LockError> {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    std::fs::create_dir_all(dir).map_err(|source| LockError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let path = lock_path(dir, set);
    let key = dir
        .canonicalize()
        .map(|d| lock_path(&d, set))
        .unwrap_or_else(|_| path.clone());
    let mut held = held();
    if held.iter().any(|(p, _)| *p == key) {
        return Ok(());
    }
    let io = |source: std::io::Error| LockError::Io {
        path: path.clone(),
        source,
    };
    for _ in 0..100 {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(io)?;
        match file.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                let mut text = String::new();
                let _ = file.read_to_string(&mut text);
                let holder = describe_holder(&text);
                return Err(LockError::Held {
                    dir: dir.to_path_buf(),
                    lock: path,
                    holder,
                });
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(io(e)),
        }
        // The holder before us may have removed the file after we opened it: the lock is then on
        // a file no longer reachable by its name, and counts for nothing. Start again.
        if !same_file(&file, &path) {
            continue;
        }
        let command: Vec<String> = std::env::args().collect();
        let text = format!("{}\n{}\n", std::process::id(), command.join(" "));
        file.set_len(0).map_err(io)?;
        file.rewind().map_err(io)?;
        file.write_all(text.as_bytes()).map_err(io)?;
        held.push((key, file));
        return Ok(());
    }
    Err(io(std::io::Error::other(
        "the lock file kept being replaced; try again",
    )))
}

/// The holder as a lock file's text names it.
fn describe_holder(text: &str) -> String {
    let mut lines = text.lines();
    match (lines.next().map(str::trim), lines.next()) {
        (Some(pid), Some(cmd)) if !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()) => {
            format!("pid {pid}: `{}`", cmd.trim())
        }
        _ => "a process that has only just started; its pid is not yet written".into(),
    }
}

/// Whether `path` still leads to the open file `file`.
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Whether `path` still leads to the open file `file` (lock files are never removed here).
#[cfg(not(unix))]
fn same_file(_file: &File, _path: &Path) -> bool {
    true
}

/// Removes the lock files this process holds and releases the locks (for the end of the
/// process, a signal handler included; the kernel would release them anyway).
pub fn release_all() {
    let mut held = held();
    for (path, file) in held.drain(..) {
        if cfg!(unix) && same_file(&file, &path) {
            let _ = std::fs::remove_file(&path);
        }
        drop(file);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holder_text_is_described() {
        assert_eq!(
            describe_holder("12\nsinsbench simulate e.toml\n"),
            "pid 12: `sinsbench simulate e.toml`"
        );
        assert!(describe_holder("").contains("only just started"));
    }

    #[test]
    fn lock_file_names_are_recognised() {
        assert!(is_lock_file(".sinsbench.lock"));
        assert!(is_lock_file(".own.sinsbench.lock"));
        assert!(!is_lock_file(".own.toml.tmp-1-2"));
        assert!(!is_lock_file("sinsbench.lock"));
    }
}
