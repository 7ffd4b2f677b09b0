//! `sinsbench report`: the paper's Table 5, replicated or on your own data.

use crate::out::say;
use crate::{argcheck, defaults, progress};
use anyhow::Result;
use sins_config::load_report_config;
use std::path::PathBuf;

/// Arguments of `report`.
#[derive(clap::Args)]
pub struct Args {
    /// Report configuration (TOML; schema in experiments/README.md). Default: the built-in
    /// replica of the paper, experiments/harness/report_paper.toml: simulate the truth IMU's 4.2 h
    /// calibration run, calibrate it with the 30- and 42-state filters, simulate the three 15 h
    /// navigation runs and replay each under both parameter sets. Your own: list your parameter
    /// files and datasets instead.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Directory that receives <NAME>/ (report.md, summary.json, plots, .rrd, error tracks).
    #[arg(long, default_value = "reports")]
    pub reports_dir: PathBuf,
    /// A `replica-uq` output directory: report.md then shows, per Table 5 cell, the Monte Carlo
    /// median and 5-95 % interval and the V&V 20 verdict against the paper beside the point
    /// replica (read from DIR/summary.json; nothing is recomputed). Overrides the
    /// configuration's `uq` key.
    #[arg(long)]
    pub uq: Option<PathBuf>,
    /// Simulated runs computed side by side: the calibration runs, then the navigation runs
    /// (results do not depend on it). Default 3, the replica's three navigation runs at once:
    /// each run's replays also hand their reconstruction to worker threads, and on 2 cores three
    /// runs at once keep both busy (28 s) where two at a time leave one idle for the third (36 s).
    #[arg(long, default_value_t = 3, value_parser = argcheck::threads)]
    pub threads: usize,
}

/// Run the configured report and write it; returns the summary path.
pub fn produce(args: &Args, quiet: bool) -> Result<PathBuf> {
    let path = args.config.clone().unwrap_or_else(defaults::report_config);
    let config = load_report_config(&path)?;
    crate::outputs::sweep(&args.reports_dir);
    sins_report::check_output_dir(&args.reports_dir, &config.name, "report")?;
    sins_files::lock::lock_output(&args.reports_dir, Some(&config.name))?;
    let mut bars = progress::Bars::new(quiet);
    let uq_dir = args.uq.clone().or_else(|| config.uq.clone());
    let uq = uq_dir.as_deref().map(load_uq_summary).transpose()?;
    let mut run = sins_report::run_report(&config, args.threads, &mut bars)?;
    if let (Some(u), Some(dir)) = (&uq, &uq_dir) {
        let s = &run.summary;
        let point = |cell: &str| point_of(s, cell);
        run.appendix = Some(sins_report::prediction_for_report(
            u,
            &study_source(dir),
            &point,
        ));
    }
    let files = sins_report::write_report(&args.reports_dir, &run)?;
    print_table(&run.summary)?;
    say!(
        "wrote {} ({} files: report.md, summary.json, plots, .rrd, error tracks)",
        files.dir.display(),
        files.files.len()
    )?;
    Ok(files.dir.join("summary.json"))
}

/// Run `report`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    produce(&args, quiet).map(|_| ())
}

fn print_table(s: &sins_harness::summary::Summary) -> Result<()> {
    for e in &s.experiments {
        let cells: Vec<String> = e
            .results
            .iter()
            .map(|(k, r)| {
                format!(
                    "{k} {:.3} nmi at {:.2} h ({})",
                    r.max_horizontal_nmi,
                    r.t_max_s / 3600.0,
                    r.segment_at_max
                )
            })
            .collect();
        let imp = e
            .improvement_percent
            .map_or(String::new(), |v| format!("; improvement {v:.1} %"));
        say!("{}: {}{imp}", e.name, cells.join(", "))?;
    }
    Ok(())
}

/// This report's figure of a Table 5 cell label ("exp1 without", "exp2 with", "exp3
/// improvement"): the n-th experiment's baseline, compensated set or improvement.
fn point_of(s: &sins_harness::summary::Summary, cell: &str) -> Option<f64> {
    let id = sins_uq::cell::CellId::parse(cell)?;
    let e = s.experiments.get(id.experiment - 1)?;
    let c = s.comparison.as_ref()?;
    let nmi = |k: &str| e.results.get(k).map(|r| r.max_horizontal_nmi);
    match id.kind {
        sins_uq::cell::CellKind::Without => nmi(&c.baseline),
        sins_uq::cell::CellKind::With => nmi(&c.compensated),
        sins_uq::cell::CellKind::Improvement => e.improvement_percent,
    }
}

/// Where the study is (relative to the working directory when inside it), its manifest's
/// digest and the command that makes it again.
fn study_source(dir: &std::path::Path) -> String {
    let shown = std::fs::canonicalize(dir)
        .ok()
        .and_then(|d| {
            let cwd = std::env::current_dir().ok()?;
            d.strip_prefix(&cwd).ok().map(std::path::Path::to_path_buf)
        })
        .unwrap_or_else(|| dir.to_path_buf());
    let digest = std::fs::read_to_string(dir.join("manifest.json"))
        .ok()
        .and_then(|m| serde_json::from_str::<serde_json::Value>(&m).ok())
        .and_then(|v| {
            v["sha256"]
                .as_str()
                .map(|h| h.chars().take(12).collect::<String>())
        })
        .map_or(String::new(), |h| format!(" (manifest sha256 {h}...)"));
    format!(
        "`{}/summary.json`{digest}; made again, bit for bit, by `sinsbench replica-uq --out {}`",
        shown.display(),
        shown.display()
    )
}

/// The summary of a `replica-uq` directory.
fn load_uq_summary(dir: &std::path::Path) -> Result<sins_uq::summary::UqSummary> {
    use anyhow::Context;
    let path = dir.join("summary.json");
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "{}: no replica-uq summary (run `sinsbench replica-uq --out {}` first)",
            path.display(),
            dir.display()
        )
    })?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not a replica-uq summary", path.display()))
}
