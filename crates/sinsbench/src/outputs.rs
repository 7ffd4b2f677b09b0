//! Output safety for every command: the SIGINT/SIGTERM handler that removes this run's temporary
//! files and staging directories before exiting, the messages about temporaries left by killed
//! runs, and the checks that an output path is not taken by something else (a directory where
//! a file goes, or the reverse) before any long work starts.

use crate::out::note;
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// Installs the signal handling of the binary: on SIGINT or SIGTERM, remove every temporary this
/// process registered (files being written, staging directories, an old output being deleted)
/// and exit with 128 + the signal number; renames in progress finish first. SIGXFSZ (a file-size
/// limit reached) makes the write fail with an error instead of killing the process. Messages
/// about temporaries of killed runs, swept at the next write in their directory, go to stderr.
pub fn install() -> Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM, SIGXFSZ};
    signal_hook::flag::register(SIGXFSZ, Arc::new(AtomicBool::new(false)))
        .context("cannot install the SIGXFSZ handler")?;
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM])
        .context("cannot install the SIGINT/SIGTERM handler")?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(sig) = signals.forever().next() {
                let name = if sig == SIGINT { "SIGINT" } else { "SIGTERM" };
                note!("{name}: stopping; this run's temporary files are removed");
                // Says what the interrupted command leaves unchanged (when it set a note) and
                // releases the output locks.
                sins_files::remove_temporaries_and_exit(128 + sig);
            }
        })
        .context("cannot start the signal thread")?;
    sins_files::set_stale_notifier(|msg| note!("note: {msg}"));
    Ok(())
}

/// Removes (and reports) the temporaries that killed runs left in `dir`, where this command is
/// about to write.
pub fn sweep(dir: &Path) {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    sins_files::sweep_stale_once(dir);
}

/// Refuses an output file path that is taken by a directory (or a link to one); a file there is
/// replaced atomically at the end.
pub fn check_file_target(path: &Path, what: &str) -> Result<()> {
    if std::fs::metadata(path).is_ok_and(|m| m.is_dir()) {
        bail!(
            "{}: exists and is a directory, where the {what} file goes; it is left untouched \
             (choose another path or remove it)",
            path.display()
        );
    }
    Ok(())
}

/// Refuses an output directory path that is taken by a file (or a link to one), then creates it.
pub fn create_dir_target(dir: &Path, what: &str) -> Result<()> {
    if let Ok(m) = std::fs::metadata(dir)
        && !m.is_dir()
    {
        bail!(
            "{}: exists and is not a directory, where the {what} directory goes; it is left \
             untouched (choose another path or remove it)",
            dir.display()
        );
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))
}

/// The parent and name of an output directory `--out` of command `kind`, after sweeping the
/// parent's stale temporaries, checking that `out` is absent or a previous output of `kind` (a
/// user's directory is never replaced) and taking the lock of `out` for the rest of the process
/// (`PARENT/.NAME.sinsbench.lock`: a second writer of the same output is refused).
pub fn output_dir(out: &Path, kind: &str) -> Result<(PathBuf, String)> {
    let parent = out.parent().map_or(PathBuf::from("."), PathBuf::from);
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .context("--out must name a directory")?;
    sweep(&parent);
    sins_report::check_output_dir(&parent, &name, kind)?;
    sins_files::lock::lock_output(&parent, Some(&name))?;
    Ok((parent, name))
}
