//! Reading `[[imu.effect]]` tables from the spanned TOML document, so that every number is
//! converted from its decimal text and every error names its key and line.

use super::schema::{Aux, magnitude_factor, schema, set_aux};
use crate::ctx::Ctx;
use crate::error::ConfigError;
use crate::exact::{ExactFactor, decimal_to_si};
use crate::plausible;
use crate::toml_util;
use sins_imu::{EffectKind, EffectSpec};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// A TOML value's description for error messages.
fn describe(v: &DeValue<'_>) -> &'static str {
    match v {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a datetime",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

/// Reads the tables of one array of effects, naming keys `<prefix>[i].<key>`.
pub(super) struct Reader<'c, 'a> {
    pub(super) ctx: &'c Ctx<'a>,
}

impl Reader<'_, '_> {
    /// A number (float or integer) converted to SI with `factor`; infinities only if `allow_inf`.
    fn number(
        &self,
        key: &str,
        v: &DeValue<'_>,
        factor: ExactFactor,
        allow_inf: bool,
    ) -> Result<f64, ConfigError> {
        let text = match v {
            DeValue::Float(f) => f.as_str().replace('_', ""),
            DeValue::Integer(i) if i.radix() == 10 => i.as_str().replace('_', ""),
            DeValue::Integer(i) => i128::from_str_radix(&i.as_str().replace('_', ""), i.radix())
                .map(|n| n.to_string())
                .unwrap_or_default(),
            other => {
                return Err(self
                    .ctx
                    .invalid(key, format!("expected a number, found {}", describe(other))));
            }
        };
        let value = decimal_to_si(&text, factor)
            .or_else(|| text.parse::<f64>().ok().map(|x| x * factor.approx()));
        match value {
            Some(x) if x.is_finite() || (allow_inf && x == f64::INFINITY) => Ok(x),
            _ => Err(self
                .ctx
                .invalid(key, format!("must be a finite number, found `{text}`"))),
        }
    }

    /// Three numbers `[x, y, z]` in SI.
    fn triple(
        &self,
        key: &str,
        v: &DeValue<'_>,
        factor: ExactFactor,
        unit: &str,
    ) -> Result<[f64; 3], ConfigError> {
        let Some(items) = v.as_array() else {
            return Err(self.ctx.invalid(
                key,
                format!(
                    "expected an array of 3 numbers [x, y, z] in {unit}, found {}",
                    describe(v)
                ),
            ));
        };
        if items.len() != 3 {
            return Err(self.ctx.invalid(
                key,
                format!(
                    "expected 3 numbers [x, y, z] in {unit}, found {}",
                    items.len()
                ),
            ));
        }
        let mut out = [0.0; 3];
        for (i, item) in items.iter().enumerate() {
            out[i] = self.number(&format!("{key}[{i}]"), item.get_ref(), factor, false)?;
        }
        Ok(out)
    }

    /// An auxiliary value: `(SI value, seed)`, validated.
    fn aux(&self, key: &str, aux: Aux, v: &DeValue<'_>) -> Result<(f64, u64), ConfigError> {
        if aux == Aux::Seed {
            let seed = match v {
                DeValue::Integer(i) => {
                    u64::from_str_radix(&i.as_str().replace('_', ""), i.radix()).ok()
                }
                _ => None,
            };
            return seed.map(|s| (0.0, s)).ok_or_else(|| {
                self.ctx
                    .invalid(key, "must be an integer from 0 to 2^64 - 1 (the seed)")
            });
        }
        let x = self.number(key, v, aux.factor(), aux == Aux::CorrelationS)?;
        let bad = match aux {
            Aux::CorrelationS if x <= 0.0 => Some("must be > 0 (or inf for a random walk)".into()),
            Aux::PeriodS | Aux::TimeConstantS | Aux::RiseTimeS | Aux::DurationS if x <= 0.0 => {
                Some("must be > 0".into())
            }
            Aux::ReferenceDegc if !plausible::temperature_ok(x) => {
                Some(format!("is {}", plausible::temperature_range_text()))
            }
            _ => None,
        };
        match bad {
            Some(problem) => Err(self.ctx.invalid(key, format!("{problem}, found {x}"))),
            None => Ok((x, 0)),
        }
    }

    /// One effect table at key path `at` (e.g. `imu.effect[2]`).
    fn effect(&self, at: &str, table: &DeTable<'_>) -> Result<EffectSpec, ConfigError> {
        let get = |name: &str| find(table, name);
        let kind_key = format!("{at}.kind");
        let kind = match get("kind") {
            None => {
                let known: Vec<_> = EffectKind::ALL.iter().map(|k| k.name()).collect();
                let note = format!("one of: {}", known.join(", "));
                return Err(self.ctx.missing(&kind_key, note));
            }
            Some(DeValue::String(name)) => EffectKind::from_name(name).ok_or_else(|| {
                let known: Vec<_> = EffectKind::ALL.iter().map(|k| k.name()).collect();
                let msg = format!("unknown effect kind `{name}` (known: {})", known.join(", "));
                self.ctx.invalid(&kind_key, msg)
            })?,
            Some(other) => {
                return Err(self.ctx.invalid(
                    &kind_key,
                    format!("expected a string, found {}", describe(other)),
                ));
            }
        };
        let (mag_keys, auxes) = schema(kind);
        let mut expected = vec!["kind"];
        expected.extend_from_slice(mag_keys);
        expected.extend(auxes.iter().map(|a| a.key()));
        for (k, _) in table.iter() {
            let name: &str = k.get_ref();
            if !expected.contains(&name) {
                return Err(ConfigError::UnknownKey {
                    origin: self.ctx.origin.clone(),
                    line: self.ctx.line(&format!("{at}.{name}")),
                    key: format!("{at}.{name}"),
                    expected: format!("{} for kind `{}`", expected.join(", "), kind.name()),
                });
            }
        }
        let unit = kind.unit();
        let factor = magnitude_factor(kind);
        let mut mags = Vec::with_capacity(kind.n_components());
        for key in mag_keys {
            let path = format!("{at}.{key}");
            let value = match get(key) {
                Some(v) => self.triple(&path, v, factor, unit.label)?,
                // The size effect's lever arms default to zero (an accelerometer at the centre).
                None if mag_keys.len() > 1 => [0.0; 3],
                None => {
                    let note = format!("[x, y, z] in {}", unit.label);
                    return Err(self.ctx.missing(&path, note));
                }
            };
            let limit = plausible::effect_limit(kind);
            for (i, x) in value.iter().enumerate() {
                let in_unit = x / unit.si;
                if in_unit.abs() > limit {
                    let msg = format!(
                        "{in_unit} {u} is beyond the plausibility limit of {limit} {u} ({}x the \
                         largest physically plausible {} {u}; check the unit)",
                        plausible::COEFFICIENT_LIMIT_FACTOR,
                        plausible::effect_largest_plausible(kind),
                        u = unit.label
                    );
                    return Err(self.ctx.invalid(&format!("{path}[{i}]"), msg));
                }
            }
            mags.extend_from_slice(&value);
        }
        let mut spec = EffectSpec::zero(kind)
            .with_magnitudes_si(&mags)
            .ok_or_else(|| self.ctx.invalid(at, "wrong number of magnitude components"))?;
        for &aux in auxes {
            let path = format!("{at}.{}", aux.key());
            match get(aux.key()) {
                Some(v) => {
                    let (x, seed) = self.aux(&path, aux, v)?;
                    set_aux(&mut spec, aux, x, seed);
                }
                None if aux == Aux::Seed => {
                    return Err(self
                        .ctx
                        .missing(&path, "an integer seed of the realisation"));
                }
                None => {}
            }
        }
        Ok(spec)
    }

    /// Every table of the array `imu.effect` in `doc` (none when absent).
    pub(super) fn all(&self, doc: &DeTable<'_>) -> Result<Vec<EffectSpec>, ConfigError> {
        let Some(imu) = find(doc, "imu") else {
            return Ok(Vec::new());
        };
        let Some(imu) = imu.as_table() else {
            return Err(self.ctx.invalid("imu", "expected a table"));
        };
        let Some(effects) = find(imu, "effect") else {
            return Ok(Vec::new());
        };
        let Some(items) = effects.as_array() else {
            return Err(self
                .ctx
                .invalid("imu.effect", "expected an array of tables ([[imu.effect]])"));
        };
        items
            .iter()
            .enumerate()
            .map(|(i, item)| {
                let at = format!("imu.effect[{i}]");
                match item.get_ref().as_table() {
                    Some(t) => self.effect(&at, t),
                    None => Err(self.ctx.invalid(&at, "expected a table ([[imu.effect]])")),
                }
            })
            .collect()
    }
}

/// The value of key `name` of `table`.
fn find<'t, 'i>(table: &'t DeTable<'i>, name: &str) -> Option<&'t DeValue<'i>> {
    table
        .iter()
        .find(|(k, _)| k.get_ref() == name)
        .map(|(_, v)| v.get_ref())
}

pub(super) fn parse_doc<'a>(
    src: &'a str,
    origin: &str,
) -> Result<Spanned<DeTable<'a>>, ConfigError> {
    DeTable::parse(src).map_err(|e| {
        // Let the serde path produce the located message for syntax errors.
        match toml_util::from_str::<toml::Table>(src, origin) {
            Err(err) => err,
            Ok(_) => ConfigError::Parse {
                origin: origin.to_owned(),
                line: None,
                column: None,
                key: None,
                message: e.message().trim().to_owned(),
            },
        }
    })
}
