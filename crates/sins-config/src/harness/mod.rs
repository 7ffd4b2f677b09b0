//! The input files of the navigation harness, read into the types of `sins-harness`: the report
//! configuration ([`load_report_config`]), the release-gate thresholds ([`load_thresholds`]) and
//! the paper's Table 5 ([`load_table5`]), and the report's `summary.json` in both directions
//! ([`summary_to_json`], [`read_summary`]). Errors are [`HarnessError`]s naming the file and the
//! key or line at fault.

mod report_config;
mod summary;
mod table5;
mod thresholds;

pub use report_config::load_report_config;
pub use summary::{read_report_list, read_summary, summary_to_json};
pub use table5::load_table5;
pub use thresholds::load_thresholds;

use sins_harness::HarnessError;
use std::path::Path;

/// The whole text of `path`; the error names the file.
fn read_text(path: &Path) -> Result<String, HarnessError> {
    std::fs::read_to_string(path).map_err(|source| HarnessError::Io {
        path: path.to_owned(),
        source,
    })
}

/// `path` is malformed: `message` names the key or line.
fn malformed(path: &Path, message: String) -> HarnessError {
    HarnessError::Malformed {
        path: path.to_owned(),
        message,
    }
}

/// Parse TOML text read from `path` into `T`; the error names the file, line and key.
fn parse_toml<T: serde::de::DeserializeOwned>(path: &Path, text: &str) -> Result<T, HarnessError> {
    toml::from_str(text).map_err(|e| malformed(path, e.to_string().trim().to_string()))
}
