//! The two small CSV tables an experiment can reference: a rotation scheme
//! (`step,axis_x,axis_y,axis_z,angle_deg`) and the vibration patterns of the paper's Table 4
//! (`pattern,axis,amplitude_deg,period_s`). Lines starting with `#` and blank lines are ignored; a
//! header line equal to the column names is optional.

use crate::error::ConfigError;
use sins_nav::{DEG, Vec3};
use std::collections::BTreeMap;

/// One data row: 1-based line number and trimmed fields.
struct Row<'a> {
    line: usize,
    fields: Vec<&'a str>,
}

struct Table<'a> {
    origin: &'a str,
    columns: &'static [&'static str],
}

impl<'a> Table<'a> {
    fn error(&self, line: usize, column: Option<usize>, message: impl Into<String>) -> ConfigError {
        ConfigError::Parse {
            origin: self.origin.to_owned(),
            line: Some(line),
            column: None,
            key: column.map(|c| self.columns[c].to_owned()),
            message: message.into(),
        }
    }

    fn rows<'t>(&self, text: &'t str) -> Result<Vec<Row<'t>>, ConfigError> {
        let mut rows = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let is_header = fields.len() == self.columns.len()
                && fields
                    .iter()
                    .zip(self.columns)
                    .all(|(f, c)| f.eq_ignore_ascii_case(c));
            if is_header {
                continue;
            }
            if fields.len() != self.columns.len() {
                return Err(self.error(
                    i + 1,
                    None,
                    format!(
                        "expected {} columns ({}), found {}",
                        self.columns.len(),
                        self.columns.join(","),
                        fields.len()
                    ),
                ));
            }
            rows.push(Row {
                line: i + 1,
                fields,
            });
        }
        if rows.is_empty() {
            return Err(ConfigError::Parse {
                origin: self.origin.to_owned(),
                line: None,
                column: None,
                key: None,
                message: "the table has no data rows".into(),
            });
        }
        Ok(rows)
    }

    fn number(&self, row: &Row<'_>, column: usize) -> Result<f64, ConfigError> {
        let text = row.fields[column];
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error(
                row.line,
                Some(column),
                format!("expected a finite number, found `{text}`"),
            )),
        }
    }
}

/// One step of a rotation scheme: rotate by `angle_rad` about the unit body axis `axis`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SchemeStep {
    pub(crate) axis: Vec3,
    pub(crate) angle_rad: f64,
}

/// Parses a rotation scheme; steps must be numbered 1, 2, 3, ... with non-zero axes and angles.
pub(crate) fn parse_scheme(text: &str, origin: &str) -> Result<Vec<SchemeStep>, ConfigError> {
    let table = Table {
        origin,
        columns: &["step", "axis_x", "axis_y", "axis_z", "angle_deg"],
    };
    let mut steps = Vec::new();
    for row in table.rows(text)? {
        let expected = steps.len() + 1;
        if row.fields[0].parse::<usize>().ok() != Some(expected) {
            let msg = format!("expected step number {expected}, found `{}`", row.fields[0]);
            return Err(table.error(row.line, Some(0), msg));
        }
        let axis = Vec3::new(
            table.number(&row, 1)?,
            table.number(&row, 2)?,
            table.number(&row, 3)?,
        );
        if axis.norm() == 0.0 {
            return Err(table.error(row.line, Some(1), "the rotation axis is zero"));
        }
        let angle_deg = table.number(&row, 4)?;
        if angle_deg == 0.0 {
            return Err(table.error(row.line, Some(4), "the rotation angle is zero"));
        }
        steps.push(SchemeStep {
            axis: axis.normalize(),
            angle_rad: angle_deg * DEG,
        });
    }
    Ok(steps)
}

/// One angular vibration pattern: amplitude (deg) and period (s) about body x, y, z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct VibrationPattern {
    pub(crate) amplitude_deg: [f64; 3],
    pub(crate) period_s: [f64; 3],
}

/// Parses the vibration-pattern table; every pattern needs exactly one row per axis x, y, z with
/// a non-negative amplitude and a positive period.
pub(crate) fn parse_patterns(
    text: &str,
    origin: &str,
) -> Result<BTreeMap<u32, VibrationPattern>, ConfigError> {
    let table = Table {
        origin,
        columns: &["pattern", "axis", "amplitude_deg", "period_s"],
    };
    let mut seen: BTreeMap<u32, ([bool; 3], VibrationPattern, usize)> = BTreeMap::new();
    for row in table.rows(text)? {
        let Ok(pattern) = row.fields[0].parse::<u32>() else {
            let msg = format!("expected a pattern number, found `{}`", row.fields[0]);
            return Err(table.error(row.line, Some(0), msg));
        };
        let axis = match row.fields[1] {
            "x" | "X" => 0,
            "y" | "Y" => 1,
            "z" | "Z" => 2,
            other => {
                return Err(table.error(
                    row.line,
                    Some(1),
                    format!("expected x, y or z, found `{other}`"),
                ));
            }
        };
        let amplitude = table.number(&row, 2)?;
        if amplitude < 0.0 {
            return Err(table.error(row.line, Some(2), "the amplitude must be >= 0"));
        }
        let period = table.number(&row, 3)?;
        if period <= 0.0 {
            return Err(table.error(row.line, Some(3), "the period must be positive"));
        }
        let empty = VibrationPattern {
            amplitude_deg: [0.0; 3],
            period_s: [0.0; 3],
        };
        let entry = seen.entry(pattern).or_insert(([false; 3], empty, row.line));
        if entry.0[axis] {
            return Err(table.error(
                row.line,
                Some(1),
                format!("pattern {pattern} lists axis {} twice", row.fields[1]),
            ));
        }
        entry.0[axis] = true;
        entry.1.amplitude_deg[axis] = amplitude;
        entry.1.period_s[axis] = period;
    }
    let mut patterns = BTreeMap::new();
    for (pattern, (axes, p, line)) in seen {
        if axes.iter().any(|a| !a) {
            return Err(table.error(
                line,
                Some(1),
                format!("pattern {pattern} needs one row for each axis x, y, z"),
            ));
        }
        patterns.insert(pattern, p);
    }
    Ok(patterns)
}
