//! The report configuration (TOML): where the parameter sets come from (calibrated from a
//! simulated calibration run, or files), what to replay (a simulated navigation experiment, or
//! the user's datasets), which two sets to compare, and the replay options. Paths are relative
//! to the configuration file. See `experiments/README.md` for the schema and
//! `experiments/harness/report_paper.toml` for the built-in replica of the paper.

use crate::HarnessError;
use crate::replay_setup::{ReplayOptions, StartMode};
use crate::summary::Comparison;
use serde::Deserialize;
use sins_imu::ParamModel;
use sins_nav::ConingOrder;
use std::path::{Path, PathBuf};

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
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    schema: u32,
    name: String,
    #[serde(default)]
    description: String,
    calibration: Option<CalibrationFile>,
    parameter_set: Vec<ParamSetFile>,
    navigation: NavigationFile,
    comparison: Option<ComparisonFile>,
    gate: Option<String>,
    uq: Option<String>,
    #[serde(default)]
    replay: ReplayFile,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CalibrationFile {
    experiment: String,
    run: Option<String>,
    #[serde(default)]
    reference_temperature_degc: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ParamSetFile {
    key: String,
    label: Option<String>,
    calibrate: Option<u32>,
    file: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NavigationFile {
    experiment: Option<String>,
    #[serde(default)]
    dataset: Vec<DatasetFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DatasetFile {
    name: String,
    path: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ComparisonFile {
    baseline: String,
    compensated: String,
    paper_table5: Option<String>,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ReplayFile {
    algorithm: Option<String>,
    alignment_s: Option<f64>,
}

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

/// Read and validate a report configuration.
pub fn load_report_config(path: &Path) -> Result<ReportConfig, HarnessError> {
    let text = std::fs::read_to_string(path).map_err(|source| HarnessError::Io {
        path: path.to_owned(),
        source,
    })?;
    let bad = |message: String| HarnessError::Malformed {
        path: path.to_owned(),
        message,
    };
    let f: File = toml::from_str(&text).map_err(|e| bad(e.to_string().trim().to_string()))?;
    if f.schema != REPORT_SCHEMA {
        return Err(bad(format!(
            "key 'schema' is {}, this build reads {REPORT_SCHEMA}",
            f.schema
        )));
    }
    if f.name.is_empty() || f.name.contains(['/', '\\']) || f.name.starts_with('.') {
        return Err(bad(format!(
            "key 'name' = '{}' must be a plain directory name",
            f.name
        )));
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let rel = |p: &str| dir.join(p);
    let mut sets = Vec::new();
    for (i, s) in f.parameter_set.iter().enumerate() {
        let at = format!("parameter_set[{i}] (key '{}')", s.key);
        if sets.iter().any(|x: &ParamSetSpec| x.key == s.key) {
            return Err(bad(format!("{at}: key '{}' is used twice", s.key)));
        }
        let origin = match (s.calibrate, &s.file) {
            (Some(30), None) => ParamOrigin::Calibrate(ParamModel::States30),
            (Some(42), None) => ParamOrigin::Calibrate(ParamModel::States42),
            (Some(n), None) => {
                return Err(bad(format!("{at}: 'calibrate' must be 30 or 42, got {n}")));
            }
            (None, Some(p)) => ParamOrigin::File(rel(p)),
            _ => {
                return Err(bad(format!(
                    "{at}: give exactly one of 'calibrate = 30|42' and 'file = \"...\"'"
                )));
            }
        };
        if matches!(origin, ParamOrigin::Calibrate(_)) && f.calibration.is_none() {
            return Err(bad(format!(
                "{at}: 'calibrate' needs a [calibration] section naming the calibration experiment"
            )));
        }
        sets.push(ParamSetSpec {
            key: s.key.clone(),
            label: s.label.clone().unwrap_or_else(|| s.key.clone()),
            origin,
        });
    }
    if sets.is_empty() {
        return Err(bad("no [[parameter_set]]: give at least one".into()));
    }
    let navigation = match (&f.navigation.experiment, f.navigation.dataset.is_empty()) {
        (Some(e), true) => NavigationSource::Experiment(rel(e)),
        (None, false) => NavigationSource::Datasets(
            f.navigation
                .dataset
                .iter()
                .map(|d| (d.name.clone(), rel(&d.path)))
                .collect(),
        ),
        _ => {
            return Err(bad(
                "[navigation]: give exactly one of 'experiment = \"...\"' and [[navigation.dataset]] entries"
                    .into(),
            ));
        }
    };
    let comparison = match &f.comparison {
        Some(c) => {
            for (k, v) in [("baseline", &c.baseline), ("compensated", &c.compensated)] {
                if !sets.iter().any(|s| &s.key == v) {
                    return Err(bad(format!(
                        "comparison.{k} = '{v}' is not the key of any [[parameter_set]]"
                    )));
                }
            }
            Some(Comparison {
                baseline: c.baseline.clone(),
                compensated: c.compensated.clone(),
            })
        }
        None => None,
    };
    let mut replay = ReplayOptions::default();
    if let Some(a) = &f.replay.algorithm {
        replay.coning = parse_algorithm(a).ok_or_else(|| {
            bad(format!(
                "replay.algorithm = '{a}' is not one of reconstruct, one-plus-previous, two-sample, three-sample, four-sample"
            ))
        })?;
    }
    if let Some(s) = f.replay.alignment_s {
        if !(s.is_finite() && s > 0.0) {
            return Err(bad(format!("replay.alignment_s = {s} must be > 0")));
        }
        replay.start = StartMode::Align(sins_nav::AlignmentConfig {
            duration_s: s,
            ..sins_nav::AlignmentConfig::default()
        });
    }
    Ok(ReportConfig {
        name: f.name,
        description: f.description,
        source_path: path.to_owned(),
        calibration: f.calibration.map(|c| CalibrationSource {
            experiment: rel(&c.experiment),
            run: c.run,
            reference_temperature_degc: c.reference_temperature_degc,
        }),
        parameter_sets: sets,
        navigation,
        comparison,
        paper_table5: f
            .comparison
            .as_ref()
            .and_then(|c| c.paper_table5.as_deref())
            .map(rel),
        gate: f.gate.as_deref().map(rel),
        uq: f.uq.as_deref().map(rel),
        replay,
    })
}
