//! `sinsbench blind`: the blind validation suite of the gap diagnosis.

use crate::out::say;
use crate::{defaults, progress};
use anyhow::{Context, Result};
use sins_diag::input::DiagnoseConfig;
use sins_gap::blind::plan::SuiteShape;
use sins_gap::blind::suite::{SuiteConfig, run_suite};
use std::path::PathBuf;

/// Arguments of `blind`.
#[derive(clap::Args)]
pub struct Args {
    /// Number of cases.
    #[arg(long, default_value_t = 30)]
    pub cases: usize,
    /// Of which without a hidden effect.
    #[arg(long, default_value_t = 5)]
    pub null: usize,
    /// Of which with an effect outside the catalogue.
    #[arg(long, default_value_t = 3)]
    pub outside: usize,
    /// Cases with an effect local in time (a bias step, ramp or transient on one channel),
    /// drawn after the others (the first cases are those of a suite without them).
    #[arg(long, default_value_t = 0)]
    pub time_local: usize,
    /// Cases of the widened time-local draw, after those: shapes in turn (step, ramp, ramp to a
    /// plateau, pulse, transient, decaying oscillation), gyro or accelerometer, in one
    /// navigation run, in every navigation run at the same time, or in the calibration run only.
    #[arg(long, default_value_t = 0)]
    pub wide_time_local: usize,
    /// Cases with a temperature-driven catalogue effect whose navigation runs have markedly
    /// different chamber histories (experiments/blind/navigation_varied_histories.toml), last.
    #[arg(long, default_value_t = 0)]
    pub different_histories: usize,
    /// The twin's noise identified from each case's own datasets (Allan deviation of their
    /// stationary segments, as `diagnose` does without --noise-from) instead of the noise file.
    #[arg(long)]
    pub identified_noise: bool,
    /// Seed of the case draw (kinds, components, magnitudes, simulation seeds).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Navigation runs recorded per case (names in experiments/paper_navigation.toml).
    #[arg(long, value_delimiter = ',', default_value = "nav1,nav2")]
    pub runs: Vec<String>,
    /// Output: sealed/ (manifests and their hash index), cases/<case>/diagnosis/, report.md.
    #[arg(long, default_value = "reports/blind")]
    pub out: PathBuf,
    /// Keep each case's datasets (about 0.6 GB per 15 h run).
    #[arg(long)]
    pub keep_datasets: bool,
    /// Run only these cases of the seeded draw (e.g. `--only case07,case12`): the same hidden
    /// effects and seeds as in the whole suite, to re-examine a case; grades cover these only.
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
}

/// Run `blind`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let exp = defaults::experiments_dir();
    let cfg = SuiteConfig {
        out: args.out.clone(),
        suite_seed: args.seed,
        shape: SuiteShape {
            cases: args.cases,
            null_cases: args.null,
            out_of_catalogue: args.outside,
            time_local: args.time_local,
            time_local_runs: args.runs.clone(),
            wide_time_local: args.wide_time_local,
            different_histories: args.different_histories,
            ..SuiteShape::default()
        },
        calibration_experiment: exp.join("paper_truth_calibration.toml"),
        navigation_experiment: exp.join("paper_navigation.toml"),
        histories_experiment: exp.join("blind/navigation_varied_histories.toml"),
        navigation_runs: args.runs.clone(),
        keep_datasets: args.keep_datasets,
        only: args.only.clone(),
        diagnose: DiagnoseConfig::default(),
        identified_noise: args.identified_noise,
    };
    let mut bars = progress::Bars::new(quiet);
    let result = run_suite(&cfg, &mut bars)?;
    let path = args.out.join("report.md");
    std::fs::write(&path, &result.markdown)
        .with_context(|| format!("cannot write {}", path.display()))?;
    let g = &result.grades;
    say!(
        "top-1 {}/{}, false alarms {}/{}, out-of-catalogue unexplained {}/{}, magnitudes within 3 sigma {}/{}, median shrinkage {}",
        g.top1.0,
        g.top1.1,
        g.false_alarms.0,
        g.false_alarms.1,
        g.out_of_catalogue_unexplained.0,
        g.out_of_catalogue_unexplained.1,
        g.magnitudes_within_3_sigma.0,
        g.magnitudes_within_3_sigma.1,
        g.median_shrinkage_percent
            .map_or("-".to_string(), |v| format!("{v:.0} %"))
    )?;
    if g.confident_misattributions.1 > 0 {
        say!(
            "confident misattributions {}/{}{}",
            g.confident_misattributions.0,
            g.confident_misattributions.1,
            if g.misattributed_cases.is_empty() {
                String::new()
            } else {
                format!(" ({})", g.misattributed_cases.join(", "))
            }
        )?;
    }
    say!(
        "wrote {} (suite SHA-256 {})",
        path.display(),
        result.index.suite_sha256
    )
}
