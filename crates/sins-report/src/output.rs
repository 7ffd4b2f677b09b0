//! Writing a report directory atomically: everything goes into a fresh sibling directory, which
//! then replaces `reports/<name>/` by two renames. An existing report is never half-overwritten:
//! if anything fails, the old one stays and the partial one is removed.

use crate::ReportError;
use crate::run::ReportRun;
use crate::{markdown, plots, rrd, tracks};
use sins_config::{ParamSet, write_params};
use std::path::{Path, PathBuf};

/// What a written report contains.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportFiles {
    /// The report directory.
    pub dir: PathBuf,
    /// Every file in it (relative names).
    pub files: Vec<String>,
}

/// `<run>_errors.parquet`.
pub(crate) fn track_file(run: &str) -> String {
    format!("{run}_errors.parquet")
}

/// `<run>.rrd`.
pub(crate) fn rrd_file(run: &str) -> String {
    format!("{run}.rrd")
}

/// `<run>_<what>.png`.
pub(crate) fn plot_file(run: &str, what: &str) -> String {
    format!("{run}_{what}.png")
}

fn write_text(path: &Path, text: &str) -> Result<(), ReportError> {
    std::fs::write(path, text).map_err(|e| ReportError::io(path, e))
}

/// Write `run` into `<reports_dir>/<name>/`, replacing an existing report only once the new one
/// is complete.
pub fn write_report(reports_dir: &Path, run: &ReportRun) -> Result<ReportFiles, ReportError> {
    write_dir_atomically(reports_dir, &run.summary.name, |dir| fill(dir, run))
}

/// Create `<reports_dir>/<name>/` with the files that `fill` writes into the directory it is
/// given (a fresh staging directory; it returns the names written). The staging directory
/// replaces an existing `<name>/` only when `fill` succeeded; on failure it is removed and the
/// old directory is untouched.
pub fn write_dir_atomically<F>(
    reports_dir: &Path,
    name: &str,
    fill: F,
) -> Result<ReportFiles, ReportError>
where
    F: FnOnce(&Path) -> Result<Vec<String>, ReportError>,
{
    std::fs::create_dir_all(reports_dir).map_err(|e| ReportError::io(reports_dir, e))?;
    let target = reports_dir.join(name);
    let staging = reports_dir.join(format!(".{name}.partial-{}", std::process::id()));
    if staging.exists() {
        std::fs::remove_dir_all(&staging).map_err(|e| ReportError::io(&staging, e))?;
    }
    std::fs::create_dir_all(&staging).map_err(|e| ReportError::io(&staging, e))?;
    match fill(&staging) {
        Ok(files) => {
            swap_into_place(&staging, &target)?;
            Ok(ReportFiles { dir: target, files })
        }
        Err(e) => {
            let _ = std::fs::remove_dir_all(&staging);
            Err(e)
        }
    }
}

fn fill(dir: &Path, run: &ReportRun) -> Result<Vec<String>, ReportError> {
    let mut files = Vec::new();
    for o in &run.outcomes {
        let t = track_file(&o.run);
        tracks::write_tracks(&dir.join(&t), o)?;
        files.push(t);
        let r = rrd_file(&o.run);
        sins_viz::write_navigation(&dir.join(&r), &o.run, &rrd::recording(o))?;
        files.push(r);
        for (what, png) in plots::render(o, &run.sets)? {
            let p = plot_file(&o.run, what);
            std::fs::write(dir.join(&p), png).map_err(|e| ReportError::io(dir.join(&p), e))?;
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
    write_text(&dir.join("summary.json"), &run.summary.to_json())?;
    files.push("summary.json".into());
    write_text(&dir.join("report.md"), &markdown::render_markdown(run))?;
    files.push("report.md".into());
    Ok(files)
}

/// Replace `target` by `staging`: move the old report aside, move the new one in, delete the
/// old one. Between the two renames the report is momentarily absent, never partial.
fn swap_into_place(staging: &Path, target: &Path) -> Result<(), ReportError> {
    let old = target.with_file_name(format!(
        ".{}.old-{}",
        target
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        std::process::id()
    ));
    let had_old = target.exists();
    if had_old {
        std::fs::rename(target, &old).map_err(|e| ReportError::io(target, e))?;
    }
    if let Err(e) = std::fs::rename(staging, target) {
        if had_old {
            let _ = std::fs::rename(&old, target);
        }
        return Err(ReportError::io(target, e));
    }
    if had_old {
        std::fs::remove_dir_all(&old).map_err(|e| ReportError::io(&old, e))?;
    }
    Ok(())
}
