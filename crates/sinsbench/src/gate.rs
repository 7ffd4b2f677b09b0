//! `sinsbench gate`: the release gate on a report's summary.

use crate::out::say;
use crate::report;
use anyhow::{Context, Result, anyhow, bail};
use sins_config::{load_report_config, load_thresholds, read_summary};
use sins_harness::gate::{Check, is_gate_junit, junit_xml};
use std::io::Read;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

/// Arguments of `gate`.
#[derive(clap::Args)]
pub struct Args {
    /// A report's summary.json to check.
    #[arg(long, conflicts_with = "config")]
    pub summary: Option<PathBuf>,
    /// Or: run this report configuration first (as `sinsbench report --config`), then check
    /// its summary; its `gate` key names the thresholds unless --thresholds is given.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Thresholds (TOML): maximum horizontal error per parameter set (nmi) and minimum
    /// improvement (%), for every experiment or per experiment. See experiments/harness/gate_paper.toml.
    #[arg(long)]
    pub thresholds: Option<PathBuf>,
    /// Also write the checks as JUnit XML (one test case per check) for CI systems: written
    /// aside and renamed into place after the PASS/FAIL lines; never over the summary, the
    /// thresholds or any file that is not a JUnit report the gate wrote (exit 2).
    #[arg(long)]
    pub junit: Option<PathBuf>,
    /// Directory of the report when --config runs one.
    #[arg(long, default_value = "reports")]
    pub reports_dir: PathBuf,
    /// Or: compare a candidate release with this baseline, each a `reports` campaign of the
    /// same report configuration over N sensor-noise seeds (`noise_seeds = N` in the campaign
    /// file; its directory or its summary.json). Per experiment and parameter set, the shift
    /// of the maximum horizontal error (Hodges-Lehmann, with a distribution-free Mann-Whitney
    /// bound) fails the gate when the candidate is worse than --margin-percent at
    /// --confidence. Needs --candidate.
    #[arg(long, requires = "candidate", conflicts_with_all = ["summary", "config", "thresholds"])]
    pub baseline: Option<PathBuf>,
    /// The candidate release's `reports` campaign (directory or summary.json), for --baseline.
    #[arg(long, requires = "baseline")]
    pub candidate: Option<PathBuf>,
    /// Largest tolerated worsening of a cell, in percent of the baseline's median (--baseline).
    #[arg(long, default_value_t = 10.0)]
    pub margin_percent: f64,
    /// Family-wise confidence over the cells that a failed cell is worse than the margin
    /// (--baseline): a release that differs only in its noise seeds fails with probability at
    /// most 1 - confidence.
    #[arg(long, default_value_t = 0.95)]
    pub confidence: f64,
    /// Or: measure the --baseline gate on one release's own run-to-run spread, from a `reports`
    /// campaign of M noise seeds (directory or summary.json): every cell's median and 5-95 %
    /// over the seeds, how often the release fails against itself on other seeds (random
    /// disjoint draws of --seeds-per-side a side, at --margin-percent and --confidence), and
    /// how often it fails when the candidate's --worsen-set cells are made worse by each of
    /// --worsen-percent. Prints a table; writes nothing.
    #[arg(long, conflicts_with_all = ["summary", "config", "thresholds", "baseline", "junit"])]
    pub power: Option<PathBuf>,
    /// Seeds a side for --power (each at most half the campaign's seeds).
    #[arg(long, value_delimiter = ',', default_values_t = [8usize], requires = "power")]
    pub seeds_per_side: Vec<usize>,
    /// Worsenings (%) of --worsen-set for --power.
    #[arg(long, value_delimiter = ',', default_values_t = [10.0, 20.0, 30.0, 50.0, 75.0, 100.0, 150.0], requires = "power")]
    pub worsen_percent: Vec<f64>,
    /// The parameter set --power worsens (default: the comparison's compensated set).
    #[arg(long, requires = "power")]
    pub worsen_set: Option<String>,
    /// Comparisons drawn per row for --power (seeded: the table is reproducible).
    #[arg(long, default_value_t = 200, requires = "power")]
    pub draws: usize,
}

/// The gate found thresholds exceeded (exit code 1; errors exit with 2). A JUnit report that
/// could not be written is said here too: the verdict keeps its exit code.
#[derive(Debug, thiserror::Error)]
#[error(
    "gate failed: {failed} of {total} checks exceeded their thresholds{}",
    junit_note(.junit_error)
)]
pub struct GateFailed {
    /// Failed checks.
    pub failed: usize,
    /// All checks.
    pub total: usize,
    /// Why the JUnit report was not written, when it was asked for and could not be.
    pub junit_error: Option<String>,
}

fn junit_note(e: &Option<String>) -> String {
    e.as_ref()
        .map_or_else(String::new, |e| format!("; and {e}"))
}

/// Run `gate`: the thresholds are read and validated first, so that a bad thresholds file is
/// refused before `--config` runs a whole report; so is a `--junit` path that is not the gate's
/// to write ([`check_junit_target`]). The PASS/FAIL lines are printed before the JUnit report is
/// written, and a report that cannot be written leaves a failed gate at exit 1 (a passed one
/// exits 2: its report is missing).
pub fn run(args: Args, quiet: bool) -> Result<()> {
    if let (Some(b), Some(c)) = (&args.baseline, &args.candidate) {
        return run_baseline(&args, b, c);
    }
    if let Some(p) = &args.power {
        let plan = sins_harness::gate_power::PowerPlan {
            seeds_per_side: args.seeds_per_side.clone(),
            worsen_percent: args.worsen_percent.clone(),
            set: args.worsen_set.clone(),
            draws: args.draws,
            rule: sins_harness::baseline::BaselineRule {
                margin_percent: args.margin_percent,
                confidence: args.confidence,
            },
            seed: 1,
        };
        return crate::gate_power::run(p, &plan);
    }
    let (thresholds_path, report) = thresholds_and_report(&args)?;
    let thresholds = load_thresholds(&thresholds_path)?;
    let mut inputs = vec![("thresholds", thresholds_path.clone())];
    inputs.extend(args.config.clone().map(|c| ("report configuration", c)));
    inputs.extend(args.summary.clone().map(|s| ("summary", s)));
    if let Some(j) = &args.junit {
        check_junit_target(j, &inputs)?;
    }
    let summary_path = match (report, &args.summary) {
        (Some(r), _) => {
            let produced = report::produce(&r, quiet)?;
            inputs.push(("summary", produced.clone()));
            if let Some(j) = &args.junit {
                check_junit_target(j, &inputs)?;
            }
            produced
        }
        (None, Some(s)) => s.clone(),
        (None, None) => bail!("give --summary FILE --thresholds FILE, or --config FILE"),
    };
    let summary = read_summary(&summary_path)?;
    let checks = thresholds
        .check(&summary, &summary_path)
        .with_context(|| format!("gate thresholds {}", thresholds_path.display()))?;
    for c in &checks {
        say!("{} {}", if c.passed { "PASS" } else { "FAIL" }, c.message)?;
    }
    let junit_error = args
        .junit
        .as_ref()
        .and_then(|j| write_junit(j, &summary.name, &checks).err());
    verdict(&checks, junit_error)
}

/// `gate --baseline B --candidate C`: the shift of every cell against the run-to-run spread
/// ([`sins_harness::baseline`]); the same lines, JUnit report and exit codes as the thresholds.
fn run_baseline(args: &Args, baseline: &Path, candidate: &Path) -> Result<()> {
    let inputs = vec![
        ("baseline", baseline.to_path_buf()),
        ("candidate", candidate.to_path_buf()),
    ];
    if let Some(j) = &args.junit {
        check_junit_target(j, &inputs)?;
    }
    let base = sins_config::read_report_list(baseline)?;
    let cand = sins_config::read_report_list(candidate)?;
    let rule = sins_harness::baseline::BaselineRule {
        margin_percent: args.margin_percent,
        confidence: args.confidence,
    };
    let (_, checks) = sins_harness::baseline::compare(&base, &cand, &rule).map_err(|e| {
        anyhow!(
            "gate --baseline {} --candidate {}: {e}",
            baseline.display(),
            candidate.display()
        )
    })?;
    for c in &checks {
        say!("{} {}", if c.passed { "PASS" } else { "FAIL" }, c.message)?;
    }
    let name = base.first().map_or("", |s| s.name.as_str());
    let suite = format!("{name} against its baseline");
    let junit_error = args
        .junit
        .as_ref()
        .and_then(|j| write_junit(j, &suite, &checks).err());
    verdict(&checks, junit_error)
}

/// Exit 1 with [`GateFailed`] when a check failed, 2 when the JUnit report asked for is
/// missing, else say that the gate passed.
fn verdict(checks: &[Check], junit_error: Option<anyhow::Error>) -> Result<()> {
    let failed = checks.iter().filter(|c| !c.passed).count();
    if failed > 0 {
        return Err(GateFailed {
            failed,
            total: checks.len(),
            junit_error: junit_error.map(|e| e.to_string()),
        }
        .into());
    }
    if let Some(e) = junit_error {
        let n = checks.len();
        return Err(e.context(format!(
            "gate passed ({n} of {n} checks), but the JUnit report asked for is missing"
        )));
    }
    say!("gate passed: {} checks", checks.len())
}

/// Writes the JUnit report aside in its directory and renames it into place.
fn write_junit(path: &Path, suite: &str, checks: &[Check]) -> Result<()> {
    crate::outputs::sweep(path.parent().unwrap_or(Path::new(".")));
    let xml = junit_xml(&format!("sinsbench gate {suite}"), checks);
    sins_files::write_file_atomically(path, xml.as_bytes()).map_err(|e| {
        anyhow!(
            "the JUnit report {} was not written: {e}; check that its directory exists and is \
             writable, or give another --junit path",
            path.display()
        )
    })
}

/// Refuses a `--junit` path that the gate must not replace: one of its `inputs` (the same file,
/// by identity: device and inode, so that a symbolic or hard link, `..` or another spelling is
/// caught), a directory, or an existing file that is not a JUnit report the gate wrote (which
/// begins with `<testsuites name="sinsbench gate">`, see `sins_harness::gate::JUNIT_HEAD`).
fn check_junit_target(junit: &Path, inputs: &[(&str, PathBuf)]) -> Result<()> {
    let meta = match std::fs::metadata(junit) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => bail!(
            "--junit {}: cannot be examined ({e}); it is left untouched: give another path",
            junit.display()
        ),
    };
    for (what, input) in inputs {
        if std::fs::metadata(input).is_ok_and(|m| (m.dev(), m.ino()) == (meta.dev(), meta.ino())) {
            let real = std::fs::canonicalize(input).unwrap_or_else(|_| input.clone());
            bail!(
                "--junit {} is {}, the {what} of this gate (the same file): the gate never \
                 writes over its input; give another path for the JUnit report",
                junit.display(),
                real.display()
            );
        }
    }
    crate::outputs::check_file_target(junit, "JUnit report")?;
    if !is_gate_junit(&file_head(junit, 128)?) {
        bail!(
            "--junit {}: exists and is not a JUnit report of `sinsbench gate` (those begin with \
             <testsuites name=\"sinsbench gate\">); it is left untouched: give another path, \
             or remove the file if it may go",
            junit.display()
        );
    }
    Ok(())
}

/// The first `n` bytes of the file at `path` (fewer when it is shorter).
fn file_head(path: &Path, n: usize) -> Result<Vec<u8>> {
    let file = std::fs::File::open(path).with_context(|| {
        format!(
            "--junit {}: cannot be read to see whether the gate wrote it; it is left untouched",
            path.display()
        )
    })?;
    let mut head = Vec::with_capacity(n);
    file.take(n as u64)
        .read_to_end(&mut head)
        .with_context(|| format!("--junit {}: cannot be read", path.display()))?;
    Ok(head)
}

/// The thresholds file to use and, with `--config`, the report to run first.
fn thresholds_and_report(args: &Args) -> Result<(PathBuf, Option<report::Args>)> {
    match (&args.summary, &args.config) {
        (Some(_), None) => {
            let t = args
                .thresholds
                .clone()
                .context("--summary needs --thresholds FILE")?;
            Ok((t, None))
        }
        (None, Some(c)) => {
            let config = load_report_config(c)?;
            let thresholds = match (&args.thresholds, &config.gate) {
                (Some(t), _) | (None, Some(t)) => t.clone(),
                (None, None) => bail!(
                    "{}: no 'gate = \"...\"' key and no --thresholds given",
                    c.display()
                ),
            };
            let r = report::Args {
                config: Some(c.clone()),
                reports_dir: args.reports_dir.clone(),
                uq: None,
                threads: 3,
            };
            Ok((thresholds, Some(r)))
        }
        _ => bail!("give --summary FILE --thresholds FILE, or --config FILE"),
    }
}
