//! Experiment files (TOML, human units) → one [`Scenario`] per `[[run]]`.

use crate::ctx::Ctx;
use crate::error::ConfigError;
use crate::motion::{MotionFile, build_motion};
use crate::params::{ParamFormat, parse_params_json, parse_params_toml};
use crate::plausible;
use crate::thermal::{ThermalFile, build_thermal};
use crate::toml_util;
use crate::units::{DEG_PER_SQRT_H, UG_PER_SQRT_HZ};
use serde::Deserialize;
use sins_nav::{ARCSEC, DEG_PER_H, Geodetic, UG};
use sins_sim::noise::gauss_markov_sigma_from_allan;
use sins_sim::scenario::{NoiseModel, Scenario};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The schema version this build reads (`schema = 1`).
pub const EXPERIMENT_SCHEMA: u32 = 1;

/// A loaded experiment: its runs as ready-to-simulate scenarios.
#[derive(Clone, Debug, PartialEq)]
pub struct Experiment {
    /// Experiment name (`name`).
    pub name: String,
    /// Free description (`description`, empty when absent).
    pub description: String,
    /// What the experiment is for (`kind`, e.g. "calibration", "navigation"), if given.
    pub kind: Option<String>,
    /// One scenario per `[[run]]`, in file order; each scenario is named after its run.
    pub scenarios: Vec<Scenario>,
    /// The file the experiment was read from.
    pub source_path: PathBuf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ExperimentFile {
    schema: u32,
    name: String,
    #[serde(default)]
    description: String,
    kind: Option<String>,
    site: SiteFile,
    sampling: SamplingFile,
    imu: ImuFile,
    thermal: Option<ThermalFile>,
    motion: MotionFile,
    run: Vec<RunFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SiteFile {
    latitude_deg: f64,
    longitude_deg: f64,
    #[serde(default)]
    height_m: f64,
}

fn default_nodes() -> usize {
    6
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SamplingFile {
    rate_hz: f64,
    #[serde(default = "default_nodes")]
    quadrature_nodes: usize,
    #[serde(default)]
    with_reference: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ImuFile {
    truth: String,
    #[serde(default)]
    noise: NoiseFile,
    #[serde(default)]
    effect: Vec<crate::effects::EffectFile>,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub(crate) struct NoiseFile {
    gyro_arw_deg_per_sqrt_h: f64,
    gyro_bias_instability_deg_per_h: f64,
    /// Left out: a random constant (an infinite correlation time).
    #[serde(default = "random_constant")]
    gyro_bias_correlation_s: f64,
    gyro_quantum_arcsec: f64,
    accel_vrw_ug_per_sqrt_hz: f64,
    accel_bias_instability_ug: f64,
    /// Left out: a random constant (an infinite correlation time).
    #[serde(default = "random_constant")]
    accel_bias_correlation_s: f64,
}

/// The correlation time of a bias whose key is left out: a random constant.
fn random_constant() -> f64 {
    f64::INFINITY
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RunFile {
    name: String,
    seed: u64,
    description: Option<String>,
    thermal: Option<ThermalFile>,
}

/// Refuses an experiment or noise file of another schema version than this build reads.
pub(crate) fn check_schema(ctx: &Ctx<'_>, schema: u32) -> Result<(), ConfigError> {
    if schema == EXPERIMENT_SCHEMA {
        return Ok(());
    }
    let msg = format!("unsupported schema version {schema} (this build reads {EXPERIMENT_SCHEMA})");
    Err(ctx.invalid("schema", msg))
}

/// Reads an experiment file and everything it references (truth parameters, scheme and pattern
/// tables, all relative to the file), validates it and returns one scenario per run.
pub fn load_experiment(path: impl AsRef<Path>) -> Result<Experiment, ConfigError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Io {
        path: path.to_owned(),
        source,
    })?;
    let ctx = Ctx::new(path, &text);
    let raw: ExperimentFile = toml_util::from_str(&text, &ctx.origin)?;
    check_schema(&ctx, raw.schema)?;
    check_name(&ctx, "name", &raw.name)?;
    if let Some(kind) = &raw.kind
        && kind.trim().is_empty()
    {
        return Err(ctx.invalid("kind", "must not be empty (or leave it out)"));
    }
    let site = build_site(&ctx, &raw.site)?;
    let s = &raw.sampling;
    let rate_hz = ctx.positive("sampling.rate_hz", s.rate_hz)?;
    if rate_hz > plausible::MAX_SAMPLE_RATE_HZ {
        let msg = format!(
            "{rate_hz} Hz is above the {} Hz maximum (navigation-grade IMUs deliver 100 Hz to 2 kHz)",
            plausible::MAX_SAMPLE_RATE_HZ
        );
        return Err(ctx.invalid("sampling.rate_hz", msg));
    }
    if !(1..=8).contains(&s.quadrature_nodes) {
        let msg = format!(
            "must be 1..=8 Gauss-Legendre nodes, got {}",
            s.quadrature_nodes
        );
        return Err(ctx.invalid("sampling.quadrature_nodes", msg));
    }
    let truth = load_truth(&ctx, &raw.imu.truth)?;
    let noise = build_noise(&ctx, &raw.imu.noise)?;
    let effects = crate::effects::build_effects(&ctx, &text, &raw.imu.effect)?;
    let motion = build_motion(&ctx, &raw.motion)?;
    let thermal = match &raw.thermal {
        Some(t) => Some(build_thermal(&ctx, "thermal", t)?),
        None => None,
    };
    if raw.run.is_empty() {
        return Err(ctx.missing("run", "an experiment needs at least one [[run]]"));
    }
    let mut names = BTreeSet::new();
    let mut scenarios = Vec::with_capacity(raw.run.len());
    for (i, run) in raw.run.iter().enumerate() {
        let p = format!("run[{i}]");
        crate::names::run_name(&run.name)
            .map_err(|e| ctx.invalid(&format!("{p}.name"), e.to_string()))?;
        if !names.insert(run.name.clone()) {
            return Err(ctx.invalid(
                &format!("{p}.name"),
                format!("duplicate run name \"{}\"", run.name),
            ));
        }
        let thermal = match (&run.thermal, &thermal) {
            (Some(t), _) => build_thermal(&ctx, &format!("{p}.thermal"), t)?,
            (None, Some(t)) => t.clone(),
            (None, None) => {
                return Err(ctx.missing(
                    &format!("{p}.thermal"),
                    "no [thermal] table at the top level nor in this run",
                ));
            }
        };
        scenarios.push(Scenario {
            name: run.name.clone(),
            description: run
                .description
                .clone()
                .unwrap_or_else(|| raw.description.clone()),
            site,
            rate_hz,
            quadrature_nodes: s.quadrature_nodes,
            motion: motion.clone(),
            thermal,
            noise,
            truth,
            effects: effects.clone(),
            seed: run.seed,
            with_reference: s.with_reference,
        });
    }
    Ok(Experiment {
        name: raw.name,
        description: raw.description,
        kind: raw.kind,
        scenarios,
        source_path: path.to_owned(),
    })
}

/// Names become file names: non-empty, ASCII letters, digits, `_`, `-`, `.` only.
fn check_name(ctx: &Ctx<'_>, key: &str, name: &str) -> Result<(), ConfigError> {
    let ok = !name.is_empty()
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c));
    if ok {
        Ok(())
    } else {
        let msg = format!("\"{name}\" is not a usable name (ASCII letters, digits, '_', '-', '.')");
        Err(ctx.invalid(key, msg))
    }
}

fn build_site(ctx: &Ctx<'_>, s: &SiteFile) -> Result<Geodetic, ConfigError> {
    let lat = ctx.finite("site.latitude_deg", s.latitude_deg)?;
    if lat.abs() > 89.0 {
        return Err(ctx.invalid(
            "site.latitude_deg",
            format!("must be within ±89 deg, got {lat}"),
        ));
    }
    let lon = ctx.finite("site.longitude_deg", s.longitude_deg)?;
    if !(-180.0..=360.0).contains(&lon) {
        return Err(ctx.invalid(
            "site.longitude_deg",
            format!("must be within -180..360 deg, got {lon}"),
        ));
    }
    let h = ctx.finite("site.height_m", s.height_m)?;
    if !plausible::height_ok(h) {
        let msg = format!("{h} m is {}", plausible::height_range_text());
        return Err(ctx.invalid("site.height_m", msg));
    }
    Ok(Geodetic::from_deg(lat, lon, h))
}

fn load_truth(ctx: &Ctx<'_>, rel: &str) -> Result<sins_imu::ImuErrorParams, ConfigError> {
    let key = "imu.truth";
    let format = ParamFormat::from_path(Path::new(rel)).map_err(|e| ctx.referenced(key, e))?;
    let (path, text) = ctx.read_referenced(key, rel)?;
    let origin = path.display().to_string();
    let set = match format {
        ParamFormat::Toml => parse_params_toml(&text, &origin),
        ParamFormat::Json => parse_params_json(&text, &origin),
    };
    set.map(|s| s.params).map_err(|e| ctx.referenced(key, e))
}

pub(crate) fn build_noise(ctx: &Ctx<'_>, n: &NoiseFile) -> Result<NoiseModel, ConfigError> {
    let k = |name: &str| format!("imu.noise.{name}");
    let correlation = |name: &str, v: f64, instability: f64| -> Result<f64, ConfigError> {
        // +inf is allowed (random constant); a positive instability needs a positive time.
        if v.is_nan() || v < 0.0 || (instability > 0.0 && v == 0.0) {
            let msg = format!(
                "must be positive (or inf for a random constant) when the bias instability is set, got {v}"
            );
            return Err(ctx.invalid(&k(name), msg));
        }
        Ok(v)
    };
    check_noise_limits(ctx, n)?;
    let gyro_bi = ctx.non_negative(
        &k("gyro_bias_instability_deg_per_h"),
        n.gyro_bias_instability_deg_per_h,
    )?;
    let accel_bi =
        ctx.non_negative(&k("accel_bias_instability_ug"), n.accel_bias_instability_ug)?;
    Ok(NoiseModel {
        gyro_arw_rad_per_sqrt_s: ctx
            .non_negative(&k("gyro_arw_deg_per_sqrt_h"), n.gyro_arw_deg_per_sqrt_h)?
            * DEG_PER_SQRT_H,
        gyro_bias_instability_radps: gauss_markov_sigma_from_allan(gyro_bi * DEG_PER_H),
        gyro_bias_correlation_s: correlation(
            "gyro_bias_correlation_s",
            n.gyro_bias_correlation_s,
            gyro_bi,
        )?,
        gyro_quantum_rad: ctx.non_negative(&k("gyro_quantum_arcsec"), n.gyro_quantum_arcsec)?
            * ARCSEC,
        accel_vrw_mps_per_sqrt_s: ctx
            .non_negative(&k("accel_vrw_ug_per_sqrt_hz"), n.accel_vrw_ug_per_sqrt_hz)?
            * UG_PER_SQRT_HZ,
        accel_bias_instability_mps2: gauss_markov_sigma_from_allan(accel_bi * UG),
        accel_bias_correlation_s: correlation(
            "accel_bias_correlation_s",
            n.accel_bias_correlation_s,
            accel_bi,
        )?,
    })
}

/// Refuses noise values beyond [`plausible::NOISE_LIMITS`] and
/// [`plausible::MAX_THERMOMETER_NOISE_DEGC`].
fn check_noise_limits(ctx: &Ctx<'_>, n: &NoiseFile) -> Result<(), ConfigError> {
    let values = [
        n.gyro_arw_deg_per_sqrt_h,
        n.gyro_bias_instability_deg_per_h,
        n.gyro_quantum_arcsec,
        n.accel_vrw_ug_per_sqrt_hz,
        n.accel_bias_instability_ug,
    ];
    for ((name, limit, plausible), v) in plausible::NOISE_LIMITS.iter().zip(values) {
        if v.abs() > *limit {
            let msg = format!(
                "{v} is beyond the plausibility limit {limit} (10x the largest plausible, {plausible})"
            );
            return Err(ctx.invalid(&format!("imu.noise.{name}"), msg));
        }
    }
    Ok(())
}
