//! The report configuration as data: where the parameter sets come from (calibrated from a
//! simulated calibration run, or files), what to replay (a simulated navigation experiment, or
//! the user's datasets), which two sets to compare, and the replay options. The TOML file is
//! read and validated by `sins_config::load_report_config` (paths there are relative to the
//! configuration file). See `experiments/README.md` for the schema and
//! `experiments/harness/report_paper.toml` for the built-in replica of the paper.

use crate::summary::Comparison;
use sins_imu::ParamModel;
use sins_nav::ConingOrder;
use sins_replay::setup::ReplayOptions;
use std::path::PathBuf;

/// Version of the report configuration layout.
pub const REPORT_SCHEMA: u32 = 1;

/// Where a parameter set comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamOrigin {
    /// Calibrated by this report from the `[calibration]` run with a 30- or 42-state filter.
    Calibrate(ParamModel),
    /// Read from a parameter file (TOML or JSON, paper units).
    File(PathBuf),
}

/// One parameter set to replay with.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSetSpec {
    /// Short key (summaries, thresholds).
    pub key: String,
    /// Human label.
    pub label: String,
    /// Its origin.
    pub origin: ParamOrigin,
    /// For a `Calibrate` set: the run of the `[calibration]` experiment it is calibrated on
    /// (`None`: the section's run), e.g. a stable-temperature run beside the ramp.
    pub calibration_run: Option<String>,
}

/// The simulated calibration run that `Calibrate` sets come from.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationSource {
    /// Calibration experiment file.
    pub experiment: PathBuf,
    /// Run name (default: the first run).
    pub run: Option<String>,
    /// Reference temperature of the temperature terms (degC).
    pub reference_temperature_degc: f64,
}

/// What is replayed.
#[derive(Clone, Debug, PartialEq)]
pub enum NavigationSource {
    /// Simulate every run of this navigation experiment.
    Experiment(PathBuf),
    /// Replay these datasets (name, path).
    Datasets(Vec<(String, PathBuf)>),
}

/// A loaded, validated report configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportConfig {
    /// Report name (the output directory is `reports/<name>/`).
    pub name: String,
    /// Description.
    pub description: String,
    /// The file it was read from.
    pub source_path: PathBuf,
    /// The calibration run, if any set is calibrated here.
    pub calibration: Option<CalibrationSource>,
    /// Parameter sets in order.
    pub parameter_sets: Vec<ParamSetSpec>,
    /// What to replay.
    pub navigation: NavigationSource,
    /// The compared pair.
    pub comparison: Option<Comparison>,
    /// The paper's Table 5, to print beside ours.
    pub paper_table5: Option<PathBuf>,
    /// Release-gate thresholds applied after the report, if given.
    pub gate: Option<PathBuf>,
    /// A `sinsbench replica-uq` output directory whose intervals and V&V verdicts the report
    /// shows beside the point replica (`report --uq DIR` overrides it).
    pub uq: Option<PathBuf>,
    /// Replay options.
    pub replay: ReplayOptions,
    /// A sensor-noise seed that replaces the seed of every simulated run (calibration and
    /// navigation) by [`reseed`] of its own: the same configuration over other noise draws, for
    /// a release gate that knows the run-to-run spread (the `reports` campaign's
    /// `noise_seeds`). `None`: the experiment files' seeds.
    pub noise_seed: Option<u64>,
}

/// The seed of a simulated run under noise seed `noise_seed` (SplitMix64 of the run's own seed
/// and the noise seed): every run keeps its own stream, and each noise seed gives another draw
/// of all of them.
pub fn reseed(run_seed: u64, noise_seed: u64) -> u64 {
    splitmix64(run_seed ^ splitmix64(noise_seed))
}

/// SplitMix64's output for state `z` (Steele, Lea & Flood 2014): the state advanced by the
/// golden gamma, then mixed. A generator returns `splitmix64(s)` and advances `s` by the gamma.
pub fn splitmix64(z: u64) -> u64 {
    let mut z = z.wrapping_add(SPLITMIX_GAMMA);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// SplitMix64's increment (2^64 / φ).
pub const SPLITMIX_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// The coning algorithm named as on the command line (`reconstruct`, `one-plus-previous`,
/// `two-sample`, `three-sample`, `four-sample`).
pub fn parse_algorithm(name: &str) -> Option<ConingOrder> {
    Some(match name {
        "reconstruct" => ConingOrder::Reconstruct,
        "one-plus-previous" => ConingOrder::OnePlusPrevious,
        "two-sample" => ConingOrder::TwoSample,
        "three-sample" => ConingOrder::ThreeSample,
        "four-sample" => ConingOrder::FourSample,
        _ => return None,
    })
}
