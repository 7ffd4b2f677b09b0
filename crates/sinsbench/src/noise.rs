//! `sinsbench noise`: the IMU's sensor noise identified from the stationary stretches of its
//! runs (Allan deviation and a fit of the terms the twin uses), written as a noise file that
//! `diagnose --noise-from` reads back.

use crate::out::{note, say};
use anyhow::Result;
use sins_gap::noise_report::{noise_rows, write_noise_report};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `noise` (the command's help is its doc in `main.rs`).
#[derive(clap::Args)]
pub struct Args {
    /// A run of the IMU: a dataset in the project's format (repeat for several runs). `NAME=PATH`
    /// names it, otherwise the file stem is the name. Its segment labels choose the stationary
    /// samples (see --labels).
    #[arg(long = "dataset", value_name = "[NAME=]PATH", required = true)]
    pub datasets: Vec<String>,
    /// Segment labels of the stationary samples (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "alignment,stationary")]
    pub labels: Vec<String>,
    /// Output directory: noise.toml (the identified [imu.noise] with [imu.noise_sigma], usable
    /// as `diagnose --noise-from`), allan.png, noise.rrd, noise.md. Replaced only by another
    /// `noise` output.
    #[arg(long, default_value = "reports/noise")]
    pub out: PathBuf,
    /// A calibrated parameter set (TOML, as `calibrate` writes): the accelerometer increments
    /// are compensated with it first, so that the chamber's temperature drift of the bias is
    /// not read as bias instability (`diagnose` always passes its --params). Without it the
    /// increments are used raw.
    #[arg(long, value_name = "FILE")]
    pub params: Option<PathBuf>,
    /// Shortest still stretch used (s). Stretches between the motion of a rocking vehicle can
    /// be short: 10-20 s still identify the white noise (the angle and velocity random walks
    /// show at averaging times of a second or less), not a bias instability.
    #[arg(long, default_value_t = 60.0, value_parser = crate::argcheck::positive_f64)]
    pub min_stretch_s: f64,
}

/// Run `noise`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let datasets = crate::argcheck::datasets(&args.datasets)?;
    let (parent, name) = crate::outputs::output_dir(&args.out, "noise")?;
    if !quiet {
        note!(
            "noise: Allan deviation of the still stretches (labelled {}, or found by the \
             stillness detector in runs without labels; motion inside them left out) of {} run(s)",
            args.labels.join(", "),
            datasets.len()
        );
    }
    let started = Instant::now();
    let set = match &args.params {
        Some(p) => {
            let set = sins_config::load_params(p)?;
            // A 42-state set compensates with the temperatures: a run without them is refused
            // here, in diagnose's words, not identified from NaN increments.
            if set.params.model == sins_imu::ParamModel::States42 {
                for (name, path) in &datasets {
                    let info = crate::argcheck::open_run(name, path)?;
                    crate::argcheck::require_temperatures(
                        name,
                        path,
                        &info,
                        &set.params,
                        p,
                        ", or leave --params out",
                    )?;
                }
            }
            Some(set)
        }
        None => None,
    };
    let cfg = sins_noiseid::NoiseIdConfig {
        labels: args.labels.clone(),
        min_stretch_s: args.min_stretch_s,
        ..Default::default()
    };
    let id = sins_gap::identify_datasets_with(&datasets, &cfg, set.as_ref().map(|s| &s.params))?;
    let seconds = started.elapsed().as_secs_f64();
    let dir = write_noise_report(&parent, &name, &id, &datasets, seconds)?;
    for (term, v) in noise_rows(&id.gyro, &id.accel) {
        say!("  {term:<52} {v}")?;
    }
    for st in &id.stretches {
        say!(
            "  still stretch used: {} {:.1}-{:.1} s ({:.1} min)",
            st.run,
            st.start_s,
            st.start_s + st.duration_s,
            st.duration_s / 60.0
        )?;
    }
    for n in &id.notes {
        say!("  note: {n}")?;
    }
    for r in &id.inconsistent {
        say!("  WARNING: the identified model is inconsistent with its data: {r}")?;
    }
    say!(
        "wrote {} ({:.2} h stationary, {seconds:.1} s); use it with `diagnose --noise-from {}`",
        dir.display(),
        id.stationary_s() / 3600.0,
        dir.join("noise.toml").display()
    )
}
