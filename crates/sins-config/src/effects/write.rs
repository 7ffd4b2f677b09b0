//! Writing effect specs as `[[imu.effect]]` tables in paper-style units, bit-exact on reading back.

use super::schema::{Aux, get_aux, magnitude_factor, schema};
use crate::exact::format_exact;
use crate::toml_util::quote;
use sins_imu::EffectSpec;
use std::fmt::Write as _;

/// Writes `specs` as `[[imu.effect]]` tables in paper-style units (every key, defaults
/// included), the shortest decimals that [`super::parse_effects_toml`] reads back to the identical SI
/// doubles. Pasted under an experiment's `[imu]` table they switch the effects on.
pub fn effects_to_toml(specs: &[EffectSpec]) -> String {
    let mut out = String::new();
    for (n, spec) in specs.iter().enumerate() {
        let kind = spec.kind();
        let (mag_keys, auxes) = schema(kind);
        if n > 0 {
            out.push('\n');
        }
        let _ = writeln!(out, "[[imu.effect]]");
        let _ = writeln!(out, "kind = {}", quote(kind.name()));
        let mags = spec.magnitudes_si();
        let factor = magnitude_factor(kind);
        for (i, key) in mag_keys.iter().enumerate() {
            let values: Vec<String> = mags[3 * i..3 * i + 3]
                .iter()
                .map(|&x| format_exact(x, factor))
                .collect();
            let _ = writeln!(
                out,
                "{key} = [{}]  # {}",
                values.join(", "),
                kind.unit().label
            );
        }
        for &aux in auxes {
            let (x, seed) = get_aux(spec, aux);
            let text = match aux {
                Aux::Seed => seed.to_string(),
                _ if x == f64::INFINITY => "inf".to_owned(),
                _ => format_exact(x, aux.factor()),
            };
            let _ = writeln!(out, "{} = {text}", aux.key());
        }
    }
    out
}
