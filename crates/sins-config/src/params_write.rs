//! Writing parameter sets in the paper's units (TOML and JSON), bit-exact on reading back.

use crate::coefficients::{Section, section_defs};
use crate::error::ConfigError;
use crate::exact::{ExactFactor, format_exact};
use crate::params::{ParamFormat, ParamSet, model_name};
use crate::toml_util::quote;
use sins_imu::{ImuErrorParams, ParamModel};
use std::fmt::Write as _;
use std::path::Path;

/// Sections present for a model, in file order.
fn sections(model: ParamModel) -> &'static [Section] {
    match model {
        ParamModel::States30 => &Section::ALL[..2],
        ParamModel::States42 => &Section::ALL,
    }
}

/// `(key, value text)` of every coefficient of `section`, values in paper units.
fn entries(p: &ImuErrorParams, section: Section) -> Vec<(&'static str, String)> {
    section_defs(section)
        .into_iter()
        .map(|d| (d.key, format_exact(d.slot.get(p), d.unit.factor())))
        .collect()
}

/// Writes `set` as a TOML parameter file in paper units. Every number is the shortest decimal that
/// [`crate::parse_params_toml`] converts back to the identical SI double.
pub fn params_to_toml(set: &ParamSet) -> String {
    let p = &set.params;
    let mut out = String::new();
    out.push_str(
        "# IMU error parameters in the units of Wang et al. 2021 (deg/h, ppm, arcsec, ug, per degC).\n",
    );
    let _ = writeln!(out, "model = {}", quote(model_name(p.model)));
    let _ = writeln!(
        out,
        "reference_temperature_degc = {}",
        format_exact(p.reference_temperature_degc, ExactFactor::ONE)
    );
    if !set.description.is_empty() {
        let _ = writeln!(out, "description = {}", quote(&set.description));
    }
    let table = |out: &mut String, prefix: &str, params: &ImuErrorParams, s: Section| {
        let _ = writeln!(out, "\n[{prefix}{}]", s.key());
        for (key, value) in entries(params, s) {
            let _ = writeln!(out, "{key} = {value}");
        }
    };
    for &s in sections(p.model) {
        table(&mut out, "", p, s);
    }
    if let Some(sigma) = &set.sigma {
        out.push_str("\n# 1-sigma uncertainties of the coefficients above, same units.");
        for &s in sections(p.model) {
            table(&mut out, "sigma.", sigma, s);
        }
    }
    out
}

/// Writes `set` as a JSON parameter file (same structure as the TOML file), bit-exact on reading
/// back with [`crate::parse_params_json`].
pub fn params_to_json(set: &ParamSet) -> String {
    let p = &set.params;
    let json_str = |s: &str| serde_json::Value::String(s.to_owned()).to_string();
    let object = |params: &ImuErrorParams, s: Section, indent: &str| {
        let body: Vec<String> = entries(params, s)
            .into_iter()
            .map(|(k, v)| format!("{indent}  {}: {v}", json_str(k)))
            .collect();
        format!(
            "{indent}{}: {{\n{}\n{indent}}}",
            json_str(s.key()),
            body.join(",\n")
        )
    };
    let mut fields = vec![
        format!("  \"model\": {}", json_str(model_name(p.model))),
        format!(
            "  \"reference_temperature_degc\": {}",
            format_exact(p.reference_temperature_degc, ExactFactor::ONE)
        ),
    ];
    if !set.description.is_empty() {
        fields.push(format!("  \"description\": {}", json_str(&set.description)));
    }
    for &s in sections(p.model) {
        fields.push(object(p, s, "  "));
    }
    if let Some(sigma) = &set.sigma {
        let inner: Vec<String> = sections(p.model)
            .iter()
            .map(|&s| object(sigma, s, "    "))
            .collect();
        fields.push(format!("  \"sigma\": {{\n{}\n  }}", inner.join(",\n")));
    }
    format!("{{\n{}\n}}\n", fields.join(",\n"))
}

/// Writes `set` to `path`, TOML or JSON by extension.
pub fn write_params(path: impl AsRef<Path>, set: &ParamSet) -> Result<(), ConfigError> {
    let path = path.as_ref();
    let text = match ParamFormat::from_path(path)? {
        ParamFormat::Toml => params_to_toml(set),
        ParamFormat::Json => params_to_json(set),
    };
    // Write aside and rename, so a failure never leaves a half-written parameter file.
    sins_files::write_file_atomically(path, text.as_bytes()).map_err(|source| ConfigError::Write {
        path: path.to_owned(),
        source,
    })
}
