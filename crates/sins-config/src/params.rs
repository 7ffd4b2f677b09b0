//! IMU parameter files (TOML or JSON) in the paper's units → [`ParamSet`] in SI.
//!
//! Numbers are converted with one correct rounding from their decimal text (see `exact.rs`), so
//! that files written by [`crate::params_to_toml`] / [`crate::params_to_json`] read back bit-exact.

use crate::coefficients::{Section, section_defs};
use crate::error::{ConfigError, line_of};
use crate::exact::{ExactFactor, decimal_to_si};
use crate::plausible;
use crate::toml_util;
use serde::Deserialize;
use serde::de::DeserializeOwned;
use serde_json::value::RawValue;
use sins_imu::{ImuErrorParams, ParamModel};
use std::collections::BTreeMap;
use std::path::Path;
use toml::Spanned;

/// A parameter set as stored in a file: the coefficients, optionally their 1-sigma uncertainties
/// (a calibration result) and a free description.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSet {
    /// The coefficients (SI).
    pub params: ImuErrorParams,
    /// 1-sigma uncertainty of each coefficient (SI, same model and layout), if the file has one.
    pub sigma: Option<ImuErrorParams>,
    /// Free text (empty when absent).
    pub description: String,
}

impl From<ImuErrorParams> for ParamSet {
    fn from(params: ImuErrorParams) -> Self {
        Self {
            params,
            sigma: None,
            description: String::new(),
        }
    }
}

/// The `model` value of a parameter file for a [`ParamModel`]: `"30-state"` or `"42-state"`.
pub fn model_name(model: ParamModel) -> &'static str {
    match model {
        ParamModel::States30 => "30-state",
        ParamModel::States42 => "42-state",
    }
}

type Table<N> = BTreeMap<String, N>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawParamFile<N> {
    model: String,
    reference_temperature_degc: Option<N>,
    description: Option<String>,
    gyro: Table<N>,
    accel: Table<N>,
    accel_temperature: Option<Table<N>>,
    sigma: Option<RawSigma<N>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSigma<N> {
    gyro: Table<N>,
    accel: Table<N>,
    accel_temperature: Option<Table<N>>,
}

/// A number as it appears in the source: its text and, for TOML, its position and parsed value.
trait RawNumber: DeserializeOwned {
    /// The literal text of the number.
    fn text<'a>(&'a self, src: &'a str) -> &'a str;
    /// The value the format's own parser produced (TOML only).
    fn parsed(&self) -> Option<f64>;
    /// 1-based source line (TOML only).
    fn line(&self, src: &str) -> Option<usize>;
}

impl RawNumber for Spanned<f64> {
    fn text<'a>(&'a self, src: &'a str) -> &'a str {
        src.get(self.span()).unwrap_or("")
    }
    fn parsed(&self) -> Option<f64> {
        Some(*self.get_ref())
    }
    fn line(&self, src: &str) -> Option<usize> {
        Some(line_of(src, self.span().start))
    }
}

impl RawNumber for Box<RawValue> {
    fn text<'a>(&'a self, _src: &'a str) -> &'a str {
        self.get()
    }
    fn parsed(&self) -> Option<f64> {
        None
    }
    fn line(&self, _src: &str) -> Option<usize> {
        None
    }
}

/// The coefficient tables of a file (or of its `[sigma]`).
struct Tables<'t, N> {
    gyro: &'t Table<N>,
    accel: &'t Table<N>,
    temperature: Option<&'t Table<N>>,
}

struct Reader<'a> {
    origin: &'a str,
    src: &'a str,
}

impl Reader<'_> {
    /// Converts one number to SI with `factor`, requiring a finite value.
    fn number<N: RawNumber>(
        &self,
        key: &str,
        n: &N,
        factor: ExactFactor,
    ) -> Result<f64, ConfigError> {
        let text = n.text(self.src).trim();
        let value = match (decimal_to_si(text, factor), n.parsed()) {
            (Some(v), _) => v,
            (None, Some(parsed)) => parsed * factor.approx(),
            (None, None) => {
                return Err(self.invalid(
                    key,
                    n.line(self.src),
                    format!("expected a number, found `{text}`"),
                ));
            }
        };
        if !value.is_finite() {
            return Err(self.invalid(
                key,
                n.line(self.src),
                format!("must be finite, found `{text}`"),
            ));
        }
        Ok(value)
    }

    fn invalid(&self, key: &str, line: Option<usize>, problem: String) -> ConfigError {
        ConfigError::Invalid {
            origin: self.origin.to_owned(),
            line,
            key: key.to_owned(),
            problem,
        }
    }

    /// Fills the coefficients of `section` from `table` (all required, no others allowed).
    fn section<N: RawNumber>(
        &self,
        prefix: &str,
        section: Section,
        table: &Table<N>,
        out: &mut ImuErrorParams,
        non_negative: bool,
    ) -> Result<(), ConfigError> {
        let defs = section_defs(section);
        let table_key = format!("{prefix}{}", section.key());
        if let Some((key, n)) = table
            .iter()
            .find(|(k, _)| !defs.iter().any(|d| d.key == k.as_str()))
        {
            return Err(ConfigError::UnknownKey {
                origin: self.origin.to_owned(),
                line: n.line(self.src),
                key: format!("{table_key}.{key}"),
                expected: defs.iter().map(|d| d.key).collect::<Vec<_>>().join(", "),
            });
        }
        for d in defs {
            let key = format!("{table_key}.{}", d.key);
            let n = table.get(d.key).ok_or_else(|| ConfigError::MissingKey {
                origin: self.origin.to_owned(),
                key: key.clone(),
                note: format!("coefficient {} in {}", d.name, d.unit.label()),
            })?;
            let v = self.number(&key, n, d.unit.factor())?;
            let in_unit = d.unit.from_si(v);
            let limit = plausible::coefficient_limit(d.unit);
            if in_unit.abs() > limit {
                let unit = d.unit.label();
                return Err(self.invalid(
                    &key,
                    n.line(self.src),
                    format!(
                        "{in_unit} {unit} is beyond the plausibility limit of {limit} {unit} \
                         ({}x the largest physically plausible {} {unit}; check the unit)",
                        plausible::COEFFICIENT_LIMIT_FACTOR,
                        plausible::largest_plausible(d.unit)
                    ),
                ));
            }
            if non_negative && v < 0.0 {
                return Err(self.invalid(
                    &key,
                    n.line(self.src),
                    "a standard deviation cannot be negative".into(),
                ));
            }
            *d.slot.get_mut(out) = v;
        }
        Ok(())
    }

    /// Fills gyro, accel and (for 42-state) accel_temperature; rejects a model mismatch.
    fn sections<N: RawNumber>(
        &self,
        prefix: &str,
        model: ParamModel,
        tables: Tables<'_, N>,
        out: &mut ImuErrorParams,
        non_negative: bool,
    ) -> Result<(), ConfigError> {
        self.section(prefix, Section::Gyro, tables.gyro, out, non_negative)?;
        self.section(prefix, Section::Accel, tables.accel, out, non_negative)?;
        let key = format!("{prefix}{}", Section::AccelTemperature.key());
        match (model, tables.temperature) {
            (ParamModel::States42, Some(t)) => {
                self.section(prefix, Section::AccelTemperature, t, out, non_negative)
            }
            (ParamModel::States42, None) => Err(ConfigError::MissingKey {
                origin: self.origin.to_owned(),
                key,
                note: "the 42-state model needs its 12 temperature coefficients".into(),
            }),
            (ParamModel::States30, Some(t)) => Err(self.invalid(
                &key,
                t.values().next().and_then(|n| n.line(self.src)),
                "a 30-state parameter set has no temperature coefficients: remove this table or set model = \"42-state\"".into(),
            )),
            (ParamModel::States30, None) => Ok(()),
        }
    }

    fn convert<N: RawNumber>(&self, raw: RawParamFile<N>) -> Result<ParamSet, ConfigError> {
        let model = match raw.model.as_str() {
            "30-state" => ParamModel::States30,
            "42-state" => ParamModel::States42,
            other => {
                return Err(self.invalid(
                    "model",
                    None,
                    format!("unknown model \"{other}\" (expected \"30-state\" or \"42-state\")"),
                ));
            }
        };
        let mut params = ImuErrorParams::ideal(model);
        if let Some(t) = &raw.reference_temperature_degc {
            let key = "reference_temperature_degc";
            let t_degc = self.number(key, t, ExactFactor::ONE)?;
            if !plausible::temperature_ok(t_degc) {
                let msg = format!("{t_degc} degC is {}", plausible::temperature_range_text());
                return Err(self.invalid(key, t.line(self.src), msg));
            }
            params.reference_temperature_degc = t_degc;
        }
        let tables = Tables {
            gyro: &raw.gyro,
            accel: &raw.accel,
            temperature: raw.accel_temperature.as_ref(),
        };
        self.sections("", model, tables, &mut params, false)?;
        let sigma = match &raw.sigma {
            Some(s) => {
                let mut sigma = params;
                let tables = Tables {
                    gyro: &s.gyro,
                    accel: &s.accel,
                    temperature: s.accel_temperature.as_ref(),
                };
                self.sections("sigma.", model, tables, &mut sigma, true)?;
                Some(sigma)
            }
            None => None,
        };
        Ok(ParamSet {
            params,
            sigma,
            description: raw.description.unwrap_or_default(),
        })
    }
}

/// Parses a TOML parameter file. `origin` names the source in errors (usually the path).
pub fn parse_params_toml(text: &str, origin: &str) -> Result<ParamSet, ConfigError> {
    let raw: RawParamFile<Spanned<f64>> = toml_util::from_str(text, origin)?;
    Reader { origin, src: text }.convert(raw)
}

/// Parses a JSON parameter file (same structure as the TOML one, tables as objects). `origin`
/// names the source in errors.
pub fn parse_params_json(text: &str, origin: &str) -> Result<ParamSet, ConfigError> {
    let raw: RawParamFile<Box<RawValue>> = serde_json::from_str(text).map_err(|e| {
        let (line, column) = (e.line(), e.column());
        let message = e.to_string();
        let suffix = format!(" at line {line} column {column}");
        ConfigError::Parse {
            origin: origin.to_owned(),
            line: (line > 0).then_some(line),
            column: (line > 0).then_some(column),
            key: None,
            message: message.strip_suffix(&suffix).unwrap_or(&message).to_owned(),
        }
    })?;
    Reader { origin, src: text }.convert(raw)
}

/// Reads a parameter file, TOML or JSON by extension (`.toml`, `.json`).
pub fn load_params(path: impl AsRef<Path>) -> Result<ParamSet, ConfigError> {
    let path = path.as_ref();
    let format = ParamFormat::from_path(path)?;
    let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Io {
        path: path.to_owned(),
        source,
    })?;
    let origin = path.display().to_string();
    match format {
        ParamFormat::Toml => parse_params_toml(&text, &origin),
        ParamFormat::Json => parse_params_json(&text, &origin),
    }
}

/// The two parameter-file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamFormat {
    /// TOML (`.toml`).
    Toml,
    /// JSON (`.json`).
    Json,
}

impl ParamFormat {
    /// The format implied by the extension of `path` (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Self, ConfigError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("toml") => Ok(ParamFormat::Toml),
            Some("json") => Ok(ParamFormat::Json),
            _ => Err(ConfigError::UnknownFormat {
                path: path.to_owned(),
            }),
        }
    }
}
