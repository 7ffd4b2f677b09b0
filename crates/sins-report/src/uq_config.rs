//! The replica's assumptions file (`experiments/replica/assumptions.toml`, paper and human units)
//! → [`sins_uq::assumptions::AssumptionSet`] in SI, the base replica it perturbs, and the paper's
//! Table 5 and Table 2. Every error names the file and the key.

use crate::ReportError;
use serde::Deserialize;
use sins_config::{coefficient_table, load_experiment, load_report_config, load_table5};
use sins_harness::config::NavigationSource;
use sins_imu::{EffectKind, ImuErrorParams, ParamModel};
use sins_uq::apply::ReplicaBase;
use sins_uq::assumptions::{
    Assumption, AssumptionSet, Candidate, CandidateEffect, Distribution, Knob,
};
use sins_uq::summary::{CellId, PaperCell, PaperData, Table2Group, all_cells};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Schema version of the assumptions file.
pub const ASSUMPTIONS_SCHEMA: u32 = 1;

/// A loaded assumptions file with everything it references.
#[derive(Clone, Debug)]
pub struct UqStudy {
    /// Study name (the output directory's default name).
    pub name: String,
    /// The assumptions and candidates (SI).
    pub set: AssumptionSet,
    /// The replica the assumptions perturb.
    pub base: ReplicaBase,
    /// The paper's Table 5 and Table 2.
    pub paper: PaperData,
    /// The file.
    pub source_path: PathBuf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    schema: u32,
    name: String,
    #[serde(default)]
    description: String,
    replica: String,
    samples: usize,
    #[serde(default)]
    pick_freeze_samples: usize,
    seed: u64,
    choose_on: Vec<String>,
    paper_table5: String,
    paper_table2: String,
    assumption: Vec<AssumptionFile>,
    #[serde(default)]
    candidate: Vec<CandidateFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DistFile {
    fixed: Option<f64>,
    uniform: Option<[f64; 2]>,
    log_uniform: Option<[f64; 2]>,
    normal: Option<NormalFile>,
    choice: Option<ChoiceFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NormalFile {
    mean: f64,
    sd: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ChoiceFile {
    labels: Vec<String>,
    weights: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AssumptionFile {
    name: String,
    knob: String,
    group: String,
    #[serde(default)]
    unit: String,
    justification: String,
    #[serde(flatten)]
    dist: DistFile,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CandidateFile {
    name: String,
    justification: String,
    samples: usize,
    #[serde(default)]
    set: BTreeMap<String, toml::Value>,
    #[serde(default)]
    effect: Vec<EffectFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EffectFile {
    kind: String,
    #[serde(default)]
    random_sign: bool,
    #[serde(flatten)]
    dist: DistFile,
}

fn invalid(path: &Path, key: &str, msg: impl std::fmt::Display) -> ReportError {
    ReportError::Mismatch(format!("{}: {key}: {msg}", path.display()))
}

/// The SI value of one unit of `label`.
pub fn unit_si(label: &str) -> Option<f64> {
    use sins_nav::{ARCSEC, DEG, DEG_PER_H, UG};
    Some(match label {
        "" | "1" | "degC" | "s" => 1.0,
        "h" => 3600.0,
        "deg" => DEG,
        "deg/h" => DEG_PER_H,
        "deg/sqrt(h)" => DEG / 60.0,
        "arcsec" => ARCSEC,
        "ug" | "ug/sqrt(Hz)" | "ug/degC" => UG,
        "ppm" | "ppm/degC" => 1e-6,
        "arcsec/degC" => ARCSEC,
        "deg/h/degC" => DEG_PER_H,
        _ => return None,
    })
}

fn knob_of(name: &str) -> Option<Knob> {
    if let Some(coef) = name.strip_prefix("truth:") {
        let table = coefficient_table(&ImuErrorParams::ideal(ParamModel::States42));
        return table
            .iter()
            .position(|c| c.name == coef)
            .map(Knob::TruthCoefficient);
    }
    Some(match name {
        "cal30_chamber" => Knob::Cal30Chamber,
        "cal30_stable_temperature" => Knob::Cal30StableTemperatureDegc,
        "accel_time_constant_scale" => Knob::AccelTimeConstantScale,
        "accel_offset_scale" => Knob::AccelOffsetScale,
        "nav_temperature_drop" => Knob::NavTemperatureDropDegc,
        "nav_fluctuation_amplitude_scale" => Knob::NavFluctuationAmplitudeScale,
        "nav_fluctuation_period_scale" => Knob::NavFluctuationPeriodScale,
        "nav_temperature_shift" => Knob::NavTemperatureShiftDegc,
        "nav_mounting" => Knob::NavMounting,
        "nav_yaw_offset" => Knob::NavYawOffsetRad,
        "vibration_phase" => Knob::VibrationPhaseRad,
        "gyro_arw" => Knob::GyroArw,
        "gyro_bias_instability" => Knob::GyroBiasInstability,
        "gyro_quantum" => Knob::GyroQuantum,
        "accel_vrw" => Knob::AccelVrw,
        "accel_bias_instability" => Knob::AccelBiasInstability,
        "bias_correlation" => Knob::BiasCorrelationS,
        "thermometer_noise" => Knob::ThermometerNoiseDegc,
        _ => return None,
    })
}

fn distribution(
    path: &Path,
    key: &str,
    d: &DistFile,
    si: f64,
) -> Result<Distribution, ReportError> {
    let mut given: Vec<Distribution> = Vec::new();
    if let Some(v) = d.fixed {
        given.push(Distribution::Fixed(v * si));
    }
    if let Some([lo, hi]) = d.uniform {
        given.push(Distribution::Uniform {
            low: lo * si,
            high: hi * si,
        });
    }
    if let Some([lo, hi]) = d.log_uniform {
        given.push(Distribution::LogUniform {
            low: lo * si,
            high: hi * si,
        });
    }
    if let Some(n) = &d.normal {
        given.push(Distribution::Normal {
            mean: n.mean * si,
            sd: n.sd * si,
        });
    }
    if let Some(c) = &d.choice {
        given.push(Distribution::Choice {
            labels: c.labels.clone(),
            weights: c.weights.clone(),
        });
    }
    let [dist] = <[Distribution; 1]>::try_from(given).map_err(|_| {
        invalid(
            path,
            key,
            "give exactly one of fixed, uniform, log_uniform, normal, choice",
        )
    })?;
    dist.validate(key).map_err(|e| invalid(path, key, e))?;
    Ok(dist)
}

/// Reads an assumptions file, the replica configuration it names and the paper's tables (all
/// relative to the file).
pub fn load_uq_study(path: &Path) -> Result<UqStudy, ReportError> {
    let text = std::fs::read_to_string(path).map_err(|e| ReportError::io(path, e))?;
    let raw: File = toml::from_str(&text).map_err(|e| invalid(path, "toml", e))?;
    if raw.schema != ASSUMPTIONS_SCHEMA {
        return Err(invalid(
            path,
            "schema",
            format!(
                "{} unsupported (this build reads {ASSUMPTIONS_SCHEMA})",
                raw.schema
            ),
        ));
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let assumptions = raw
        .assumption
        .iter()
        .enumerate()
        .map(|(i, a)| assumption(path, i, a))
        .collect::<Result<Vec<_>, _>>()?;
    let mut set = AssumptionSet {
        assumptions,
        candidates: Vec::new(),
        samples: raw.samples,
        pick_freeze_samples: raw.pick_freeze_samples,
        seed: raw.seed,
        choose_on: Vec::new(),
    };
    for (i, c) in raw.candidate.iter().enumerate() {
        let cand = candidate(path, i, c, &set)?;
        set.candidates.push(cand);
    }
    set.choose_on = raw
        .choose_on
        .iter()
        .map(|c| {
            CellId::parse(c).ok_or_else(|| {
                invalid(
                    path,
                    "choose_on",
                    format!("'{c}' is not a cell like 'exp1 without'"),
                )
            })
        })
        .collect::<Result<_, _>>()?;
    set.validate()
        .map_err(|e| invalid(path, "assumptions", e))?;
    let base = load_base(&dir.join(&raw.replica))?;
    let table5 = load_table5(&dir.join(&raw.paper_table5))?;
    let paper = PaperData {
        cells: paper_cells(&table5, base.navigation.len()),
        table2: load_table2(&dir.join(&raw.paper_table2))?,
    };
    if let Some(bad) = set
        .choose_on
        .iter()
        .find(|c| c.experiment > base.navigation.len())
    {
        return Err(invalid(
            path,
            "choose_on",
            format!(
                "{} is beyond the replica's {} runs",
                bad.label(),
                base.navigation.len()
            ),
        ));
    }
    let _ = raw.description;
    Ok(UqStudy {
        name: raw.name,
        set,
        base,
        paper,
        source_path: path.to_owned(),
    })
}

fn assumption(path: &Path, i: usize, a: &AssumptionFile) -> Result<Assumption, ReportError> {
    let key = format!("assumption[{i}] ({})", a.name);
    let knob = knob_of(&a.knob)
        .ok_or_else(|| invalid(path, &key, format!("unknown knob '{}'", a.knob)))?;
    let si = unit_si(&a.unit)
        .ok_or_else(|| invalid(path, &key, format!("unknown unit '{}'", a.unit)))?;
    if a.justification.trim().is_empty() {
        return Err(invalid(path, &key, "needs a justification"));
    }
    Ok(Assumption {
        name: a.name.clone(),
        knob,
        distribution: distribution(path, &key, &a.dist, si)?,
        group: a.group.clone(),
        unit: a.unit.clone(),
        unit_si: si,
        justification: a.justification.clone(),
    })
}

fn candidate(
    path: &Path,
    i: usize,
    c: &CandidateFile,
    set: &AssumptionSet,
) -> Result<Candidate, ReportError> {
    let key = format!("candidate[{i}] ({})", c.name);
    let mut overrides = Vec::new();
    for (name, v) in &c.set {
        let idx = set
            .index_of(name)
            .ok_or_else(|| invalid(path, &key, format!("sets unknown assumption '{name}'")))?;
        let a = &set.assumptions[idx];
        let d = match (v, a.distribution.labels()) {
            (toml::Value::String(s), Some(labels)) => labels
                .iter()
                .position(|l| l == s)
                .map(|p| Distribution::Fixed(p as f64))
                .ok_or_else(|| {
                    invalid(
                        path,
                        &key,
                        format!("{name} = '{s}' is not one of {labels:?}"),
                    )
                })?,
            (toml::Value::Float(f), None) => Distribution::Fixed(f * a.unit_si),
            (toml::Value::Integer(n), None) => Distribution::Fixed(*n as f64 * a.unit_si),
            _ => {
                return Err(invalid(
                    path,
                    &key,
                    format!("{name}: a label for a choice, a number otherwise"),
                ));
            }
        };
        overrides.push((idx, d));
    }
    let effects = c
        .effect
        .iter()
        .map(|e| {
            let kind = EffectKind::from_name(&e.kind)
                .ok_or_else(|| invalid(path, &key, format!("unknown effect kind '{}'", e.kind)))?;
            Ok(CandidateEffect {
                kind,
                magnitude: distribution(
                    path,
                    &format!("{key}.effect {}", e.kind),
                    &e.dist,
                    kind.unit().si,
                )?,
                random_sign: e.random_sign,
            })
        })
        .collect::<Result<Vec<_>, ReportError>>()?;
    if c.justification.trim().is_empty() {
        return Err(invalid(path, &key, "needs a justification"));
    }
    Ok(Candidate {
        name: c.name.clone(),
        justification: c.justification.clone(),
        overrides,
        effects,
        samples: c.samples,
    })
}

/// The replica a report configuration defines: its calibration run and navigation experiment
/// (simulated navigation only).
pub fn load_base(config_path: &Path) -> Result<ReplicaBase, ReportError> {
    let config = load_report_config(config_path)?;
    let cal = config.calibration.as_ref().ok_or_else(|| {
        invalid(
            config_path,
            "calibration",
            "the replica must calibrate from a simulated run",
        )
    })?;
    let exp = load_experiment(&cal.experiment)?;
    let calibration = match &cal.run {
        Some(r) => exp.scenarios.iter().find(|s| &s.name == r).cloned(),
        None => exp.scenarios.first().cloned(),
    }
    .ok_or_else(|| {
        invalid(
            config_path,
            "calibration.run",
            "no such run in the experiment",
        )
    })?;
    let navigation = match &config.navigation {
        NavigationSource::Experiment(p) => load_experiment(p)?.scenarios,
        NavigationSource::Datasets(_) => {
            return Err(invalid(
                config_path,
                "navigation",
                "the replica must simulate its navigation runs",
            ));
        }
    };
    Ok(ReplicaBase {
        calibration,
        navigation,
        reference_temperature_degc: cal.reference_temperature_degc,
        replay: config.replay,
    })
}

/// Table 5 as cells (without, with, improvement per experiment), each with the STD of its
/// column over the paper's experiments as the paper's own scatter.
pub fn paper_cells(rows: &[sins_harness::reference::PaperRow], runs: usize) -> Vec<PaperCell> {
    let sd = |f: &dyn Fn(&sins_harness::reference::PaperRow) -> f64| {
        let v: Vec<f64> = rows.iter().map(f).collect();
        sins_uq::stats::mean_sd(&v).1
    };
    let scatter = [
        sd(&|r| r.without_compensation_nmi),
        sd(&|r| r.with_compensation_nmi),
        sd(&|r| r.improvement_percent),
    ];
    all_cells(runs)
        .iter()
        .filter_map(|id| {
            let r = rows
                .iter()
                .find(|r| r.experiment as usize == id.experiment)?;
            let (value, s) = match id.kind {
                sins_uq::summary::CellKind::Without => (r.without_compensation_nmi, scatter[0]),
                sins_uq::summary::CellKind::With => (r.with_compensation_nmi, scatter[1]),
                sins_uq::summary::CellKind::Improvement => (r.improvement_percent, scatter[2]),
            };
            Some(PaperCell { value, scatter: s })
        })
        .collect()
}

/// Table 2 (`group,unit,std` with the STDs separated by `/`, in the state order of eq 8 within
/// the group); the group keys are those of [`table2_indices`].
pub fn load_table2(path: &Path) -> Result<Vec<Table2Group>, ReportError> {
    let text = std::fs::read_to_string(path).map_err(|e| ReportError::io(path, e))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let key = format!("line {}", i + 1);
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let [group, unit, values] = f[..] else {
            return Err(invalid(path, &key, "expected group,unit,std1/std2/..."));
        };
        let indices = table2_indices(group)
            .ok_or_else(|| invalid(path, &key, format!("unknown group '{group}'")))?;
        let unit_si =
            unit_si(unit).ok_or_else(|| invalid(path, &key, format!("unknown unit '{unit}'")))?;
        let paper_std = values
            .split('/')
            .map(|v| {
                v.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite() && *x >= 0.0)
            })
            .collect::<Option<Vec<f64>>>()
            .filter(|v| v.len() == indices.len())
            .ok_or_else(|| {
                invalid(
                    path,
                    &key,
                    format!(
                        "needs {} non-negative numbers separated by '/'",
                        indices.len()
                    ),
                )
            })?;
        out.push(Table2Group {
            name: group.to_string(),
            unit: unit.to_string(),
            unit_si,
            indices: indices.to_vec(),
            paper_std,
        });
    }
    Ok(out)
}

/// Coefficient indices (state order of eq 8) of each Table 2 group.
pub fn table2_indices(group: &str) -> Option<&'static [usize]> {
    Some(match group {
        "gyro_drift" => &[0, 1, 2],
        "accel_bias" => &[3, 4, 5],
        "gyro_scale" => &[6, 9, 11],
        "gyro_installation" => &[7, 8, 10],
        "accel_scale" => &[12, 16, 20],
        "accel_installation" => &[13, 14, 15, 17, 18, 19],
        "temp_bias" => &[21, 22, 23],
        "temp_scale" => &[24, 25, 26],
        "temp_installation" => &[27, 28, 29, 30, 31, 32],
        _ => return None,
    })
}
