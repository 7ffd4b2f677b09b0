//! `summary.json` of a report (written by `sins-report`, read by `sinsbench gate`):
//! [`summary_to_json`] writes a [`Summary`] as pretty JSON and [`read_summary`] reads one back,
//! checking its layout version and its maxima.

use super::{malformed, read_text};
use sins_harness::HarnessError;
use sins_harness::summary::{SUMMARY_SCHEMA, Summary};
use std::path::Path;

/// `summary` as pretty JSON (errors in nmi and m, times in s and h, as the fields say).
pub fn summary_to_json(summary: &Summary) -> String {
    // Serialising plain structs of numbers and strings cannot fail.
    serde_json::to_string_pretty(summary).unwrap_or_default()
}

/// Read a `summary.json`; errors name the file, line and field.
pub fn read_summary(path: &Path) -> Result<Summary, HarnessError> {
    let text = read_text(path)?;
    let s: Summary = serde_json::from_str(&text)
        .map_err(|e| malformed(path, format!("not a sinsbench summary: {e}")))?;
    check_summary(&s).map_err(|m| malformed(path, m))?;
    Ok(s)
}

/// The layout version is this build's and every maximum horizontal error is a finite number of
/// nautical miles >= 0; the message names the field.
fn check_summary(s: &Summary) -> Result<(), String> {
    if s.schema != SUMMARY_SCHEMA {
        return Err(format!(
            "key 'schema' is {}, this build reads {SUMMARY_SCHEMA}",
            s.schema
        ));
    }
    for e in &s.experiments {
        for (set, r) in &e.results {
            if !r.max_horizontal_nmi.is_finite() || r.max_horizontal_nmi < 0.0 {
                return Err(format!(
                    "experiments['{}'].results['{set}'].max_horizontal_nmi is {} (must be a finite number >= 0)",
                    e.name, r.max_horizontal_nmi
                ));
            }
        }
    }
    Ok(())
}
