//! `sinsbench gate`: the release gate on a report's summary.

use crate::report;
use anyhow::{Context, Result, bail};
use sins_harness::gate::{Thresholds, junit_xml};
use sins_harness::summary::Summary;
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

/// Run `gate`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let (summary_path, thresholds_path) = match (&args.summary, &args.config) {
        (Some(s), None) => (
            s.clone(),
            args.thresholds
                .clone()
                .context("--summary needs --thresholds FILE")?,
        ),
        (None, Some(c)) => {
            let config = sins_harness::config::load_report_config(c)?;
            let thresholds = match (&args.thresholds, &config.gate) {
                (Some(t), _) => t.clone(),
                (None, Some(t)) => t.clone(),
                (None, None) => bail!(
                    "{}: no 'gate = \"...\"' key and no --thresholds given",
                    c.display()
                ),
            };
            let r = report::Args {
                config: Some(c.clone()),
                reports_dir: args.reports_dir.clone(),
            };
            (report::produce(&r, quiet)?, thresholds)
        }
        _ => bail!("give --summary FILE --thresholds FILE, or --config FILE"),
    };
    let thresholds = Thresholds::load(&thresholds_path)?;
    let summary = Summary::from_json_file(&summary_path)?;
    let checks = thresholds.evaluate(&summary);
    if let Some(j) = &args.junit {
        let xml = junit_xml(&format!("sinsbench gate {}", summary.name), &checks);
        std::fs::write(j, xml).with_context(|| format!("cannot write {}", j.display()))?;
    }
    let failed = checks.iter().filter(|c| !c.passed).count();
    for c in &checks {
        println!("{} {}", if c.passed { "PASS" } else { "FAIL" }, c.message);
    }
    if failed > 0 {
        return Err(GateFailed {
            failed,
            total: checks.len(),
        }
        .into());
    }
    println!("gate passed: {} checks", checks.len());
    Ok(())
}
