//! `sinsbench simulate`: experiment definition → one dataset per run.

use crate::{defaults, progress};
use anyhow::{Context, Result};
use sins_data::{ColumnSet, DatasetMeta, DatasetWriter, ReferenceRow, SampleBatch};
use sins_nav::attitude::euler_from_ned_from_body;
use sins_sim::{Scenario, SimBatch, Simulator};
use std::path::{Path, PathBuf};

/// Arguments of `simulate`.
#[derive(clap::Args)]
pub struct Args {
    /// Experiment definition (TOML, see experiments/README.md). Default: the paper's 15 h
    /// navigation experiment, experiments/paper_navigation.toml.
    pub experiment: Option<PathBuf>,
    /// Output directory; each run becomes <OUT>/<run>.parquet (or .csv).
    /// Default: out/<experiment name>.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Simulate only this run (repeat for several). Default: every run.
    #[arg(long = "run", value_name = "NAME")]
    pub runs: Vec<String>,
    /// Dataset format.
    #[arg(long, value_enum, default_value_t = Format::Parquet)]
    pub format: Format,
    /// Override the seed of every run.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Also write the truth columns (ref_lat_rad … ref_yaw_rad).
    #[arg(long)]
    pub reference: bool,
}

/// Dataset file format.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Format {
    /// Apache Parquet with key-value metadata (default).
    Parquet,
    /// CSV with `# key = value` metadata lines.
    Csv,
}

impl Format {
    fn extension(self) -> &'static str {
        match self {
            Format::Parquet => "parquet",
            Format::Csv => "csv",
        }
    }
}

/// Run `simulate`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let path = args
        .experiment
        .clone()
        .unwrap_or_else(defaults::navigation_experiment);
    let experiment = sins_config::load_experiment(&path)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&experiment.name));
    std::fs::create_dir_all(&out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    for name in &args.runs {
        if !experiment.scenarios.iter().any(|s| &s.name == name) {
            let known: Vec<_> = experiment
                .scenarios
                .iter()
                .map(|s| s.name.as_str())
                .collect();
            anyhow::bail!(
                "{}: no run named '{name}' (runs: {})",
                path.display(),
                known.join(", ")
            );
        }
    }
    for scenario in &experiment.scenarios {
        if !args.runs.is_empty() && !args.runs.contains(&scenario.name) {
            continue;
        }
        let mut scenario = scenario.clone();
        if let Some(seed) = args.seed {
            scenario.seed = seed;
        }
        scenario.with_reference |= args.reference;
        let file = out.join(format!("{}.{}", scenario.name, args.format.extension()));
        let summary = simulate_one(&experiment.name, &scenario, &file, quiet)?;
        println!(
            "{}: {} samples, {:.2} h, {:.1} MB",
            summary.path.display(),
            summary.n_rows,
            summary.n_rows as f64 / scenario.rate_hz / 3600.0,
            summary.n_bytes as f64 / 1e6
        );
    }
    Ok(())
}

/// Dataset metadata for a simulated scenario: site, rate, description, and the experiment,
/// run, seed and initial attitude as extra keys.
pub fn dataset_meta(experiment: &str, scenario: &Scenario) -> DatasetMeta {
    let mut meta = DatasetMeta::new(
        scenario.rate_hz,
        scenario.site,
        scenario.description.clone(),
    );
    let e = euler_from_ned_from_body(&scenario.motion.initial_ned_from_body);
    for (k, v) in [
        ("experiment", experiment.to_string()),
        ("run", scenario.name.clone()),
        ("seed", scenario.seed.to_string()),
        ("initial_pitch_deg", e.pitch_rad.to_degrees().to_string()),
        ("initial_roll_deg", e.roll_rad.to_degrees().to_string()),
        ("initial_yaw_deg", e.yaw_rad.to_degrees().to_string()),
    ] {
        meta.extra.insert(k.to_string(), v);
    }
    meta
}

/// Simulate one scenario into `file` (written aside and renamed when complete).
pub fn simulate_one(
    experiment: &str,
    scenario: &Scenario,
    file: &Path,
    quiet: bool,
) -> Result<sins_data::WriteSummary> {
    let mut sim = Simulator::from_scenario(scenario)
        .with_context(|| format!("scenario '{}'", scenario.name))?;
    let labels = sim.segment_labels().to_vec();
    let label_of_segment = sim.segment_label_indices().to_vec();
    let columns = ColumnSet {
        temperature: true,
        segment: true,
        reference: scenario.with_reference,
    };
    let mut writer =
        DatasetWriter::create(file, &dataset_meta(experiment, scenario), columns, &labels)?;
    let pb = progress::bar(sim.n_samples() as u64, &scenario.name, quiet);
    let mut batch = SampleBatch {
        first_row: 0,
        samples: Vec::new(),
        segment_index: Some(Vec::new()),
        reference: None,
    };
    sim.run(65_536, |b: &SimBatch| -> Result<()> {
        to_sample_batch(b, &label_of_segment, &mut batch);
        writer.write_batch(&batch)?;
        pb.inc(b.samples.len() as u64);
        Ok(())
    })?;
    pb.finish_and_clear();
    Ok(writer.finish()?)
}

fn to_sample_batch(b: &SimBatch, label_of_segment: &[u16], out: &mut SampleBatch) {
    out.samples.clear();
    out.samples.extend_from_slice(&b.samples);
    let seg = out.segment_index.get_or_insert_with(Vec::new);
    seg.clear();
    seg.extend(
        b.segment_index
            .iter()
            .map(|&s| label_of_segment.get(s as usize).copied().unwrap_or(0)),
    );
    out.reference = b.reference.as_ref().map(|refs| {
        refs.iter()
            .map(|r| {
                let e = euler_from_ned_from_body(&r.ned_from_body);
                ReferenceRow {
                    lat_rad: r.position.lat_rad,
                    lon_rad: r.position.lon_rad,
                    height_m: r.position.height_m,
                    vel_n_mps: r.vel_ned_mps.x,
                    vel_e_mps: r.vel_ned_mps.y,
                    vel_d_mps: r.vel_ned_mps.z,
                    pitch_rad: e.pitch_rad,
                    roll_rad: e.roll_rad,
                    yaw_rad: e.yaw_rad,
                }
            })
            .collect()
    });
}
