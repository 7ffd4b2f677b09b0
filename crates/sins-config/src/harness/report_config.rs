//! The report configuration file (TOML, `schema = 1`) of `sinsbench report`: where the
//! parameter sets come from, what to replay, which two sets to compare and the replay options.
//! Paths in it are relative to the file. See `experiments/README.md` for the schema.

use super::{malformed, parse_toml, read_text};
use serde::Deserialize;
use sins_harness::HarnessError;
use sins_harness::config::{
    CalibrationSource, NavigationSource, ParamOrigin, ParamSetSpec, REPORT_SCHEMA, ReportConfig,
    parse_algorithm,
};
use sins_harness::summary::Comparison;
use sins_imu::ParamModel;
use sins_replay::setup::{ReplayOptions, StartMode};
use std::path::Path;

/// The whole file as written.
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

/// `[calibration]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CalibrationFile {
    experiment: String,
    run: Option<String>,
    #[serde(default)]
    reference_temperature_degc: f64,
}

/// One `[[parameter_set]]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ParamSetFile {
    key: String,
    label: Option<String>,
    calibrate: Option<u32>,
    file: Option<String>,
    calibration_run: Option<String>,
}

/// `[navigation]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NavigationFile {
    experiment: Option<String>,
    #[serde(default)]
    dataset: Vec<DatasetFile>,
}

/// One `[[navigation.dataset]]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DatasetFile {
    name: String,
    path: String,
}

/// `[comparison]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ComparisonFile {
    baseline: String,
    compensated: String,
    paper_table5: Option<String>,
    reason: Option<String>,
    #[serde(default)]
    variant_baselines: Vec<String>,
}

/// `[replay]`.
#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ReplayFile {
    algorithm: Option<String>,
    alignment_s: Option<f64>,
}

/// Read and validate a report configuration; errors name the file and the key (for TOML syntax
/// errors also the line).
pub fn load_report_config(path: &Path) -> Result<ReportConfig, HarnessError> {
    let text = read_text(path)?;
    let f: File = parse_toml(path, &text)?;
    build(f, path).map_err(|m| malformed(path, m))
}

/// The validated configuration of file `f` read from `path`; the error names the key.
fn build(f: File, path: &Path) -> Result<ReportConfig, String> {
    check_header(&f)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let parameter_sets = parameter_sets(&f, dir)?;
    let navigation = navigation(&f.navigation, dir)?;
    let comparison = comparison(f.comparison.as_ref(), &parameter_sets)?;
    let replay = replay_options(&f.replay)?;
    Ok(ReportConfig {
        name: f.name,
        description: f.description,
        source_path: path.to_owned(),
        calibration: f.calibration.map(|c| CalibrationSource {
            experiment: dir.join(&c.experiment),
            run: c.run,
            reference_temperature_degc: c.reference_temperature_degc,
        }),
        parameter_sets,
        navigation,
        comparison,
        paper_table5: f
            .comparison
            .as_ref()
            .and_then(|c| c.paper_table5.as_deref())
            .map(|p| dir.join(p)),
        gate: f.gate.as_deref().map(|p| dir.join(p)),
        uq: f.uq.as_deref().map(|p| dir.join(p)),
        replay,
        noise_seed: None,
    })
}

/// The layout version is this build's and the name is a plain directory name.
fn check_header(f: &File) -> Result<(), String> {
    if f.schema != REPORT_SCHEMA {
        return Err(format!(
            "key 'schema' is {}, this build reads {REPORT_SCHEMA}",
            f.schema
        ));
    }
    if f.name.is_empty() || f.name.contains(['/', '\\']) || f.name.starts_with('.') {
        return Err(format!(
            "key 'name' = '{}' must be a plain directory name",
            f.name
        ));
    }
    Ok(())
}

/// The `[[parameter_set]]` entries in order: keys unique, at least one, each with one origin.
fn parameter_sets(f: &File, dir: &Path) -> Result<Vec<ParamSetSpec>, String> {
    let mut sets: Vec<ParamSetSpec> = Vec::new();
    for (i, s) in f.parameter_set.iter().enumerate() {
        let at = format!("parameter_set[{i}] (key '{}')", s.key);
        if sets.iter().any(|x| x.key == s.key) {
            return Err(format!("{at}: key '{}' is used twice", s.key));
        }
        let origin = param_origin(s, &at, dir)?;
        if matches!(origin, ParamOrigin::Calibrate(_)) && f.calibration.is_none() {
            return Err(format!(
                "{at}: 'calibrate' needs a [calibration] section naming the calibration experiment"
            ));
        }
        if s.calibration_run.is_some() && !matches!(origin, ParamOrigin::Calibrate(_)) {
            return Err(format!(
                "{at}: 'calibration_run' applies to a set with 'calibrate = 30|42' only"
            ));
        }
        sets.push(ParamSetSpec {
            key: s.key.clone(),
            label: s.label.clone().unwrap_or_else(|| s.key.clone()),
            origin,
            calibration_run: s.calibration_run.clone(),
        });
    }
    if sets.is_empty() {
        return Err("no [[parameter_set]]: give at least one".into());
    }
    Ok(sets)
}

/// Where one parameter set comes from (`at` names the entry in messages).
fn param_origin(s: &ParamSetFile, at: &str, dir: &Path) -> Result<ParamOrigin, String> {
    match (s.calibrate, &s.file) {
        (Some(30), None) => Ok(ParamOrigin::Calibrate(ParamModel::States30)),
        (Some(42), None) => Ok(ParamOrigin::Calibrate(ParamModel::States42)),
        (Some(n), None) => Err(format!("{at}: 'calibrate' must be 30 or 42, got {n}")),
        (None, Some(p)) => Ok(ParamOrigin::File(dir.join(p))),
        _ => Err(format!(
            "{at}: give exactly one of 'calibrate = 30|42' and 'file = \"...\"'"
        )),
    }
}

/// What `[navigation]` replays: one experiment or a list of datasets.
fn navigation(n: &NavigationFile, dir: &Path) -> Result<NavigationSource, String> {
    match (&n.experiment, n.dataset.is_empty()) {
        (Some(e), true) => Ok(NavigationSource::Experiment(dir.join(e))),
        (None, false) => {
            for (i, d) in n.dataset.iter().enumerate() {
                crate::names::run_name(&d.name)
                    .map_err(|e| format!("navigation.dataset[{i}].name: {e}"))?;
            }
            Ok(NavigationSource::Datasets(
                n.dataset
                    .iter()
                    .map(|d| (d.name.clone(), dir.join(&d.path)))
                    .collect(),
            ))
        }
        _ => Err(
            "[navigation]: give exactly one of 'experiment = \"...\"' and [[navigation.dataset]] entries"
                .into(),
        ),
    }
}

/// The compared pair, whose keys must name parameter sets.
fn comparison(
    c: Option<&ComparisonFile>,
    sets: &[ParamSetSpec],
) -> Result<Option<Comparison>, String> {
    let Some(c) = c else {
        return Ok(None);
    };
    let named = [("baseline", &c.baseline), ("compensated", &c.compensated)];
    let variants = c.variant_baselines.iter().map(|v| ("variant_baselines", v));
    for (k, v) in named.into_iter().chain(variants) {
        if !sets.iter().any(|s| &s.key == v) {
            return Err(format!(
                "comparison.{k}: '{v}' is not the key of any [[parameter_set]]"
            ));
        }
    }
    if let Some(v) = c
        .variant_baselines
        .iter()
        .find(|v| **v == c.baseline || **v == c.compensated)
    {
        return Err(format!(
            "comparison.variant_baselines: '{v}' is already the baseline or the compensated set"
        ));
    }
    Ok(Some(Comparison {
        baseline: c.baseline.clone(),
        compensated: c.compensated.clone(),
        reason: c.reason.clone(),
        variant_baselines: c.variant_baselines.clone(),
    }))
}

/// The replay options: the defaults with `[replay]`'s algorithm and alignment time (s).
fn replay_options(r: &ReplayFile) -> Result<ReplayOptions, String> {
    let mut replay = ReplayOptions::default();
    if let Some(a) = &r.algorithm {
        replay.coning = parse_algorithm(a).ok_or_else(|| {
            format!(
                "replay.algorithm = '{a}' is not one of reconstruct, one-plus-previous, two-sample, three-sample, four-sample"
            )
        })?;
    }
    if let Some(s) = r.alignment_s {
        if !(s.is_finite() && s > 0.0) {
            return Err(format!("replay.alignment_s = {s} must be > 0"));
        }
        replay.start = StartMode::Align(sins_nav::AlignmentConfig {
            duration_s: s,
            ..sins_nav::AlignmentConfig::default()
        });
    }
    Ok(replay)
}
