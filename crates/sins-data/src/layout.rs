//! Matching a file's column names against the format: which groups are present and where.

use std::collections::HashSet;
use std::path::Path;

use crate::error::DataError;
use crate::schema::{
    ColumnSet, REFERENCE_COLUMNS, REQUIRED_COLUMNS, SEGMENT_COLUMN, TEMPERATURE_COLUMNS,
};

/// Where the format's columns sit in a file's column list.
#[derive(Clone, Debug)]
pub(crate) struct Layout {
    /// Optional groups present.
    pub columns: ColumnSet,
    /// Position in the file of each column of `columns.float_columns()`, in that order.
    pub float_pos: Vec<usize>,
    /// Position of the `segment` column.
    pub segment_pos: Option<usize>,
    /// Names present in the file that the format does not define.
    pub ignored: Vec<String>,
}

/// Resolve `names` (the file's columns in file order) into a [`Layout`], rejecting duplicates,
/// missing required columns and partial groups.
pub(crate) fn resolve_layout(file: &Path, names: &[String]) -> Result<Layout, DataError> {
    let mut seen = HashSet::new();
    for name in names {
        if !seen.insert(name.as_str()) {
            return Err(DataError::DuplicateColumn {
                file: file.to_path_buf(),
                column: name.clone(),
            });
        }
    }
    let pos = |col: &str| names.iter().position(|n| n == col);
    for col in REQUIRED_COLUMNS {
        if pos(col).is_none() {
            return Err(DataError::MissingColumn {
                file: file.to_path_buf(),
                column: col.to_string(),
            });
        }
    }
    let temperature = group_present(file, "temperature", &TEMPERATURE_COLUMNS, &pos)?;
    let reference = group_present(file, "reference", &REFERENCE_COLUMNS, &pos)?;
    let segment_pos = pos(SEGMENT_COLUMN);
    let columns = ColumnSet {
        temperature,
        segment: segment_pos.is_some(),
        reference,
    };
    let float_pos = columns
        .float_columns()
        .iter()
        .filter_map(|c| pos(c))
        .collect();
    let known = columns.all_columns();
    let ignored = names
        .iter()
        .filter(|n| !known.contains(&n.as_str()))
        .cloned()
        .collect();
    Ok(Layout {
        columns,
        float_pos,
        segment_pos,
        ignored,
    })
}

fn group_present(
    file: &Path,
    group: &'static str,
    cols: &[&str],
    pos: &dyn Fn(&str) -> Option<usize>,
) -> Result<bool, DataError> {
    let (present, missing): (Vec<&str>, Vec<&str>) = cols.iter().partition(|c| pos(c).is_some());
    if present.is_empty() {
        return Ok(false);
    }
    if missing.is_empty() {
        return Ok(true);
    }
    Err(DataError::PartialColumnGroup {
        file: file.to_path_buf(),
        group,
        present: present.iter().map(|s| s.to_string()).collect(),
        missing: missing.iter().map(|s| s.to_string()).collect(),
    })
}
