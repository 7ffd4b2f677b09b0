//! `sinsbench gate`: the release gate on a report's summary.

use crate::out::say;
use crate::report;
use anyhow::{Context, Result, bail};
use sins_config::{load_report_config, load_thresholds, read_summary};
use sins_harness::gate::junit_xml;
use std::path::PathBuf;

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
    /// Also write the checks as JUnit XML (one test case per check) for CI systems.
    #[arg(long)]
    pub junit: Option<PathBuf>,
    /// Directory of the report when --config runs one.
    #[arg(long, default_value = "reports")]
    pub reports_dir: PathBuf,
}

/// The gate found thresholds exceeded (exit code 1; errors exit with 2).
#[derive(Debug, thiserror::Error)]
#[error("gate failed: {failed} of {total} checks exceeded their thresholds")]
pub struct GateFailed {
    /// Failed checks.
    pub failed: usize,
    /// All checks.
    pub total: usize,
}

/// Run `gate`: the thresholds are read and validated first, so that a bad thresholds file is
/// refused before `--config` runs a whole report.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let (thresholds_path, report) = thresholds_and_report(&args)?;
    let thresholds = load_thresholds(&thresholds_path)?;
    let summary_path = match (report, &args.summary) {
        (Some(r), _) => report::produce(&r, quiet)?,
        (None, Some(s)) => s.clone(),
        (None, None) => bail!("give --summary FILE --thresholds FILE, or --config FILE"),
    };
    let summary = read_summary(&summary_path)?;
    let checks = thresholds.check(&summary, &summary_path).with_context(|| {
        format!(
            "nothing to check with thresholds {}",
            thresholds_path.display()
        )
    })?;
    if let Some(j) = &args.junit {
        let xml = junit_xml(&format!("sinsbench gate {}", summary.name), &checks);
        std::fs::write(j, xml).with_context(|| format!("cannot write {}", j.display()))?;
    }
    for c in &checks {
        say!("{} {}", if c.passed { "PASS" } else { "FAIL" }, c.message)?;
    }
    let failed = checks.iter().filter(|c| !c.passed).count();
    if failed > 0 {
        return Err(GateFailed {
            failed,
            total: checks.len(),
        }
        .into());
    }
    say!("gate passed: {} checks", checks.len())
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
            };
            Ok((thresholds, Some(r)))
        }
        _ => bail!("give --summary FILE --thresholds FILE, or --config FILE"),
    }
}
