//! The release-gate thresholds file (TOML, `schema = 1`); the layout is documented in
//! `sins_harness::gate`.

use super::{malformed, parse_toml, read_text};
use sins_harness::HarnessError;
use sins_harness::gate::{THRESHOLDS_SCHEMA, Thresholds};
use std::path::Path;

/// Read a thresholds file (limits in nmi and %) and validate it; errors name the file, line and
/// key.
pub fn load_thresholds(path: &Path) -> Result<Thresholds, HarnessError> {
    let text = read_text(path)?;
    let t: Thresholds = parse_toml(path, &text)?;
    if t.schema != THRESHOLDS_SCHEMA {
        return Err(malformed(
            path,
            format!(
                "key 'schema' is {}, this build reads {THRESHOLDS_SCHEMA}",
                t.schema
            ),
        ));
    }
    t.validate().map_err(|m| malformed(path, m))?;
    Ok(t)
}
