//! The paper's Table 5 as a small CSV file
//! (`experiments/reference/table5_navigation_results.csv`).

use super::{malformed, read_text};
use sins_harness::HarnessError;
use sins_harness::reference::PaperRow;
use std::path::Path;

/// Read Table 5 (`experiment,with_nmi,without_nmi,improvement_percent`, errors in nmi and
/// improvement in %; `#` comments and blank lines are skipped); errors name the file and line.
pub fn load_table5(path: &Path) -> Result<Vec<PaperRow>, HarnessError> {
    let text = read_text(path)?;
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let row =
            parse_row(line).map_err(|what| malformed(path, format!("line {}: {what}", i + 1)))?;
        rows.push(row);
    }
    Ok(rows)
}

/// One data line; the error says which field is wrong.
fn parse_row(line: &str) -> Result<PaperRow, String> {
    let f: Vec<&str> = line.split(',').map(str::trim).collect();
    if f.len() != 4 {
        return Err(format!("expected 4 fields, found {}", f.len()));
    }
    let num = |k: usize, name: &str| -> Result<f64, String> {
        f[k].parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{name} '{}' is not a number", f[k]))
    };
    Ok(PaperRow {
        experiment: f[0]
            .parse()
            .map_err(|_| format!("experiment '{}' is not a whole number", f[0]))?,
        with_compensation_nmi: num(1, "with_temperature_compensation_nmi")?,
        without_compensation_nmi: num(2, "without_temperature_compensation_nmi")?,
        improvement_percent: num(3, "improvement_percent")?,
    })
}
