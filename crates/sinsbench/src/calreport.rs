//! `sinsbench calibration-report`: the paper's Table 1 reproduced over Monte Carlo seeds, the
//! 30-state filter's temperature leak, and the least-squares baseline against the 42-state
//! filter (Table 3 with the truth column).

use crate::defaults;
use crate::out::{note, say};
use anyhow::{Context, Result};
use sins_calstudy::{StudyConfig, render_markdown, run_study};
use std::path::PathBuf;

/// Arguments of `calibration-report`.
#[derive(clap::Args)]
pub struct Args {
    /// Monte Carlo seeds of the Table 1 simulation (the paper's 4.2 h run, 42-state filter).
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u16).range(1..=1000))]
    pub seeds: u16,
    /// Worker threads (the results are identical for any count).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(1..=64))]
    pub threads: u8,
    /// Directory that receives calibration/ (report.md, summary.json).
    #[arg(long, default_value = "reports")]
    pub reports_dir: PathBuf,
}

/// Run `calibration-report`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let mut config = StudyConfig::paper(defaults::experiments_dir());
    config.seeds = args.seeds as usize;
    config.threads = args.threads as usize;
    if !quiet {
        note!(
            "calibration study: {} Monte Carlo seeds of the 4.2 h run (42-state), the 30-state filter, \
             four least-squares temperature points and the proposed run ({} calibrations, about {} s on 2 cores)",
            config.seeds,
            config.seeds + 7,
            (config.seeds + 7) * 2
        );
    }
    // Sweeps, checks that REPORTS/calibration is absent or a previous calibration report, and
    // locks it for this process: a second `calibration-report` into it is refused at once.
    crate::outputs::output_dir(&args.reports_dir.join("calibration"), "calibration-report")?;
    let study = run_study(&config)?;
    let json = serde_json::to_string_pretty(&study).context("serialising the study")?;
    let md = render_markdown(&study);
    let files = sins_report::write_dir_atomically(
        &args.reports_dir,
        "calibration",
        "calibration-report",
        |dir| {
            for (name, text) in [("report.md", &md), ("summary.json", &json)] {
                sins_report::write_bytes(&dir.join(name), text.as_bytes())?;
            }
            Ok(vec!["report.md".into(), "summary.json".into()])
        },
    )?;
    say!("wrote {}/report.md and summary.json", files.dir.display())
}
