//! The paper's Table 1 (simulation presets, estimates, residuals) and Table 3 (temperature
//! coefficients of the real IMU, proposed method vs least squares), read from the project's own
//! copies in `experiments/reference/` (CSV, `#` comments, paper units). Every problem names the
//! file, the line and what is wrong.

use crate::units::{PARAMS, param_index};
use std::path::Path;

/// A reference table could not be read or is malformed.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// The file could not be read.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: String,
        /// The reason.
        source: std::io::Error,
    },
    /// A row (or the table as a whole, line 0) is malformed.
    #[error("{file}, line {line}: {what}")]
    Malformed {
        /// The file.
        file: String,
        /// 1-based line number of the row (0: the table as a whole).
        line: usize,
        /// What is wrong.
        what: String,
    },
}

/// One row of Table 1, in the paper's units.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Table1Row {
    /// Coefficient name as in eq (8), e.g. `"dM_gyx"`.
    pub name: String,
    /// Paper unit, e.g. `"arcsec"`.
    pub unit: String,
    /// Index among the 33 coefficients in the state order of eq (8).
    pub state_index: usize,
    /// Preset (truth) value.
    pub preset: f64,
    /// The paper's estimate.
    pub estimate: f64,
    /// The paper's residual |estimate − preset| as printed.
    pub residual: f64,
    /// Last printed digit of the estimate or residual (e.g. 0.001 for "0.500"): the paper's
    /// residuals are rounded to this.
    pub resolution: f64,
}

/// Table 1: 33 rows in the paper's printed order.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Table1 {
    /// The rows as printed (gyro, accelerometer, temperature groups).
    pub rows: Vec<Table1Row>,
}

impl Table1 {
    /// The row of coefficient `state_index` (eq-8 order, 0..33).
    pub fn by_state(&self, state_index: usize) -> Option<&Table1Row> {
        self.rows.iter().find(|r| r.state_index == state_index)
    }
}

/// One temperature coefficient of Table 3, in the paper's units.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Table3Row {
    /// Coefficient name as in eq (8), e.g. `"TM_ayx"` (Table 3's TM are read in eq-8 order).
    pub name: String,
    /// Paper unit (`ug/degC`, `ppm/degC`, `arcsec/degC`).
    pub unit: String,
    /// Index among the 33 coefficients (21..33).
    pub state_index: usize,
    /// The paper's proposed (42-state) value.
    pub proposed: f64,
    /// The paper's four-temperature least-squares value.
    pub least_squares: f64,
}

/// Table 3: the 12 temperature coefficients in eq-8 order.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Table3 {
    /// TB x/y/z, TK x/y/z, TM in eq-8 order.
    pub rows: Vec<Table3Row>,
}

/// File name of Table 1 inside the reference directory.
pub const TABLE1_FILE: &str = "table1_simulation.csv";
/// File name of Table 3 inside the reference directory.
pub const TABLE3_FILE: &str = "table3_temperature_coefficients.csv";

fn read(path: &Path) -> Result<String, ReferenceError> {
    std::fs::read_to_string(path).map_err(|source| ReferenceError::Io {
        file: path.display().to_string(),
        source,
    })
}

/// Read Table 1 from a file (see [`parse_table1`]).
pub fn load_table1(path: impl AsRef<Path>) -> Result<Table1, ReferenceError> {
    let path = path.as_ref();
    parse_table1(&read(path)?, &path.display().to_string())
}

/// Read Table 3 from a file (see [`parse_table3`]).
pub fn load_table3(path: impl AsRef<Path>) -> Result<Table3, ReferenceError> {
    let path = path.as_ref();
    parse_table3(&read(path)?, &path.display().to_string())
}

/// Non-empty, non-comment lines with their 1-based numbers, split at commas.
fn rows(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(i, l)| {
        let l = l.trim();
        (!l.is_empty() && !l.starts_with('#'))
            .then(|| (i + 1, l.split(',').map(str::trim).collect()))
    })
}

struct Ctx<'a> {
    file: &'a str,
}

impl Ctx<'_> {
    fn err(&self, line: usize, what: impl Into<String>) -> ReferenceError {
        ReferenceError::Malformed {
            file: self.file.to_owned(),
            line,
            what: what.into(),
        }
    }

    fn number(&self, line: usize, column: &str, text: &str) -> Result<f64, ReferenceError> {
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.err(line, format!("{column} \"{text}\" is not a finite number"))),
        }
    }

    fn fields(&self, line: usize, f: &[&str], header: &str) -> Result<(), ReferenceError> {
        let want = header.split(',').count();
        if f.len() == want {
            Ok(())
        } else {
            Err(self.err(
                line,
                format!("{} fields, expected {want} ({header})", f.len()),
            ))
        }
    }

    fn unit(&self, line: usize, k: usize, unit: &str) -> Result<(), ReferenceError> {
        let want = PARAMS[k].unit;
        if unit == want {
            Ok(())
        } else {
            Err(self.err(
                line,
                format!("unit \"{unit}\" of {}, expected \"{want}\"", PARAMS[k].name),
            ))
        }
    }
}

/// Decimal places of a number as printed ("0.00016" → 5, "20" → 0).
fn decimals(text: &str) -> i32 {
    text.split_once('.').map_or(0, |(_, f)| f.len() as i32)
}

/// Parse Table 1: rows `name,unit,preset,estimate,residual` with the coefficient names of
/// eq (8); all 33 exactly once, each in its paper unit. `origin` names the source in errors.
pub fn parse_table1(text: &str, origin: &str) -> Result<Table1, ReferenceError> {
    let cx = Ctx { file: origin };
    let mut out: Vec<Table1Row> = Vec::with_capacity(33);
    for (line, f) in rows(text) {
        cx.fields(line, &f, "name,unit,preset,estimate,residual")?;
        let k = param_index(f[0])
            .ok_or_else(|| cx.err(line, format!("unknown coefficient \"{}\"", f[0])))?;
        if out.iter().any(|r| r.state_index == k) {
            return Err(cx.err(line, format!("{} appears twice", f[0])));
        }
        cx.unit(line, k, f[1])?;
        let preset = cx.number(line, "preset", f[2])?;
        let estimate = cx.number(line, "estimate", f[3])?;
        let residual = cx.number(line, "residual", f[4])?;
        if residual < 0.0 {
            return Err(cx.err(line, format!("residual {residual} is negative")));
        }
        out.push(Table1Row {
            name: f[0].to_owned(),
            unit: f[1].to_owned(),
            state_index: k,
            preset,
            estimate,
            residual,
            resolution: 10f64.powi(-decimals(f[3]).max(decimals(f[4]))),
        });
    }
    if let Some(p) = PARAMS.iter().find(|p| out.iter().all(|r| r.name != p.name)) {
        return Err(cx.err(0, format!("no row for {}", p.name)));
    }
    Ok(Table1 { rows: out })
}

/// Parse Table 3: rows `group,unit,index,proposed,least_squares` with group TB/TK (index
/// x, y, z) or TM (index 1..6 in the state order of eq 8); all 12 exactly once.
pub fn parse_table3(text: &str, origin: &str) -> Result<Table3, ReferenceError> {
    let cx = Ctx { file: origin };
    let mut out: Vec<Table3Row> = Vec::with_capacity(12);
    for (line, f) in rows(text) {
        cx.fields(line, &f, "group,unit,index,proposed,least_squares")?;
        let offset = match (f[0], f[2]) {
            ("TB", "x") => 0,
            ("TB", "y") => 1,
            ("TB", "z") => 2,
            ("TK", "x") => 3,
            ("TK", "y") => 4,
            ("TK", "z") => 5,
            ("TM", i) => match i.parse::<usize>() {
                Ok(n @ 1..=6) => 5 + n,
                _ => return Err(cx.err(line, format!("TM index \"{i}\" is not 1..6"))),
            },
            (g, i) => {
                return Err(cx.err(
                    line,
                    format!("group/index \"{g}\"/\"{i}\" is not TB|TK with x|y|z or TM with 1..6"),
                ));
            }
        };
        let k = 21 + offset;
        if out.iter().any(|r| r.state_index == k) {
            return Err(cx.err(line, format!("{} appears twice", PARAMS[k].name)));
        }
        cx.unit(line, k, f[1])?;
        out.push(Table3Row {
            name: PARAMS[k].name.to_owned(),
            unit: f[1].to_owned(),
            state_index: k,
            proposed: cx.number(line, "proposed", f[3])?,
            least_squares: cx.number(line, "least_squares", f[4])?,
        });
    }
    if let Some(p) = PARAMS[21..]
        .iter()
        .find(|p| out.iter().all(|r| r.name != p.name))
    {
        return Err(cx.err(0, format!("no row for {}", p.name)));
    }
    out.sort_by_key(|r| r.state_index);
    Ok(Table3 { rows: out })
}
