//! CSV writer: `# key = value` metadata comment lines, a header row, then one line per sample.
//! Floats use Rust's shortest round-trip formatting, so values survive bit-exactly.

use std::fmt::Write as _;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::DataError;
use crate::schema::ColumnSet;

/// Escape a metadata value for a single comment line (`\` -> `\\`, newline -> `\n`, CR -> `\r`).
pub(crate) fn escape_meta_value(v: &str) -> String {
    let mut out = String::with_capacity(v.len());
    for c in v.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            c => out.push(c),
        }
    }
    out
}

/// Append `x` in shortest round-trip form: plain decimal for moderate magnitudes, otherwise
/// scientific notation (both parse back to the identical f64).
#[inline]
pub(crate) fn push_f64(buf: &mut String, x: f64) {
    let a = x.abs();
    let _ = if a == 0.0 || (1e-5..1e16).contains(&a) {
        write!(buf, "{x}")
    } else {
        write!(buf, "{x:e}")
    };
}

/// Quote a segment label when it holds a comma, quote or surrounding whitespace.
fn csv_label(label: &str) -> String {
    let needs_quotes = label.contains([',', '"'])
        || label.starts_with(char::is_whitespace)
        || label.ends_with(char::is_whitespace);
    if needs_quotes {
        format!("\"{}\"", label.replace('"', "\"\""))
    } else {
        label.to_string()
    }
}

/// Streaming CSV writer into an already-created (temporary) file.
pub(crate) struct CsvSink {
    file: PathBuf,
    out: BufWriter<File>,
    line: String,
    labels: Vec<String>,
    /// Number of float columns before the `segment` column.
    n_before_segment: usize,
}

impl CsvSink {
    /// Write the metadata comments and the header. `file` is the user's path (for errors).
    pub fn start(
        file: &Path,
        out: File,
        columns: ColumnSet,
        labels: &[String],
        kv: &[(String, String)],
    ) -> Result<Self, DataError> {
        if let Some(bad) = labels.iter().find(|l| l.contains(['\n', '\r'])) {
            return Err(DataError::invalid_write(
                file,
                format!("segment label {bad:?} contains a line break (not allowed in CSV)"),
            ));
        }
        let mut head = String::new();
        for (k, v) in kv {
            let _ = writeln!(head, "# {k} = {}", escape_meta_value(v));
        }
        head.push_str(&columns.all_columns().join(","));
        head.push('\n');
        let mut out = BufWriter::with_capacity(1 << 20, out);
        out.write_all(head.as_bytes())
            .map_err(|e| DataError::io(file, "writing the CSV header", e))?;
        Ok(Self {
            file: file.to_path_buf(),
            out,
            line: String::with_capacity(512),
            labels: labels.iter().map(|l| csv_label(l)).collect(),
            n_before_segment: if columns.temperature { 10 } else { 7 },
        })
    }

    /// Write one row: floats in `ColumnSet::float_columns` order plus the segment index (already
    /// range-checked) when the column exists.
    pub fn push_row(&mut self, values: &[f64], segment: Option<u16>) -> Result<(), DataError> {
        self.line.clear();
        for (i, &v) in values.iter().enumerate() {
            if i == self.n_before_segment
                && let Some(s) = segment
            {
                let label = self.labels.get(usize::from(s)).map_or("", String::as_str);
                self.line.push_str(label);
                self.line.push(',');
            }
            push_f64(&mut self.line, v);
            self.line.push(',');
        }
        if values.len() == self.n_before_segment
            && let Some(s) = segment
        {
            let label = self.labels.get(usize::from(s)).map_or("", String::as_str);
            self.line.push_str(label);
            self.line.push(',');
        }
        self.line.pop();
        self.line.push('\n');
        self.out
            .write_all(self.line.as_bytes())
            .map_err(|e| DataError::io(&self.file, "writing CSV", e))
    }

    /// Flush and return the (unsynced) file.
    pub fn finish(self) -> Result<File, DataError> {
        let file = self.file;
        self.out
            .into_inner()
            .map_err(|e| DataError::io(&file, "flushing CSV", e.into_error()))
    }
}
