//! Writing outputs safely: every file is written aside and renamed into place, every temporary
//! path is registered so that a signal handler can remove it, and temporaries left by killed
//! runs are swept at the next run.
//!
//! - [`write_file_atomically`] writes bytes to `.NAME.tmp-PID-N` beside the target, syncs it and
//!   renames it over the target; a failure removes the temporary and leaves the target as it was.
//! - [`Temporary`] is a registered temporary file or directory: removed on drop unless committed,
//!   and by [`remove_temporaries_and_exit`] (the binary's SIGINT/SIGTERM handler).
//! - [`commit_section`] runs renames that must not be cut in half by the signal handler, and
//!   [`replace_dir`] swaps a staged output directory into place.
//! - [`commit_files`] moves a whole set of files staged in a `.NAME.partial-PID` directory into
//!   place together: all of them or none, even when the process is killed in the middle.
//! - [`sweep_stale`] removes the temporaries of processes that no longer run (named
//!   `.NAME.tmp-PID[-N]`, `.NAME.partial-PID`, `.NAME.old-PID`), putting back an output that a
//!   killed run had moved aside and not yet replaced, and completing a set commit that a killed
//!   run had started ([`COMMIT_RECORD`]).
//!
//! One writer per output directory is [`crate::lock`]'s business.

use std::collections::HashSet;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, OnceLock};

/// Temporaries of this process that are still in flight: id and path.
static LIVE: Mutex<Vec<(u64, PathBuf)>> = Mutex::new(Vec::new());
/// Ids of registered temporaries and the counter in temporary file names.
static COUNTER: AtomicU64 = AtomicU64::new(0);
/// Directories already swept by this process.
static SWEPT: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);
/// Where messages about stale temporaries go (set by the binary; silent by default).
static NOTIFIER: OnceLock<fn(&str)> = OnceLock::new();
/// What an interruption leaves unchanged ([`set_interrupt_note`]), said by
/// [`remove_temporaries_and_exit`]; cleared when a [`commit_files`] has put the new set in place.
static INTERRUPT_NOTE: Mutex<Option<String>> = Mutex::new(None);

/// The name of the commit record that [`commit_files`] writes inside a staging directory once
/// every file of the new set is complete, before the first rename: its presence in the staging
/// directory of a process that no longer runs means the set was committed, and [`sweep_stale`]
/// then moves the files still in the staging directory into place (roll forward).
pub const COMMIT_RECORD: &str = ".sinsbench-commit";
/// First line of a [`COMMIT_RECORD`].
const COMMIT_HEADER: &str = "sinsbench commit 1";
/// Prefix, inside a staging directory, of the hard links to the files a commit replaces (so that
/// a rename failing half-way can be undone).
const PREVIOUS_PREFIX: &str = ".previous.";

fn interrupt_note() -> MutexGuard<'static, Option<String>> {
    INTERRUPT_NOTE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Sets what a SIGINT/SIGTERM would leave unchanged (e.g. "the previous datasets in D are
/// unchanged"), said through the notifier by [`remove_temporaries_and_exit`]; `None` clears it.
/// [`commit_files`] clears it as soon as the new set is in place.
pub fn set_interrupt_note(note: Option<String>) {
    *interrupt_note() = note;
}

fn live() -> MutexGuard<'static, Vec<(u64, PathBuf)>> {
    LIVE.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Sends the messages of the automatic sweeps ([`sweep_stale_once`]) to `notify` (the binary
/// prints them on stderr). Only the first call has an effect.
pub fn set_stale_notifier(notify: fn(&str)) {
    let _ = NOTIFIER.set(notify);
}

/// A temporary file or directory beside a target, registered for removal on a signal; removed
/// when dropped unless [`Temporary::commit`] moved it into place.
#[derive(Debug)]
pub struct Temporary {
    id: u64,
    path: PathBuf,
    dir: bool,
    armed: bool,
}

/// The directory holding `target` (`.` for a bare file name).
fn parent_of(target: &Path) -> PathBuf {
    match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

fn file_name_of(target: &Path) -> std::io::Result<String> {
    target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .ok_or_else(|| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("{}: the path names no file", target.display()),
            )
        })
}

fn unregister(id: u64) {
    live().retain(|(i, _)| *i != id);
}

/// Attempts at removing one temporary in the signal handler (see
/// [`remove_temporaries_and_exit`]).
const REMOVAL_ATTEMPTS: usize = 1000;

fn remove_path(path: &Path) {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => {
            let _ = std::fs::remove_dir_all(path);
        }
        Ok(_) => {
            let _ = std::fs::remove_file(path);
        }
        Err(_) => {}
    }
}

/// Refuses a target that is an existing directory (a file goes there).
fn refuse_directory(target: &Path) -> std::io::Result<()> {
    match std::fs::symlink_metadata(target) {
        Ok(m) if m.is_dir() => Err(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            "exists and is a directory, where a file is to be written; it is left untouched \
             (choose another path or remove it)",
        )),
        _ => Ok(()),
    }
}

impl Temporary {
    /// Creates `.NAME.tmp-PID-N` beside `target` (a new, empty file) after sweeping the
    /// directory's stale temporaries once per process. Refuses a `target` that is a directory.
    pub fn file(target: &Path) -> std::io::Result<(Self, File)> {
        refuse_directory(target)?;
        let name = file_name_of(target)?;
        let dir = parent_of(target);
        sweep_stale_once(&dir);
        let pid = std::process::id();
        loop {
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let path = dir.join(format!(".{name}.tmp-{pid}-{n}"));
            // Created and registered under the registry's lock: a signal handler removes it
            // or runs before it exists, never in between.
            let mut registry = live();
            match OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(file) => {
                    let id = COUNTER.fetch_add(1, Ordering::Relaxed);
                    registry.push((id, path.clone()));
                    return Ok((
                        Self {
                            id,
                            path,
                            dir: false,
                            armed: true,
                        },
                        file,
                    ));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
    }

    /// Creates the staging directory `.NAME.partial-PID` beside `target` (removing one this
    /// process left), after sweeping the parent's stale temporaries once per process.
    pub fn dir(target: &Path) -> std::io::Result<Self> {
        let name = file_name_of(target)?;
        let parent = parent_of(target);
        sweep_stale_once(&parent);
        let path = parent.join(format!(".{name}.partial-{}", std::process::id()));
        remove_path(&path);
        let mut registry = live();
        std::fs::create_dir(&path)?;
        let id = COUNTER.fetch_add(1, Ordering::Relaxed);
        registry.push((id, path.clone()));
        Ok(Self {
            id,
            path,
            dir: true,
            armed: true,
        })
    }

    /// The temporary path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Syncs `file` (this temporary file, fully written) to disk, closes it and commits it to
    /// `target` ([`Temporary::commit`]): the one way a written file reaches its place.
    pub fn commit_file(self, file: File, target: &Path) -> std::io::Result<()> {
        file.sync_all()?;
        drop(file);
        self.commit(target)
    }

    /// Renames the temporary to `target` (inside a [`commit_section`]: a signal cannot cut it in
    /// half) and syncs the directory; the temporary is then no longer removed.
    pub fn commit(mut self, target: &Path) -> std::io::Result<()> {
        commit_section(|| std::fs::rename(&self.path, target))?;
        self.armed = false;
        unregister(self.id);
        if let Ok(d) = File::open(parent_of(target)) {
            let _ = d.sync_all();
        }
        Ok(())
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if self.armed {
            // Removed and unregistered under the registry's lock: the signal handler removes it
            // first or finds it gone, never races this removal (two `remove_dir_all` at once
            // can each stop at an entry the other took, and the exit then leaves the rest).
            let mut registry = live();
            if self.dir {
                let _ = std::fs::remove_dir_all(&self.path);
            } else {
                let _ = std::fs::remove_file(&self.path);
            }
            registry.retain(|(i, _)| *i != self.id);
        }
    }
}

/// Runs `f` (renames that put outputs into place) while the signal handler waits: the handler
/// removes the temporaries before or after, never in the middle. `f` must not create, commit or
/// drop a [`Temporary`] (the registry is locked).
pub fn commit_section<T>(f: impl FnOnce() -> T) -> T {
    let _guard = live();
    f()
}

/// Replaces the directory `target` by the staging directory `staging`: moves an existing
/// `target` aside (`.NAME.old-PID`), moves `staging` in, then deletes the old one. Both renames
/// run while the signal handler waits; after a SIGKILL between them, [`sweep_stale`] at the next
/// run puts the old directory back. On a failed rename the old directory is put back and
/// `staging` is removed.
pub fn replace_dir(staging: Temporary, target: &Path) -> std::io::Result<()> {
    let name = file_name_of(target)?;
    let parent = parent_of(target);
    let old = parent.join(format!(".{name}.old-{}", std::process::id()));
    let mut staging = staging;
    let old_temp = {
        let mut registry = live();
        let had_old = std::fs::symlink_metadata(target).is_ok();
        if had_old {
            std::fs::rename(target, &old)?;
        }
        if let Err(e) = std::fs::rename(&staging.path, target) {
            if had_old {
                let _ = std::fs::rename(&old, target);
            }
            return Err(e);
        }
        staging.armed = false;
        registry.retain(|(i, _)| *i != staging.id);
        had_old.then(|| {
            let id = COUNTER.fetch_add(1, Ordering::Relaxed);
            registry.push((id, old.clone()));
            Temporary {
                id,
                path: old.clone(),
                dir: true,
                armed: true,
            }
        })
    };
    drop(staging);
    if let Ok(d) = File::open(&parent) {
        let _ = d.sync_all();
    }
    if let Some(old_temp) = old_temp {
        drop(old_temp);
        if std::fs::symlink_metadata(&old).is_ok() {
            return Err(std::io::Error::other(format!(
                "the previous output, moved aside to {}, could not be deleted",
                old.display()
            )));
        }
    }
    Ok(())
}

/// Removes every registered temporary of this process, says the interruption note
/// ([`set_interrupt_note`]) through the notifier, releases the output locks
/// ([`crate::lock::release_all`]) and exits with `code`; the lock on the registry is held until
/// the exit, so no rename can follow. For the binary's signal handler.
pub fn remove_temporaries_and_exit(code: i32) -> ! {
    let guard = live();
    // Newest first: a temporary file inside a staging directory goes before the directory.
    // Other threads keep running until the exit: a file one of them creates in a staging
    // directory while it is being removed makes that removal fail (not empty), so each path is
    // removed again until it is gone.
    for (_, path) in guard.iter().rev() {
        for _ in 0..REMOVAL_ATTEMPTS {
            remove_path(path);
            if std::fs::symlink_metadata(path).is_err() {
                break;
            }
            std::thread::yield_now();
        }
    }
    let note = interrupt_note().take();
    if let (Some(note), Some(notify)) = (note, NOTIFIER.get()) {
        notify(&note);
    }
    crate::lock::release_all();
    std::process::exit(code)
}

/// Moves the files `names` (plain names) of the staging directory `staging` (made by
/// [`Temporary::dir`]) into the directory that holds it, replacing files of the same names: the
/// whole set or nothing.
///
/// Before anything moves, each file to be replaced is hard-linked into the staging directory
/// (a failure there, a full disk included, leaves every target as it was) and the
/// [`COMMIT_RECORD`] is written and synced. The renames then run inside a [`commit_section`],
/// so SIGINT/SIGTERM take effect before the first or after the last, never in between. A rename
/// that fails half-way is undone from the links. A SIGKILL (or a power cut) between two renames
/// cannot be stopped by any handler: the set in the directory is then mixed until the next
/// sinsbench command that writes there runs [`sweep_stale`], which finds the record of a process
/// that no longer runs and completes the commit. A reader that does not sweep (`navigate` on one
/// dataset) can see that mixed set in the meantime; it lasts only as long as the killed run's
/// remaining renames would have.
///
/// The staging directory is removed in every case.
pub fn commit_files(staging: Temporary, names: &[String]) -> std::io::Result<()> {
    let dir = parent_of(&staging.path);
    for name in names {
        if name.is_empty() || name.contains('/') || name.starts_with('.') {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("{name:?}: not a plain file name for a commit"),
            ));
        }
        let target = dir.join(name);
        refuse_directory(&target).map_err(|e| named(&target, e))?;
        let staged = staging.path.join(name);
        match std::fs::symlink_metadata(&staged) {
            Ok(m) if m.is_file() => {}
            Ok(_) => {
                return Err(named(
                    &staged,
                    std::io::Error::other("is not a regular file"),
                ));
            }
            Err(e) => return Err(named(&staged, e)),
        }
        if std::fs::symlink_metadata(&target).is_ok() {
            let link = staging.path.join(format!("{PREVIOUS_PREFIX}{name}"));
            std::fs::hard_link(&target, &link).map_err(|e| named(&link, e))?;
        }
    }
    let mut record = format!("{COMMIT_HEADER}\n");
    for name in names {
        record.push_str(name);
        record.push('\n');
    }
    write_file_atomically(&staging.path.join(COMMIT_RECORD), record.as_bytes())?;
    let moved = commit_section(|| {
        for (done, name) in names.iter().enumerate() {
            if let Err(e) = std::fs::rename(staging.path.join(name), dir.join(name)) {
                return Err((done, named(&dir.join(name), e)));
            }
        }
        *interrupt_note() = None;
        Ok(())
    });
    if let Err((done, e)) = moved {
        // Undo: the files already moved go back to what they were.
        let mut undo_failed = Vec::new();
        for name in names.iter().take(done) {
            let target = dir.join(name);
            let link = staging.path.join(format!("{PREVIOUS_PREFIX}{name}"));
            let undone = if link.exists() {
                std::fs::rename(&link, &target)
            } else {
                std::fs::remove_file(&target)
            };
            if undone.is_err() {
                undo_failed.push(target.display().to_string());
            }
        }
        // The record goes before the staging directory, so that no sweep rolls this forward.
        let _ = std::fs::remove_file(staging.path.join(COMMIT_RECORD));
        if undo_failed.is_empty() {
            return Err(e);
        }
        return Err(std::io::Error::new(
            e.kind(),
            format!(
                "{e}; and {} could not be put back as they were (the set there is mixed)",
                undo_failed.join(", ")
            ),
        ));
    }
    drop(staging);
    if let Ok(d) = File::open(&dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// `e` with `path` in front of its message.
fn named(path: &Path, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// Completes the commit recorded in `staging` (a staging directory of a process that no longer
/// runs, holding a [`COMMIT_RECORD`]): moves every listed file still there into `dir`. Returns
/// the number moved, or why it could not.
fn roll_forward(staging: &Path, dir: &Path) -> Result<usize, String> {
    let record = staging.join(COMMIT_RECORD);
    let text =
        std::fs::read_to_string(&record).map_err(|e| format!("{}: {e}", record.display()))?;
    let mut lines = text.lines();
    if lines.next() != Some(COMMIT_HEADER) {
        return Err(format!("{}: not a commit record", record.display()));
    }
    let mut moved = 0;
    for name in lines.filter(|l| !l.is_empty()) {
        if name.contains('/') || name.starts_with('.') {
            return Err(format!("{}: bad name {name:?}", record.display()));
        }
        let from = staging.join(name);
        if std::fs::symlink_metadata(&from).is_ok() {
            std::fs::rename(&from, dir.join(name))
                .map_err(|e| format!("{} -> {}: {e}", from.display(), dir.display()))?;
            moved += 1;
        }
    }
    Ok(moved)
}

/// Writes `bytes` to `.NAME.tmp-PID-N` beside `path`, syncs it and renames it over `path`; the
/// temporary file is removed when any step fails (or on SIGINT/SIGTERM through the binary's
/// handler), and `path` is then as it was. Refuses a `path` that is an existing directory.
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let (tmp, mut file) = Temporary::file(path)?;
    file.write_all(bytes)?;
    tmp.commit_file(file, path)
}

/// What a temporary name says: the target's name, the kind and the process that made it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// `.NAME.tmp-PID` or `.NAME.tmp-PID-N`: a file being written.
    Tmp,
    /// `.NAME.partial-PID`: a staging directory.
    Partial,
    /// `.NAME.old-PID`: an output moved aside while the new one moved in.
    Old,
}

fn parse_temporary(name: &str) -> Option<(&str, Kind, u32)> {
    let rest = name.strip_prefix('.')?;
    let (base, tail) = rest.rsplit_once('.')?;
    if base.is_empty() {
        return None;
    }
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if let Some(t) = tail.strip_prefix("tmp-") {
        let pid = match t.split_once('-') {
            Some((p, n)) if digits(n) => p,
            Some(_) => return None,
            None => t,
        };
        return digits(pid)
            .then(|| pid.parse().ok())
            .flatten()
            .map(|p| (base, Kind::Tmp, p));
    }
    for (prefix, kind) in [("partial-", Kind::Partial), ("old-", Kind::Old)] {
        if let Some(pid) = tail.strip_prefix(prefix) {
            return digits(pid)
                .then(|| pid.parse().ok())
                .flatten()
                .map(|p| (base, kind, p));
        }
    }
    None
}

/// Whether process `pid` runs: `Some(true/false)` where /proc tells, `None` where it cannot.
fn process_alive(pid: u32) -> Option<bool> {
    if pid == std::process::id() {
        return Some(true);
    }
    if !Path::new("/proc/self").exists() {
        return None;
    }
    Some(Path::new("/proc").join(pid.to_string()).exists())
}

/// Removes the temporaries in `dir` left by processes that no longer run (`.NAME.tmp-PID[-N]`,
/// `.NAME.partial-PID`, `.NAME.old-PID`); an `.NAME.old-PID` whose `NAME` is missing (the run
/// was killed between moving the old output aside and moving the new one in) is put back as
/// `NAME`. Returns one message per temporary found: removed, restored, or named and left (its
/// process still runs, or this system cannot tell).
pub fn sweep_stale(dir: &Path) -> Vec<String> {
    let mut notes = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return notes;
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some((base, kind, pid)) = parse_temporary(&name) else {
            continue;
        };
        let path = entry.path();
        match process_alive(pid) {
            Some(true) => {
                if pid != std::process::id() {
                    notes.push(format!(
                        "{}: temporary of process {pid}, which still runs; left alone",
                        path.display()
                    ));
                }
            }
            None => notes.push(format!(
                "{}: temporary left by process {pid} (cannot tell whether it still runs); \
                 remove it by hand if it does not",
                path.display()
            )),
            Some(false) => {
                let target = dir.join(base);
                let missing = std::fs::symlink_metadata(&target).is_err();
                if kind == Kind::Old && missing {
                    match std::fs::rename(&path, &target) {
                        Ok(()) => notes.push(format!(
                            "{}: restored from {} (process {pid} was stopped while replacing it)",
                            target.display(),
                            path.display()
                        )),
                        Err(e) => notes.push(format!(
                            "{}: cannot restore it as {}: {e}",
                            path.display(),
                            target.display()
                        )),
                    }
                    continue;
                }
                if kind == Kind::Partial && path.join(COMMIT_RECORD).is_file() {
                    match roll_forward(&path, dir) {
                        Ok(0) => {}
                        Ok(n) => notes.push(format!(
                            "{}: completed the replacement of the output set ({n} file(s) moved \
                             into place; process {pid} was stopped while moving them)",
                            dir.display()
                        )),
                        Err(e) => {
                            notes.push(format!(
                                "{}: cannot complete the replacement of the output set that \
                                 process {pid} had started ({e}); left for you to inspect",
                                path.display()
                            ));
                            continue;
                        }
                    }
                }
                remove_path(&path);
                if std::fs::symlink_metadata(&path).is_ok() {
                    notes.push(format!(
                        "{}: stale temporary of process {pid} could not be removed",
                        path.display()
                    ));
                } else {
                    notes.push(format!(
                        "removed {} (a temporary left by process {pid}, which no longer runs)",
                        path.display()
                    ));
                }
            }
        }
    }
    notes.sort();
    notes
}

/// [`sweep_stale`] on `dir` the first time this process writes there; the messages go to the
/// notifier set by [`set_stale_notifier`].
pub fn sweep_stale_once(dir: &Path) {
    let key = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    {
        let mut swept = SWEPT
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if !swept.get_or_insert_with(HashSet::new).insert(key) {
            return;
        }
    }
    let notes = sweep_stale(dir);
    if let Some(notify) = NOTIFIER.get() {
        for n in &notes {
            notify(n);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_parse_and_others_do_not() {
        assert_eq!(
            parse_temporary(".a.toml.tmp-12-3"),
            Some(("a.toml", Kind::Tmp, 12))
        );
        assert_eq!(
            parse_temporary(".a.toml.tmp-12"),
            Some(("a.toml", Kind::Tmp, 12))
        );
        assert_eq!(
            parse_temporary(".paper_replica.partial-7"),
            Some(("paper_replica", Kind::Partial, 7))
        );
        assert_eq!(parse_temporary(".r.old-99"), Some(("r", Kind::Old, 99)));
        for other in [
            "a.toml",
            ".gitignore",
            ".a.tmp-",
            ".a.tmp-x",
            ".a.tmp-1-",
            ".a.old-1x",
            "..old-3",
            ".sinsbench-output",
        ] {
            assert_eq!(parse_temporary(other), None, "{other}");
        }
    }

    #[test]
    fn stale_temporaries_are_removed_restored_or_named() {
        let dir = tempfile::tempdir().expect("tempdir");
        let d = dir.path();
        // A pid that cannot run: above the kernel's maximum (4194304).
        let dead = 4_999_999;
        std::fs::write(d.join(format!(".p.toml.tmp-{dead}-0")), "half").unwrap();
        std::fs::create_dir(d.join(format!(".rep.partial-{dead}"))).unwrap();
        std::fs::create_dir(d.join(format!(".gone.old-{dead}"))).unwrap();
        std::fs::write(d.join(format!(".gone.old-{dead}/report.md")), "old").unwrap();
        std::fs::create_dir(d.join("kept")).unwrap();
        std::fs::create_dir(d.join(format!(".kept.old-{dead}"))).unwrap();
        let mine = format!(".x.tmp-{}-5", std::process::id());
        std::fs::write(d.join(&mine), "in flight").unwrap();
        std::fs::write(d.join("user.txt"), "mine").unwrap();
        let notes = sweep_stale(d);
        assert_eq!(notes.len(), 4, "{notes:?}");
        assert!(notes.iter().any(|n| n.contains("restored")), "{notes:?}");
        let mut left: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(
            left,
            vec![mine, "gone".into(), "kept".into(), "user.txt".into()]
        );
        assert_eq!(
            std::fs::read_to_string(d.join("gone/report.md")).unwrap(),
            "old"
        );
    }

    #[test]
    fn atomic_write_replaces_a_file_and_refuses_a_directory() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("a.json");
        write_file_atomically(&p, b"one").unwrap();
        write_file_atomically(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        let sub = dir.path().join("sub.json");
        std::fs::create_dir(&sub).unwrap();
        std::fs::write(sub.join("keep"), "x").unwrap();
        let e = write_file_atomically(&sub, b"three").unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::IsADirectory);
        assert!(e.to_string().contains("is a directory"), "{e}");
        assert!(sub.join("keep").is_file());
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 2, "no temporary left: {names:?}");
    }

    #[test]
    fn a_failed_write_leaves_no_temporary_and_the_target_as_it_was() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("a.txt");
        std::fs::write(&p, "good").unwrap();
        let (tmp, mut f) = Temporary::file(&p).unwrap();
        f.write_all(b"half").unwrap();
        let tmp_path = tmp.path().to_path_buf();
        assert!(tmp_path.is_file());
        drop(tmp);
        assert!(!tmp_path.exists());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "good");
    }

    #[test]
    fn replace_dir_swaps_in_the_staged_directory_and_deletes_the_old_one() {
        let dir = tempfile::tempdir().expect("tempdir");
        let target = dir.path().join("out");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("a"), "old").unwrap();
        let staged = Temporary::dir(&target).unwrap();
        std::fs::write(staged.path().join("a"), "new").unwrap();
        replace_dir(staged, &target).unwrap();
        assert_eq!(std::fs::read_to_string(target.join("a")).unwrap(), "new");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "only out/ remains: {names:?}");
    }
    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|x| (*x).to_string()).collect()
    }

    #[test]
    fn commit_files_replaces_the_whole_set_and_leaves_nothing() {
        let dir = tempfile::tempdir().expect("tempdir");
        let d = dir.path();
        for n in ["a", "b", "c"] {
            std::fs::write(d.join(n), "old").unwrap();
        }
        let staged = Temporary::dir(&d.join("set")).unwrap();
        for n in ["a", "b", "c"] {
            std::fs::write(staged.path().join(n), "new").unwrap();
        }
        commit_files(staged, &names(&["a", "b", "c"])).unwrap();
        for n in ["a", "b", "c"] {
            assert_eq!(std::fs::read_to_string(d.join(n)).unwrap(), "new");
        }
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 3, "no staging left");
    }

    #[test]
    fn a_failed_commit_puts_every_file_back() {
        let dir = tempfile::tempdir().expect("tempdir");
        let d = dir.path();
        std::fs::write(d.join("a"), "old a").unwrap();
        let staged = Temporary::dir(&d.join("set")).unwrap();
        std::fs::write(staged.path().join("a"), "new a").unwrap();
        std::fs::write(staged.path().join("b"), "new b").unwrap();
        // "c" was never written: refused before anything moves.
        let e = commit_files(staged, &names(&["a", "b", "c"])).unwrap_err();
        assert!(e.to_string().contains('c'), "{e}");
        assert_eq!(std::fs::read_to_string(d.join("a")).unwrap(), "old a");
        assert!(!d.join("b").exists());
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 1, "no staging left");
    }

    #[test]
    fn a_commit_cut_by_sigkill_is_completed_by_the_next_sweep() {
        let dir = tempfile::tempdir().expect("tempdir");
        let d = dir.path();
        let dead = 4_999_999;
        // The killed run had moved "a" and was about to move "b" and "c".
        std::fs::write(d.join("a"), "new").unwrap();
        std::fs::write(d.join("b"), "old").unwrap();
        std::fs::write(d.join("c"), "old").unwrap();
        let staging = d.join(format!(".set.partial-{dead}"));
        std::fs::create_dir(&staging).unwrap();
        std::fs::write(staging.join("b"), "new").unwrap();
        std::fs::write(staging.join("c"), "new").unwrap();
        std::fs::write(staging.join(".previous.b"), "old").unwrap();
        std::fs::write(
            staging.join(COMMIT_RECORD),
            format!("{COMMIT_HEADER}\na\nb\nc\n"),
        )
        .unwrap();
        let notes = sweep_stale(d);
        assert!(
            notes
                .iter()
                .any(|n| n.contains("completed the replacement")),
            "{notes:?}"
        );
        for n in ["a", "b", "c"] {
            assert_eq!(std::fs::read_to_string(d.join(n)).unwrap(), "new", "{n}");
        }
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 3, "{notes:?}");
        // Without a record (killed before the commit), the staged files are only removed.
        let staging = d.join(format!(".set.partial-{dead}"));
        std::fs::create_dir(&staging).unwrap();
        std::fs::write(staging.join("a"), "newer").unwrap();
        sweep_stale(d);
        assert_eq!(std::fs::read_to_string(d.join("a")).unwrap(), "new");
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 3);
    }
}
