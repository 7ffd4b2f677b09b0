//! `[[imu.effect]]` tables: effects outside the paper's model in paper-style units, read into SI
//! [`EffectSpec`]s and written back bit-exactly.
//!
//! Every table has `kind` (a [`sins_imu::EffectKind::name`]), the magnitude key(s) of that kind
//! (three values `[x, y, z]` in the unit the key names; the size effect has one lever-arm key per
//! accelerometer) and the kind's auxiliary keys ([`schema`]). Numbers are converted from their
//! decimal text with one correct rounding (the SI factor being the `f64` of
//! [`sins_imu::EffectKind::unit`]), and [`effects_to_toml`] writes the shortest decimals that read
//! back to the identical doubles.

mod read;
mod schema;
mod write;

use crate::ctx::Ctx;
use crate::error::ConfigError;
use read::{Reader, parse_doc};
use sins_imu::EffectSpec;
use std::path::Path;
pub use write::effects_to_toml;

/// One `[[imu.effect]]` table as seen by the experiment's structural pass (any value); the
/// tables are converted from the source text by [`build_effects`].
pub(crate) type EffectFile = serde::de::IgnoredAny;

/// Convert the `[[imu.effect]]` tables of the experiment source `src` (whose structural pass gave
/// `files`) to SI specs, naming `imu.effect[i].<key>` (with its line) on any problem.
pub(crate) fn build_effects(
    ctx: &Ctx<'_>,
    src: &str,
    files: &[EffectFile],
) -> Result<Vec<EffectSpec>, ConfigError> {
    let doc = parse_doc(src, &ctx.origin)?;
    let specs = Reader { ctx }.all(doc.get_ref())?;
    if specs.len() != files.len() {
        let msg = format!("found {} tables, expected {}", specs.len(), files.len());
        return Err(ctx.invalid("imu.effect", msg));
    }
    Ok(specs)
}

/// Reads the `[[imu.effect]]` tables of a TOML document (an experiment file, or a document holding
/// only effects such as [`effects_to_toml`] writes) into SI specs; other keys of the document are
/// ignored. `origin` names the source in errors (usually the path). Errors name the key
/// (`imu.effect[1].delay_ms[2]`), its line and what is wrong: unknown kind or key, missing key,
/// wrong type or length, non-finite value, non-positive period or correlation time, bad seed.
pub fn parse_effects_toml(text: &str, origin: &str) -> Result<Vec<EffectSpec>, ConfigError> {
    let ctx = Ctx::new(Path::new(origin), text);
    let doc = parse_doc(text, origin)?;
    Reader { ctx: &ctx }.all(doc.get_ref())
}
