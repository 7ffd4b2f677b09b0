//! The paper's Table 5 (maximum horizontal error of its three 15 h experiments with and without
//! temperature compensation) as data: `experiments/reference/table5_navigation_results.csv`.

use crate::HarnessError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One row of the paper's Table 5.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperRow {
    /// Experiment number (1-based).
    pub experiment: u32,
    /// Maximum horizontal error with temperature compensation (nmi).
    pub with_compensation_nmi: f64,
    /// Maximum horizontal error without it (nmi).
    pub without_compensation_nmi: f64,
    /// Improvement (%).
    pub improvement_percent: f64,
}

/// Read Table 5 (`experiment,with_nmi,without_nmi,improvement_percent`, `#` comments).
pub fn load_table5(path: &Path) -> Result<Vec<PaperRow>, HarnessError> {
    let text = std::fs::read_to_string(path).map_err(|source| HarnessError::Io {
        path: path.to_owned(),
        source,
    })?;
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let bad = |what: String| HarnessError::Malformed {
            path: path.to_owned(),
            message: format!("line {}: {what}", i + 1),
        };
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() != 4 {
            return Err(bad(format!("expected 4 fields, found {}", f.len())));
        }
        let num = |k: usize, name: &str| -> Result<f64, HarnessError> {
            f[k].parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(format!("{name} '{}' is not a number", f[k])))
        };
        rows.push(PaperRow {
            experiment: f[0]
                .parse()
                .map_err(|_| bad(format!("experiment '{}' is not a whole number", f[0])))?,
            with_compensation_nmi: num(1, "with_temperature_compensation_nmi")?,
            without_compensation_nmi: num(2, "without_temperature_compensation_nmi")?,
            improvement_percent: num(3, "improvement_percent")?,
        });
    }
    Ok(rows)
}
