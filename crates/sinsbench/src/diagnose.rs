//! `sinsbench diagnose`: where real data part from the twin, which unmodelled effect explains
//! it, and how far the gap shrinks on withheld runs.

use crate::out::{note, say};
use crate::{argcheck, defaults};
use anyhow::{Context, Result, bail};
use sins_diag::input::DiagnoseConfig;
use sins_diag::noise::NoiseSpec;
use sins_gap::{DiagnoseRequest, diagnose_datasets, write_diagnosis};
use std::path::PathBuf;

/// Arguments of `diagnose`.
#[derive(clap::Args)]
pub struct Args {
    /// A real run: a dataset in the project's format (repeat for several runs of the same IMU:
    /// the calibration run and/or navigation runs on the turntable). `NAME=PATH` names it,
    /// otherwise the file stem is the name. Runs need a 20 min stationary start (the
    /// self-alignment) and the site in their metadata; 42-state sets need the temperatures.
    #[arg(long = "dataset", value_name = "[NAME=]PATH", required = true)]
    pub datasets: Vec<String>,
    /// The calibrated parameter set the real runs are compensated with (TOML/JSON in the
    /// paper's units; its 1-sigma, when present, widens the twin).
    #[arg(long)]
    pub params: PathBuf,
    /// An experiment file whose [imu.noise] describes the IMU's sensor noise (the twin's spread).
    /// Default: experiments/paper_navigation.toml (the paper IMU's figures).
    #[arg(long)]
    pub noise_from: Option<PathBuf>,
    /// Only these candidate effects (comma-separated kind names); default the whole catalogue.
    #[arg(long, value_delimiter = ',')]
    pub candidates: Vec<String>,
    /// Output directory: report.md, diagnosis.json, gap_<run>.png, diagnosis.rrd.
    #[arg(long, default_value = "reports/diagnosis")]
    pub out: PathBuf,
    /// The run the parameter set was calibrated from (by `sinsbench calibrate`, same model):
    /// the diagnosis recalibrates it once per candidate component with the component added, so
    /// that each candidate also acts through the coefficients the calibration absorbed it into
    /// (an effect present during calibration biases them; about 1 s of filter per component).
    /// Default: the run named `cal`, if any; `none` turns it off.
    #[arg(long, value_name = "NAME")]
    pub calibration_run: Option<String>,
    /// Worker threads (results do not depend on it).
    #[arg(long, default_value_t = 2, value_parser = argcheck::threads)]
    pub threads: usize,
}

/// Run `diagnose`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let mut datasets = Vec::new();
    for d in &args.datasets {
        let (name, path) = match d.split_once('=') {
            Some((n, p)) if !n.is_empty() => (n.to_string(), PathBuf::from(p)),
            _ => {
                let p = PathBuf::from(d);
                let n = p
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .with_context(|| format!("--dataset {d}: not a file path"))?;
                (n, p)
            }
        };
        if datasets.iter().any(|(n, _): &(String, PathBuf)| n == &name) {
            bail!("--dataset: two runs are named '{name}'; name them with NAME=PATH");
        }
        datasets.push((name, path));
    }
    let calibration_run = match args.calibration_run.as_deref() {
        Some("none") => None,
        Some(name) => {
            if !datasets.iter().any(|(n, _)| n == name) {
                bail!("--calibration-run {name}: no --dataset is named '{name}'");
            }
            Some(name.to_string())
        }
        None => datasets
            .iter()
            .find(|(n, _)| n == "cal")
            .map(|(n, _)| n.clone()),
    };
    let parent = args.out.parent().map_or(PathBuf::from("."), PathBuf::from);
    let name = args
        .out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .context("--out must name a directory")?;
    crate::outputs::sweep(&parent);
    sins_report::check_output_dir(&parent, &name, "diagnose")?;
    let set = sins_config::load_params(&args.params)?;
    let noise_path = args
        .noise_from
        .clone()
        .unwrap_or_else(defaults::navigation_experiment);
    let exp = sins_config::load_experiment(&noise_path)?;
    let noise = NoiseSpec::from(
        &exp.scenarios
            .first()
            .with_context(|| format!("{}: no [[run]]", noise_path.display()))?
            .noise,
    );
    let config = DiagnoseConfig {
        candidates: args.candidates.clone(),
        threads: args.threads,
        ..DiagnoseConfig::default()
    };
    config
        .candidate_kinds()
        .map_err(|e| anyhow::anyhow!("--candidates: {e}"))?;
    if !quiet {
        note!(
            "diagnose: replaying {} run(s) with {} and fitting the catalogue against the twin",
            datasets.len(),
            args.params.display()
        );
    }
    let outcome = diagnose_datasets(&DiagnoseRequest {
        datasets,
        params: set.params,
        param_sigma: set.sigma,
        param_covariance: None,
        noise,
        calibration_run,
        config,
    })?;
    let dir = write_diagnosis(&parent, &name, &outcome)?;
    say!("verdict: {:?}", outcome.diagnosis.verdict)?;
    for c in outcome.diagnosis.candidates.iter().take(3) {
        say!(
            "  {:<32} dchi2 {:>10.1}  dBIC {:>10.1}  {}",
            c.kind,
            c.dchi2,
            c.delta_bic,
            if c.passes { "passes" } else { "" }
        )?;
    }
    say!(
        "wrote {} (replays {:.1} s, diagnosis {:.1} s)",
        dir.display(),
        outcome.replay_s,
        outcome.diagnose_s
    )
}
