//! `sinsbench diagnose`: where real data part from the twin, which unmodelled effect explains
//! it, and how far the gap shrinks on withheld runs.

use crate::argcheck;
use crate::out::{note, say};
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
    /// The IMU's sensor noise (the twin's spread): a noise file written by `sinsbench noise`
    /// (noise.toml) or an experiment file whose [imu.noise] gives it (e.g.
    /// experiments/paper_navigation.toml, the paper IMU's figures). Default: identified from
    /// the datasets' stationary segments (see --noise-labels) exactly as `sinsbench noise` does;
    /// the report's notes say which noise was used.
    #[arg(long)]
    pub noise_from: Option<PathBuf>,
    /// Segment labels of the stationary samples the noise is identified from when no
    /// --noise-from is given (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "alignment,stationary")]
    pub noise_labels: Vec<String>,
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
    let datasets = argcheck::datasets(&args.datasets)?;
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
    let (parent, name) = crate::outputs::output_dir(&args.out, "diagnose")?;
    let set = sins_config::load_params(&args.params)?;
    let (noise, noise_notes, untrusted) = match &args.noise_from {
        Some(path) => {
            let table = sins_config::load_noise(path)?;
            let what = if table.from_noise_file {
                "noise file"
            } else {
                "[imu.noise] of experiment"
            };
            let walks = match table.unresolved_walk_per_sqrt_s {
                Some([g, a]) => format!(
                    "; rate random walks it could not exclude, fitted on the gap up to {:.3e} deg/h/√h (gyro) and {:.3} ug/√h (accel)",
                    g / sins_config::units::DEG_PER_H_PER_SQRT_H,
                    a / sins_config::units::UG_PER_SQRT_H
                ),
                None => String::new(),
            };
            (
                NoiseSpec {
                    unresolved_walk_per_sqrt_s: table.unresolved_walk_per_sqrt_s,
                    ..NoiseSpec::from(&table.noise)
                },
                vec![format!("twin noise: the {what} {}{walks}", path.display())],
                table.inconsistent.clone(),
            )
        }
        None => {
            if !quiet {
                note!(
                    "diagnose: no --noise-from: identifying the twin's noise from the stationary segments ({}) of the datasets",
                    args.noise_labels.join(", ")
                );
            }
            let id = sins_gap::identify_datasets(&datasets, &args.noise_labels, Some(&set.params))
                .context("no --noise-from was given, so the noise is identified from the data (give --noise-from FILE to use a file instead)")?;
            let line = crate::noise::one_line(&id);
            let mut notes = vec![format!(
                "twin noise: identified from the data's stationary segments (sinsbench noise): {line}"
            )];
            notes.extend(id.turn_on_note());
            notes.extend(id.change_notes());
            notes.extend(id.motion_notes());
            (id.to_noise_spec(), notes, id.inconsistent.clone())
        }
    };
    for n in &noise_notes {
        say!("{n}")?;
    }
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
    let mut outcome = outcome;
    outcome.diagnosis.notes.splice(0..0, noise_notes);
    outcome.diagnosis.noise_untrusted = untrusted;
    let dir = write_diagnosis(&parent, &name, &outcome)?;
    say!("verdict: {:?}", outcome.diagnosis.verdict)?;
    for r in &outcome.diagnosis.noise_untrusted {
        say!("  the twin's noise cannot be trusted: {r}")?;
    }
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
