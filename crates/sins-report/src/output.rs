//! Writing a report directory atomically: everything goes into a fresh sibling directory, which
//! then replaces `reports/<name>/` by two renames. An existing report is never half-overwritten:
//! if anything fails, the old one stays and the partial one is removed. Only a previous output of
//! the same command is ever replaced: a user's file or directory in the way is refused, never
//! moved.

use crate::ReportError;
use crate::names::{plot_file, rrd_file, segments_file, track_file};
use crate::run::ReportRun;
use crate::{markdown, plots, rrd, tracks};
use sins_config::{ParamSet, summary_to_json, write_params};
use std::path::{Path, PathBuf};

/// What a written report contains.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportFiles {
    /// The report directory.
    pub dir: PathBuf,
    /// Every file in it (relative names).
    pub files: Vec<String>,
}

fn write_text(path: &Path, text: &str) -> Result<(), ReportError> {
    write_bytes(path, text.as_bytes())
}

/// Writes `bytes` aside and renames them into place ([`sins_files::write_file_atomically`]).
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    sins_files::write_file_atomically(path, bytes).map_err(|e| ReportError::io(path, e))
}

/// Write `run` into `<reports_dir>/<name>/`, replacing an existing report only once the new one
/// is complete.
pub fn write_report(reports_dir: &Path, run: &ReportRun) -> Result<ReportFiles, ReportError> {
    write_dir_atomically(reports_dir, &run.summary.name, "report", |dir| {
        fill(dir, run)
    })
}

/// The hidden file that marks a directory as an output of a sinsbench command; it holds the
/// command's name (`report`, `diagnose`, `calibration-report`).
pub const OUTPUT_MARKER: &str = ".sinsbench-output";

/// Create `<reports_dir>/<name>/` with the files that `fill` writes into the directory it is
/// given (a fresh staging directory `.<name>.partial-PID`; it returns the names written), for
/// the command `kind` (recorded in [`OUTPUT_MARKER`]). The staging directory replaces an
/// existing `<name>/` only when `fill` succeeded; on failure (or SIGINT/SIGTERM, through the
/// binary's handler) it is removed and the old directory is untouched.
///
/// An existing `<name>` is replaced only when it is a previous output of the same command: a
/// directory with the marker of `kind`, an empty directory, or (an output of a version before
/// the marker) a directory holding only regular files among those `fill` wrote. Anything else
/// (a file, a link, another command's output, a directory with other content) is refused with
/// an error naming it, before `fill` runs where possible, and is never moved.
pub fn write_dir_atomically<F>(
    reports_dir: &Path,
    name: &str,
    kind: &str,
    fill: F,
) -> Result<ReportFiles, ReportError>
where
    F: FnOnce(&Path) -> Result<Vec<String>, ReportError>,
{
    std::fs::create_dir_all(reports_dir).map_err(|e| ReportError::io(reports_dir, e))?;
    let target = reports_dir.join(name);
    check_replaceable(&target, kind, None)?;
    let staging = sins_files::Temporary::dir(&target).map_err(|e| ReportError::io(&target, e))?;
    let files = fill(staging.path())?;
    let marker = staging.path().join(OUTPUT_MARKER);
    sins_files::write_file_atomically(&marker, format!("{kind}\n").as_bytes())
        .map_err(|e| ReportError::io(&marker, e))?;
    check_replaceable(&target, kind, Some(&files))?;
    swap_into_place(staging, &target)?;
    Ok(ReportFiles { dir: target, files })
}

/// Refuses, before any long work, an output directory `<reports_dir>/<name>` that
/// [`write_dir_atomically`] would refuse at the end (a file or link, another command's output,
/// a directory with hidden entries or subdirectories and no marker).
pub fn check_output_dir(reports_dir: &Path, name: &str, kind: &str) -> Result<(), ReportError> {
    check_replaceable(&reports_dir.join(name), kind, None)
}

/// Refuses a `target` that is not a previous output of `kind` (see [`write_dir_atomically`]);
/// `written` is the list of files of the new output (`None` before it is known: a directory
/// without the marker then passes if it holds only regular, visible files).
fn check_replaceable(
    target: &Path,
    kind: &str,
    written: Option<&[String]>,
) -> Result<(), ReportError> {
    let refuse = |why: String| {
        Err(ReportError::Refused {
            path: target.to_path_buf(),
            why,
        })
    };
    let meta = match std::fs::symlink_metadata(target) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(ReportError::io(target, e)),
    };
    if meta.file_type().is_symlink() {
        return refuse("exists and is a symbolic link, where the output directory goes".into());
    }
    if !meta.is_dir() {
        return refuse(
            "exists and is not a directory (a file is where the output directory goes)".into(),
        );
    }
    let marker = target.join(OUTPUT_MARKER);
    match std::fs::symlink_metadata(&marker) {
        Ok(m) if m.is_file() => {
            let text = std::fs::read_to_string(&marker).map_err(|e| ReportError::io(&marker, e))?;
            let theirs = text.trim();
            if theirs == kind {
                return Ok(());
            }
            return refuse(format!(
                "is the output of `sinsbench {theirs}`, not of `sinsbench {kind}`"
            ));
        }
        Ok(_) => return refuse(format!("{OUTPUT_MARKER} is not a regular file")),
        Err(_) => {}
    }
    let entries = std::fs::read_dir(target).map_err(|e| ReportError::io(target, e))?;
    for entry in entries {
        let entry = entry.map_err(|e| ReportError::io(target, e))?;
        let file_name = entry.file_name().to_string_lossy().into_owned();
        let is_file = entry.file_type().is_ok_and(|t| t.is_file());
        let ours = match written {
            Some(files) => files.contains(&file_name),
            None => !file_name.starts_with('.'),
        };
        if !is_file || !ours {
            return refuse(format!(
                "exists and is not an output of `sinsbench {kind}` (no {OUTPUT_MARKER}, and it holds \
                 '{file_name}', which the command does not write)"
            ));
        }
    }
    Ok(())
}

fn fill(dir: &Path, run: &ReportRun) -> Result<Vec<String>, ReportError> {
    let mut files = Vec::new();
    for o in &run.outcomes {
        let (t, g) = (track_file(&o.run), segments_file(&o.run));
        tracks::write_tracks(&dir.join(&t), &dir.join(&g), o)?;
        files.push(t);
        files.push(g);
        let r = rrd_file(&o.run);
        sins_viz::write_navigation(&dir.join(&r), &o.run, &rrd::recording(o))?;
        files.push(r);
        for (what, png) in plots::render(o, &run.sets)? {
            let p = plot_file(&o.run, what);
            write_bytes(&dir.join(&p), &png)?;
            files.push(p);
        }
    }
    for s in run.sets.iter().filter(|s| s.calibrated) {
        let p = format!("params_{}.toml", s.key);
        write_params(
            dir.join(&p),
            &ParamSet {
                params: s.params,
                sigma: s.sigma,
                description: s.source.clone(),
            },
        )?;
        files.push(p);
    }
    write_text(&dir.join("summary.json"), &summary_to_json(&run.summary))?;
    files.push("summary.json".into());
    write_text(&dir.join("report.md"), &markdown::render_markdown(run))?;
    files.push("report.md".into());
    Ok(files)
}

/// Replace `target` by `staging` ([`sins_files::replace_dir`]): the old output is moved
/// aside, the new one moved in, the old one deleted; the output is momentarily absent, never
/// partial, and a run killed in between has the old one put back by the next run.
fn swap_into_place(staging: sins_files::Temporary, target: &Path) -> Result<(), ReportError> {
    sins_files::replace_dir(staging, target).map_err(|e| ReportError::io(target, e))
}
