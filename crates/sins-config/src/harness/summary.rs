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

/// Read the reports of a `reports` campaign (its `summary.json`, `{"reports": [...]}`, or the
/// campaign directory that holds it), each checked as [`read_summary`] checks one; a single
/// report's `summary.json` reads as a list of one. Errors name the file and the report.
pub fn read_report_list(path: &Path) -> Result<Vec<Summary>, HarnessError> {
    let file = if path.is_dir() {
        path.join("summary.json")
    } else {
        path.to_path_buf()
    };
    let text = read_text(&file)?;
    #[derive(serde::Deserialize)]
    struct List {
        reports: Vec<Summary>,
    }
    let list = match serde_json::from_str::<List>(&text) {
        Ok(l) => l.reports,
        Err(list_error) => match serde_json::from_str::<Summary>(&text) {
            Ok(one) => vec![one],
            Err(_) => {
                return Err(malformed(
                    &file,
                    format!(
                        "neither a `reports` campaign's summary nor a report's summary:                          {list_error}"
                    ),
                ));
            }
        },
    };
    for (i, s) in list.iter().enumerate() {
        check_summary(s).map_err(|m| malformed(&file, format!("reports[{i}]: {m}")))?;
    }
    Ok(list)
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
