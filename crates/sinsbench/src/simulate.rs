//! `sinsbench simulate`: experiment definition → one dataset per run.

use crate::out::say;
use crate::{defaults, progress};
use anyhow::{Context, Result};
use sins_sim::Scenario;
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
    /// Add the `[[imu.effect]]` tables of this TOML file to every run's IMU, after the
    /// experiment's own (e.g. to make "real" data with a known unmodelled effect for
    /// `diagnose`; keys and units in experiments/README.md).
    #[arg(long, value_name = "FILE")]
    pub effects: Option<PathBuf>,
    /// Refuse, before writing anything, when the datasets are estimated at more than this many
    /// GB (decimal). Default: the SINSBENCH_MAX_OUTPUT_GB environment variable when set,
    /// otherwise no limit beyond the free space of the output file system (always checked).
    #[arg(long, value_name = "GB", value_parser = crate::argcheck::positive_f64)]
    pub max_output_gb: Option<f64>,
}

/// Environment variable that sets the default of `simulate --max-output-gb` (GB, decimal).
pub const MAX_OUTPUT_ENV: &str = "SINSBENCH_MAX_OUTPUT_GB";

/// The output limit in bytes: `--max-output-gb`, else [`MAX_OUTPUT_ENV`], else none.
fn output_limit_bytes(args: &Args) -> Result<Option<u64>> {
    let gb = match args.max_output_gb {
        Some(gb) => Some(gb),
        None => match std::env::var(MAX_OUTPUT_ENV) {
            Ok(text) => Some(crate::argcheck::positive_f64(&text).map_err(|e| {
                anyhow::anyhow!("environment variable {MAX_OUTPUT_ENV}={text:?}: {e}")
            })?),
            Err(_) => None,
        },
    };
    // f64 -> u64 saturates, so an enormous limit is simply no limit.
    Ok(gb.map(|gb| (gb * 1e9) as u64))
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
    // Writing a dataset is this command's main cost: keep the Parquet writer's pages.
    crate::malloc::tune();
    let path = args
        .experiment
        .clone()
        .unwrap_or_else(defaults::navigation_experiment);
    let experiment = sins_config::load_experiment(&path)?;
    let extra = match &args.effects {
        Some(f) => {
            let text = std::fs::read_to_string(f)
                .with_context(|| format!("cannot read effects file {}", f.display()))?;
            let specs = sins_config::parse_effects_toml(&text, &f.display().to_string())?;
            anyhow::ensure!(
                !specs.is_empty(),
                "{}: no [[imu.effect]] table",
                f.display()
            );
            specs
        }
        None => Vec::new(),
    };
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&experiment.name));
    let selected = experiment
        .scenarios
        .iter()
        .filter(|s| args.runs.is_empty() || args.runs.contains(&s.name));
    let needed: u64 = selected
        .map(|s| {
            let n_rows = (sins_config::motion_duration_s(&s.motion) * s.rate_hz).round() as u64;
            let reference = s.with_reference || args.reference;
            let csv = matches!(args.format, Format::Csv);
            sins_report::estimated_dataset_bytes(n_rows, reference, csv)
        })
        .fold(0u64, u64::saturating_add);
    for name in &args.runs {
        sins_config::run_name(name).map_err(|e| anyhow::anyhow!("--run: {e}"))?;
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
    sins_report::check_output_space(&out, needed, output_limit_bytes(&args)?)?;
    std::fs::create_dir_all(&out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    sins_files::lock::lock_output(&out, None)?;
    // Every run is written into a staging directory inside OUT and the whole set is moved into
    // place at the end: an interrupted or failed run leaves the previous datasets as they were.
    let staging = sins_files::Temporary::dir(&out.join("simulate"))
        .with_context(|| format!("cannot create a staging directory in {}", out.display()))?;
    let unchanged = format!("the previous datasets in {} are unchanged", out.display());
    sins_files::set_interrupt_note(Some(unchanged.clone()));
    let mut names = Vec::new();
    let mut lines = Vec::new();
    for scenario in &experiment.scenarios {
        if !args.runs.is_empty() && !args.runs.contains(&scenario.name) {
            continue;
        }
        let mut scenario = scenario.clone();
        if let Some(seed) = args.seed {
            scenario.seed = seed;
        }
        scenario.with_reference |= args.reference;
        scenario.effects.extend(extra.iter().cloned());
        let name = format!("{}.{}", scenario.name, args.format.extension());
        let summary = simulate_one(
            &experiment.name,
            &scenario,
            &staging.path().join(&name),
            quiet,
        )
        .with_context(|| format!("run '{}' failed; {unchanged}", scenario.name))?;
        lines.push(format!(
            "{}: {} samples, {:.2} h, {:.1} MB",
            out.join(&name).display(),
            summary.n_rows,
            summary.n_rows as f64 / scenario.rate_hz / 3600.0,
            summary.n_bytes as f64 / 1e6
        ));
        names.push(name);
    }
    sins_files::commit_files(staging, &names).with_context(|| {
        format!(
            "cannot move the new datasets into {}; {unchanged}",
            out.display()
        )
    })?;
    for line in &lines {
        say!("{line}")?;
    }
    Ok(())
}

/// Simulate one scenario into `file` (written aside and renamed when complete).
pub fn simulate_one(
    experiment: &str,
    scenario: &Scenario,
    file: &Path,
    quiet: bool,
) -> Result<sins_data::WriteSummary> {
    let mut bars = progress::Bars::new(quiet);
    Ok(sins_report::simulate_to_dataset(
        experiment, scenario, file, &mut bars,
    )?)
}
