//! Noise files: the `[imu.noise]` table of an experiment on its own, with its 1-sigma, as
//! `sinsbench noise` writes it and `sinsbench diagnose --noise-from` reads it.
//!
//! ```toml
//! schema = 1
//! kind = "noise"
//! description = "identified by sinsbench noise from nav1 (5.0 h stationary)"
//! [imu.noise]           # the keys and units of an experiment's [imu.noise]
//! gyro_arw_deg_per_sqrt_h = 0.00049
//! ...
//! [imu.noise_sigma]     # optional: 1-sigma of each figure, same keys and units
//! gyro_arw_deg_per_sqrt_h = 0.00002
//! [imu.unresolved_walk] # optional: the rate random walks the data could not exclude
//! gyro_deg_per_h_per_sqrt_h = 0.0031   # 95 % upper bounds; 0 where the walk was resolved
//! accel_ug_per_sqrt_h = 2.4            # a key left out: the data put no finite bound on it
//! ```
//!
//! [`load_noise`] reads either such a file or a whole experiment file (the noise of its first
//! run); a parameter set given instead is named as such ([`ConfigError::WrongKind`]). Unknown
//! keys are errors, as everywhere. Every figure written is one the reader takes back, and none
//! is infinite: a walk bound or a 1-sigma the data did not bound, and the correlation time of a
//! random-constant bias, are left out with a comment, never written as `inf`. Writing then
//! reading reproduces the SI model to a few units in the last place (each figure is written as
//! the shortest decimal of its paper-unit value; a bias instability passes through the
//! Allan-peak ratio 0.6174).

use crate::ctx::Ctx;
use crate::error::ConfigError;
use crate::experiment::{EXPERIMENT_SCHEMA, NoiseFile, build_noise, check_schema, load_experiment};
use crate::toml_util;
use crate::units::{DEG_PER_H_PER_SQRT_H, DEG_PER_SQRT_H, UG_PER_SQRT_H, UG_PER_SQRT_HZ};
use serde::Deserialize;
use sins_files::write_file_atomically;
use sins_nav::{ARCSEC, DEG_PER_H, UG};
use sins_sim::NoiseModel;
use sins_sim::noise::GM_ALLAN_PEAK_RATIO;
use std::path::{Path, PathBuf};

/// The `kind` of a noise file.
pub const NOISE_KIND: &str = "noise";

/// A sensor-noise model with its uncertainty, as read from a noise or experiment file.
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseTable {
    /// The noise model (SI; bias instabilities as Gauss-Markov σ).
    pub noise: NoiseModel,
    /// 1-sigma of every field of `noise` (SI, same layout), when the file gives them.
    pub sigma: Option<NoiseModel>,
    /// The rate random walks the identification could not exclude, gyro (rad/s/√s) and
    /// accelerometer (m/s²/√s): 95 % upper bounds, 0 for a walk it resolved, +∞ for a walk the
    /// data put no finite bound on (its key left out of the file; the diagnosis does not fit
    /// it); `None` when the file has no `[imu.unresolved_walk]` (an experiment never has).
    pub unresolved_walk_per_sqrt_s: Option<[f64; 2]>,
    /// Why the identification found its model inconsistent with the data (the
    /// `[identification] inconsistent` list; empty when consistent or absent).
    pub inconsistent: Vec<String>,
    /// The file's description.
    pub description: String,
    /// Whether it came from a noise file (`kind = "noise"`) rather than an experiment.
    pub from_noise_file: bool,
    /// The file read.
    pub source_path: PathBuf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NoiseOnlyFile {
    schema: u32,
    #[allow(dead_code)]
    kind: String,
    #[serde(default)]
    description: String,
    imu: NoiseImu,
    #[serde(default)]
    identification: Option<IdentificationFile>,
}

/// `[identification]`: whether the identified model agrees with the data it came from.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct IdentificationFile {
    consistent: bool,
    #[serde(default)]
    inconsistent: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NoiseImu {
    noise: NoiseFile,
    noise_sigma: Option<SigmaFile>,
    unresolved_walk: Option<WalkFile>,
}

/// `[imu.unresolved_walk]`: 95 % upper bounds of the rate random walks, paper units; a key
/// left out is a walk the data put no finite bound on.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WalkFile {
    #[serde(default)]
    gyro_deg_per_h_per_sqrt_h: Option<f64>,
    #[serde(default)]
    accel_ug_per_sqrt_h: Option<f64>,
}

/// `[imu.noise_sigma]`: 1-sigma of each figure, paper units; a key left out is a figure the
/// data did not bound (an infinite 1-sigma, e.g. the correlation time of a random constant).
#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
struct SigmaFile {
    gyro_arw_deg_per_sqrt_h: Option<f64>,
    gyro_bias_instability_deg_per_h: Option<f64>,
    gyro_bias_correlation_s: Option<f64>,
    gyro_quantum_arcsec: Option<f64>,
    accel_vrw_ug_per_sqrt_hz: Option<f64>,
    accel_bias_instability_ug: Option<f64>,
    accel_bias_correlation_s: Option<f64>,
}

/// Read a noise file or, when its `kind` is not `"noise"`, an experiment file (whose first
/// run's noise is taken; all its runs share `[imu.noise]`).
pub fn load_noise(path: impl AsRef<Path>) -> Result<NoiseTable, ConfigError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Io {
        path: path.to_owned(),
        source,
    })?;
    let is_noise = toml::from_str::<toml::Table>(&text)
        .ok()
        .and_then(|t| {
            t.get("kind")
                .and_then(|k| k.as_str().map(|k| k == NOISE_KIND))
        })
        .unwrap_or(false);
    if !is_noise {
        if let Some(found) = other_kind(path, &text) {
            return Err(ConfigError::WrongKind {
                path: path.to_owned(),
                found: found.into(),
                expected: "a noise file (noise's output)".into(),
            });
        }
        let exp = load_experiment(path)?;
        let ctx = Ctx::new(path, &text);
        let noise = exp
            .scenarios
            .first()
            .map(|s| s.noise)
            .ok_or_else(|| ctx.missing("run", "an experiment needs at least one [[run]]"))?;
        return Ok(NoiseTable {
            noise,
            sigma: None,
            unresolved_walk_per_sqrt_s: None,
            inconsistent: Vec::new(),
            description: exp.description,
            from_noise_file: false,
            source_path: path.to_owned(),
        });
    }
    parse_noise_file(&text, path)
}

/// What a file that is not a noise file is, when it is recognisably something else: a
/// parameter set (TOML with `[gyro]`/`[accel]` tables or a `model` key and neither `[imu]`
/// nor `[[run]]`, or JSON with those keys).
fn other_kind(path: &Path, text: &str) -> Option<&'static str> {
    const PARAMS: &str = "a parameter set (calibrate's output)";
    let looks_like_params = |has: &dyn Fn(&str) -> bool| {
        (has("gyro") || has("accel") || has("model")) && !has("imu") && !has("run")
    };
    if let Ok(t) = toml::from_str::<toml::Table>(text) {
        return looks_like_params(&|k| t.contains_key(k)).then_some(PARAMS);
    }
    match serde_json::from_str::<serde_json::Value>(text) {
        Ok(serde_json::Value::Object(o)) => {
            looks_like_params(&|k| o.contains_key(k)).then_some(PARAMS)
        }
        _ => {
            let json = path.extension().is_some_and(|e| e == "json");
            json.then_some("a JSON file")
        }
    }
}

/// Read the text of a noise file (`kind = "noise"`; not an experiment) read from `path`, as
/// [`load_noise`] does: e.g. to check that a noise file about to be written reads back.
pub fn parse_noise_file(text: &str, path: &Path) -> Result<NoiseTable, ConfigError> {
    let ctx = Ctx::new(path, text);
    let raw: NoiseOnlyFile = toml_util::from_str(text, &ctx.origin)?;
    check_schema(&ctx, raw.schema)?;
    let noise = build_noise(&ctx, &raw.imu.noise)?;
    let sigma = match &raw.imu.noise_sigma {
        Some(s) => Some(sigma_model(&ctx, s)?),
        None => None,
    };
    let unresolved_walk_per_sqrt_s = match &raw.imu.unresolved_walk {
        Some(w) => Some(walk_bounds(&ctx, w)?),
        None => None,
    };
    let inconsistent = match raw.identification {
        Some(i) if !i.consistent && i.inconsistent.is_empty() => {
            vec!["the noise file says the identification is inconsistent (no reason given)".into()]
        }
        Some(i) if !i.consistent => i.inconsistent,
        _ => Vec::new(),
    };
    Ok(NoiseTable {
        noise,
        sigma,
        unresolved_walk_per_sqrt_s,
        inconsistent,
        description: raw.description,
        from_noise_file: true,
        source_path: path.to_owned(),
    })
}

fn walk_bounds(ctx: &Ctx<'_>, w: &WalkFile) -> Result<[f64; 2], ConfigError> {
    let check = |name: &str, v: Option<f64>, unit: f64| match v {
        None => Ok(f64::INFINITY),
        Some(v) if v.is_finite() && v >= 0.0 => Ok(v * unit),
        Some(v) => Err(ctx.invalid(
            &format!("imu.unresolved_walk.{name}"),
            format!(
                "a bound must be finite and >= 0, got {v} (leave the key out where the data \
                 put no finite bound on the walk)"
            ),
        )),
    };
    Ok([
        check(
            "gyro_deg_per_h_per_sqrt_h",
            w.gyro_deg_per_h_per_sqrt_h,
            DEG_PER_H_PER_SQRT_H,
        )?,
        check("accel_ug_per_sqrt_h", w.accel_ug_per_sqrt_h, UG_PER_SQRT_H)?,
    ])
}

fn sigma_model(ctx: &Ctx<'_>, s: &SigmaFile) -> Result<NoiseModel, ConfigError> {
    let k = |name: &str| format!("imu.noise_sigma.{name}");
    let nn = |name: &str, v: Option<f64>| -> Result<f64, ConfigError> {
        match v {
            None => Ok(f64::INFINITY),
            Some(v) if v.is_nan() || v < 0.0 => Err(ctx.invalid(
                &k(name),
                format!(
                    "a 1-sigma must be >= 0, got {v} (leave the key out where the data did not \
                     bound the figure)"
                ),
            )),
            Some(v) => Ok(v),
        }
    };
    Ok(NoiseModel {
        gyro_arw_rad_per_sqrt_s: nn("gyro_arw_deg_per_sqrt_h", s.gyro_arw_deg_per_sqrt_h)?
            * DEG_PER_SQRT_H,
        gyro_bias_instability_radps: nn(
            "gyro_bias_instability_deg_per_h",
            s.gyro_bias_instability_deg_per_h,
        )? * DEG_PER_H
            / GM_ALLAN_PEAK_RATIO,
        gyro_bias_correlation_s: nn("gyro_bias_correlation_s", s.gyro_bias_correlation_s)?,
        gyro_quantum_rad: nn("gyro_quantum_arcsec", s.gyro_quantum_arcsec)? * ARCSEC,
        accel_vrw_mps_per_sqrt_s: nn("accel_vrw_ug_per_sqrt_hz", s.accel_vrw_ug_per_sqrt_hz)?
            * UG_PER_SQRT_HZ,
        accel_bias_instability_mps2: nn("accel_bias_instability_ug", s.accel_bias_instability_ug)?
            * UG
            / GM_ALLAN_PEAK_RATIO,
        accel_bias_correlation_s: nn("accel_bias_correlation_s", s.accel_bias_correlation_s)?,
    })
}

/// The seven figures of a model in the file's units, in key order.
fn paper_values(m: &NoiseModel) -> [(&'static str, f64, &'static str); 7] {
    [
        (
            "gyro_arw_deg_per_sqrt_h",
            m.gyro_arw_rad_per_sqrt_s / DEG_PER_SQRT_H,
            "angle random walk",
        ),
        (
            "gyro_bias_instability_deg_per_h",
            m.gyro_bias_instability_radps * GM_ALLAN_PEAK_RATIO / DEG_PER_H,
            "Allan bias-instability figure = 0.6174 x Gauss-Markov sigma",
        ),
        (
            "gyro_bias_correlation_s",
            m.gyro_bias_correlation_s,
            "Gauss-Markov correlation time",
        ),
        (
            "gyro_quantum_arcsec",
            m.gyro_quantum_rad / ARCSEC,
            "output quantum",
        ),
        (
            "accel_vrw_ug_per_sqrt_hz",
            m.accel_vrw_mps_per_sqrt_s / UG_PER_SQRT_HZ,
            "velocity random walk",
        ),
        (
            "accel_bias_instability_ug",
            m.accel_bias_instability_mps2 * GM_ALLAN_PEAK_RATIO / UG,
            "Allan bias-instability figure = 0.6174 x Gauss-Markov sigma",
        ),
        (
            "accel_bias_correlation_s",
            m.accel_bias_correlation_s,
            "Gauss-Markov correlation time",
        ),
    ]
}

/// A TOML number: the shortest decimal that reads back to `v` (`inf` for infinity, `nan` for
/// NaN: valid TOML, which the reader then refuses naming the key; the writer leaves out the
/// infinite figures it may meet, a random constant's correlation time and unbounded 1-sigmas).
fn number(v: f64) -> String {
    if v.is_nan() {
        return "nan".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf".into() } else { "-inf".into() };
    }
    let s = format!("{v:?}");
    if s.contains(['.', 'e', 'E']) {
        s
    } else {
        format!("{s}.0")
    }
}

/// A noise file (`kind = "noise"`) of `noise` with its optional 1-sigma and unresolved rate
/// random walks (gyro rad/s/√s, accelerometer m/s²/√s; see
/// [`NoiseTable::unresolved_walk_per_sqrt_s`]), `comments` as leading `#` lines (e.g. how it
/// was identified) and `description`.
pub fn noise_to_toml(
    noise: &NoiseModel,
    sigma: Option<&NoiseModel>,
    unresolved_walk_per_sqrt_s: Option<[f64; 2]>,
    description: &str,
    comments: &[String],
) -> String {
    render(
        noise,
        sigma,
        unresolved_walk_per_sqrt_s,
        description,
        comments,
        None,
    )
}

/// [`noise_to_toml`] with the identification's consistency: a non-empty `inconsistent` writes
/// `[identification] consistent = false` and its reasons, which `diagnose --noise-from` reads.
pub fn noise_to_toml_checked(
    noise: &NoiseModel,
    sigma: Option<&NoiseModel>,
    unresolved_walk_per_sqrt_s: Option<[f64; 2]>,
    description: &str,
    comments: &[String],
    inconsistent: &[String],
) -> String {
    render(
        noise,
        sigma,
        unresolved_walk_per_sqrt_s,
        description,
        comments,
        Some(inconsistent),
    )
}

fn render(
    noise: &NoiseModel,
    sigma: Option<&NoiseModel>,
    unresolved_walk_per_sqrt_s: Option<[f64; 2]>,
    description: &str,
    comments: &[String],
    inconsistent: Option<&[String]>,
) -> String {
    let mut out = String::new();
    for c in comments {
        for line in c.lines() {
            out.push_str(&format!("# {line}\n"));
        }
    }
    out.push_str(&format!(
        "schema = {EXPERIMENT_SCHEMA}\nkind = \"{NOISE_KIND}\"\ndescription = {}\n\n[imu.noise]\n",
        toml_util::quote(description)
    ));
    for (key, v, what) in paper_values(noise) {
        if v == f64::INFINITY && key.ends_with("_correlation_s") {
            out.push_str(&format!(
                "# {key} left out: the bias is a random constant (no finite correlation time)\n"
            ));
        } else {
            out.push_str(&format!("{key} = {}    # {what}\n", number(v)));
        }
    }
    if let Some(s) = sigma {
        out.push_str("\n# 1-sigma of each figure above (same units)\n[imu.noise_sigma]\n");
        for (key, v, _) in paper_values(s) {
            if v == f64::INFINITY {
                out.push_str(&format!("# {key} left out: the data put no bound on it\n"));
            } else {
                out.push_str(&format!("{key} = {}\n", number(v)));
            }
        }
    }
    if let Some([g, a]) = unresolved_walk_per_sqrt_s {
        out.push_str(
            "\n# Rate random walks the stationary data could not exclude (95 % upper bounds; 0 where\n\
             # the walk was resolved): the diagnosis fits walks up to these on the navigation gap.\n\
             [imu.unresolved_walk]\n",
        );
        for (key, si, unit, what) in [
            ("gyro_deg_per_h_per_sqrt_h", g, DEG_PER_H_PER_SQRT_H, "gyro"),
            ("accel_ug_per_sqrt_h", a, UG_PER_SQRT_H, "accelerometer"),
        ] {
            let v = si / unit;
            if v.is_finite() {
                out.push_str(&format!("{key} = {}\n", number(v)));
            } else {
                out.push_str(&format!(
                    "# {key} left out: the stationary data put no finite 95 % bound on the {what} \
                     rate random walk (too little or too short still data), so the diagnosis does not fit it\n"
                ));
            }
        }
    }
    let Some(inconsistent) = inconsistent else {
        return out;
    };
    out.push_str(&format!(
        "\n# Whether the identified model agrees with the data it came from (diagnose reads this)\n\
         [identification]\nconsistent = {}\n",
        inconsistent.is_empty()
    ));
    if !inconsistent.is_empty() {
        out.push_str("inconsistent = [\n");
        for r in inconsistent {
            out.push_str(&format!("    {},\n", toml_util::quote(r)));
        }
        out.push_str("]\n");
    }
    out
}

/// Write a noise file to `path` (aside, then renamed into place).
pub fn write_noise(
    path: impl AsRef<Path>,
    noise: &NoiseModel,
    sigma: Option<&NoiseModel>,
    unresolved_walk_per_sqrt_s: Option<[f64; 2]>,
    description: &str,
    comments: &[String],
) -> Result<(), ConfigError> {
    let path = path.as_ref();
    let text = noise_to_toml(
        noise,
        sigma,
        unresolved_walk_per_sqrt_s,
        description,
        comments,
    );
    write_file_atomically(path, text.as_bytes()).map_err(|source| ConfigError::Io {
        path: path.to_owned(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        a == b || (a / b - 1.0).abs() < 1e-14
    }

    fn model() -> NoiseModel {
        NoiseModel {
            gyro_arw_rad_per_sqrt_s: 1.4123e-7,
            gyro_bias_instability_radps: 3.1e-9,
            gyro_bias_correlation_s: 4321.5,
            gyro_quantum_rad: 4.848_136_811_095_36e-6,
            accel_vrw_mps_per_sqrt_s: 9.81e-5,
            accel_bias_instability_mps2: 7.7e-5,
            accel_bias_correlation_s: f64::INFINITY,
        }
    }

    #[test]
    fn noise_file_round_trip_reproduces_the_model_and_its_sigma() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("noise.toml");
        let mut sigma = model();
        sigma.gyro_arw_rad_per_sqrt_s = 2e-9;
        sigma.gyro_bias_correlation_s = f64::INFINITY;
        write_noise(
            &path,
            &model(),
            Some(&sigma),
            Some([3.3e-9, 0.0]),
            "test \"quoted\"",
            &["line one\nline two".into()],
        )
        .expect("written");
        let text = std::fs::read_to_string(&path).expect("read");
        assert!(
            !text.contains("= inf"),
            "an infinite figure was written:\n{text}"
        );
        let t = load_noise(&path).expect("read back");
        assert!(t.from_noise_file);
        assert_eq!(t.description, "test \"quoted\"");
        let (a, b) = (t.noise, model());
        for (x, y) in [
            (a.gyro_arw_rad_per_sqrt_s, b.gyro_arw_rad_per_sqrt_s),
            (a.gyro_bias_instability_radps, b.gyro_bias_instability_radps),
            (a.gyro_bias_correlation_s, b.gyro_bias_correlation_s),
            (a.gyro_quantum_rad, b.gyro_quantum_rad),
            (a.accel_vrw_mps_per_sqrt_s, b.accel_vrw_mps_per_sqrt_s),
            (a.accel_bias_instability_mps2, b.accel_bias_instability_mps2),
            (a.accel_bias_correlation_s, b.accel_bias_correlation_s),
        ] {
            assert!(close(x, y), "{x} vs {y}");
        }
        let s = t.sigma.expect("sigma");
        assert!(close(s.gyro_arw_rad_per_sqrt_s, 2e-9));
        assert!(s.gyro_bias_correlation_s.is_infinite());
        let [g, a] = t.unresolved_walk_per_sqrt_s.expect("walk bounds");
        assert!(close(g, 3.3e-9) && a == 0.0, "{g} {a}");
    }

    #[test]
    fn a_walk_bound_that_is_not_finite_is_left_out_and_reads_back_as_unbounded() {
        let text = noise_to_toml(&model(), None, Some([3.3e-9, f64::INFINITY]), "x", &[]);
        let walks = text
            .split("[imu.unresolved_walk]")
            .nth(1)
            .expect("walk table");
        assert!(!walks.contains("= inf"), "{text}");
        assert!(
            text.contains("# accel_ug_per_sqrt_h left out: the stationary data put no finite"),
            "{text}"
        );
        let t = parse_noise_file(&text, Path::new("noise.toml")).expect("reads back");
        let [g, a] = t.unresolved_walk_per_sqrt_s.expect("bounds");
        assert!(close(g, 3.3e-9) && a == f64::INFINITY, "{g} {a}");
        let nan = noise_to_toml(&model(), None, Some([f64::NAN, 0.0]), "x", &[]);
        assert!(
            nan.contains("# gyro_deg_per_h_per_sqrt_h left out"),
            "{nan}"
        );
        // A NaN figure elsewhere is written as TOML's `nan`, which the reader refuses by key.
        let mut bad = model();
        bad.gyro_arw_rad_per_sqrt_s = f64::NAN;
        let e = parse_noise_file(
            &noise_to_toml(&bad, None, None, "x", &[]),
            Path::new("n.toml"),
        )
        .expect_err("nan refused")
        .to_string();
        assert!(e.contains("imu.noise.gyro_arw_deg_per_sqrt_h"), "{e}");
    }

    #[test]
    fn a_parameter_set_given_as_a_noise_file_is_named_as_such() {
        let imu = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments/imu");
        let e = load_noise(imu.join("paper_truth.toml"))
            .expect_err("a parameter set")
            .to_string();
        assert!(
            e.contains("paper_truth.toml is a parameter set (calibrate's output), not a noise file (noise's output)"),
            "{e}"
        );
        assert!(!e.contains("unknown field"), "{e}");
    }

    #[test]
    fn noise_file_refuses_unknown_keys_and_an_experiment_still_loads() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("bad.toml");
        let text = noise_to_toml(&model(), None, None, "x", &[])
            .replace("[imu.noise]\n", "[imu.noise]\ngyro_typo = 1.0\n");
        std::fs::write(&path, text).expect("write");
        let e = load_noise(&path)
            .expect_err("unknown key refused")
            .to_string();
        assert!(e.contains("gyro_typo") && e.contains("bad.toml"), "{e}");
        let negative = noise_to_toml(&model(), None, Some([1e-9, 1e-6]), "x", &[])
            .replace("accel_ug_per_sqrt_h = ", "accel_ug_per_sqrt_h = -");
        std::fs::write(&path, negative).expect("write");
        let e = load_noise(&path).expect_err("negative bound").to_string();
        assert!(e.contains("imu.unresolved_walk.accel_ug_per_sqrt_h"), "{e}");
        let exp =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments/paper_navigation.toml");
        let t = load_noise(&exp).expect("experiment");
        assert!(!t.from_noise_file);
        assert!((t.noise.gyro_quantum_rad / ARCSEC - 1.0).abs() < 1e-12);
    }
}
