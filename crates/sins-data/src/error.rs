//! The error type of dataset I/O: every variant names the file and, where it applies, the row,
//! line, column or metadata key, so a message is actionable without a debugger.

use std::fmt;
use std::path::{Path, PathBuf};

/// Position of a data row in a dataset: the 0-based data row index and, for CSV files, the
/// 1-based line number in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowRef {
    /// 0-based index of the data row (the header and comment lines are not counted).
    pub row: u64,
    /// 1-based line number in a CSV file; `None` for Parquet files and for writers.
    pub line: Option<u64>,
}

impl RowRef {
    /// A row of a Parquet file or of a batch handed to a writer (no line number).
    pub fn row(row: u64) -> Self {
        Self { row, line: None }
    }

    /// A row of a CSV file at the given 1-based line.
    pub fn csv(row: u64, line: u64) -> Self {
        Self {
            row,
            line: Some(line),
        }
    }
}

impl fmt::Display for RowRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "row {} (line {line})", self.row),
            None => write!(f, "row {}", self.row),
        }
    }
}

/// Everything that can go wrong reading or writing a sinsbench dataset. `file` is always the
/// dataset path the user asked for (never an internal temporary name).
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    /// An operating-system I/O error while `action` (e.g. "opening", "renaming into place").
    #[error("{}: I/O error while {action}: {source}", file.display())]
    Io {
        /// The dataset file.
        file: PathBuf,
        /// What was being done.
        action: &'static str,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The file is neither a Parquet file (no `PAR1` magic) nor a sinsbench CSV file.
    #[error("{}: not a sinsbench dataset: {reason}", file.display())]
    NotADataset {
        /// The file.
        file: PathBuf,
        /// Why it was rejected.
        reason: String,
    },
    /// The file starts like a Parquet file but its structure cannot be decoded (for example it
    /// was truncated, so the footer is missing).
    #[error("{}: corrupt or truncated Parquet file: {reason}", file.display())]
    CorruptParquet {
        /// The file.
        file: PathBuf,
        /// What the decoder reported.
        reason: String,
    },
    /// A malformed CSV line (wrong number of fields, bad quoting, invalid UTF-8, ...).
    #[error("{}: line {line}: malformed CSV: {reason}", file.display())]
    MalformedCsv {
        /// The file.
        file: PathBuf,
        /// 1-based line number.
        line: u64,
        /// What is wrong.
        reason: String,
    },
    /// The file extension does not select a format (only `.parquet` and `.csv` are written).
    #[error("{}: unsupported dataset extension (expected .parquet or .csv)", file.display())]
    UnsupportedExtension {
        /// The file.
        file: PathBuf,
    },
    /// A required column is absent.
    #[error("{}: missing required column '{column}'", file.display())]
    MissingColumn {
        /// The file.
        file: PathBuf,
        /// The missing column.
        column: String,
    },
    /// A column appears twice in the header or schema.
    #[error("{}: duplicate column '{column}'", file.display())]
    DuplicateColumn {
        /// The file.
        file: PathBuf,
        /// The repeated column.
        column: String,
    },
    /// Only part of an all-or-nothing column group (temperature or reference) is present.
    #[error(
        "{}: partial {group} column group: has {present:?} but is missing {missing:?} (give all or none)",
        file.display()
    )]
    PartialColumnGroup {
        /// The file.
        file: PathBuf,
        /// `"temperature"` or `"reference"`.
        group: &'static str,
        /// Group columns found.
        present: Vec<String>,
        /// Group columns not found.
        missing: Vec<String>,
    },
    /// A column has the wrong data type.
    #[error("{}: column '{column}' has type {found}, expected {expected}", file.display())]
    WrongColumnType {
        /// The file.
        file: PathBuf,
        /// The column.
        column: String,
        /// The required type.
        expected: &'static str,
        /// The type found in the file.
        found: String,
    },
    /// A required metadata key is absent.
    #[error("{}: missing metadata key '{key}'", file.display())]
    MissingMetadata {
        /// The file.
        file: PathBuf,
        /// The missing key.
        key: String,
    },
    /// A metadata key is present but its value is unusable.
    #[error("{}: metadata key '{key}' = {value:?} is invalid: {reason}", file.display())]
    InvalidMetadata {
        /// The file.
        file: PathBuf,
        /// The key.
        key: String,
        /// The value found.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
    /// The dataset's schema version is not understood by this build.
    #[error(
        "{}: unsupported schema version {found} (sinsbench.schema_version; this build reads version {supported})",
        file.display()
    )]
    UnsupportedSchemaVersion {
        /// The file.
        file: PathBuf,
        /// The version in the file.
        found: u32,
        /// The version this build reads and writes.
        supported: u32,
    },
    /// A cell could not be parsed as a number (CSV) or is null (Parquet).
    #[error("{}: {at}, column '{column}': cannot read value {text:?}: {reason}", file.display())]
    BadValue {
        /// The file.
        file: PathBuf,
        /// Where.
        at: RowRef,
        /// The column.
        column: String,
        /// The cell text (`""` for a Parquet null).
        text: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// A value is NaN or infinite.
    #[error("{}: {at}, column '{column}': value {value} is not finite", file.display())]
    NonFinite {
        /// The file.
        file: PathBuf,
        /// Where.
        at: RowRef,
        /// The column.
        column: String,
        /// The offending value.
        value: f64,
    },
    /// A value lies outside what a real IMU on the Earth can produce (an increment beyond the
    /// full scale of a navigation-grade sensor over one sample, a temperature outside
    /// -60..125 degC, a position off the Earth).
    #[error(
        "{}: {at}, column '{column}': value {value} is implausible ({why})",
        file.display()
    )]
    Implausible {
        /// The file.
        file: PathBuf,
        /// Where.
        at: RowRef,
        /// The column.
        column: String,
        /// The offending value (column unit).
        value: f64,
        /// The accepted range and why it is what it is.
        why: String,
    },
    /// `t_s` does not strictly increase.
    #[error(
        "{}: {at}: t_s = {t_s} s is not after the previous row's t_s = {prev_t_s} s (t_s must strictly increase)",
        file.display()
    )]
    TimeNotIncreasing {
        /// The file.
        file: PathBuf,
        /// The later of the two rows.
        at: RowRef,
        /// `t_s` of the previous row (s).
        prev_t_s: f64,
        /// `t_s` of this row (s).
        t_s: f64,
    },
    /// A step of `t_s` differs from the sample interval 1/rate (missing samples or jitter).
    #[error(
        "{}: {at}: gap in t_s: step from the previous row is {} s, expected {} s \
         (1/sample_rate_hz; steps within 45 % of it are taken as jitter); dropped samples are \
         bridged by `sinsbench import`",
        file.display(), short(.step_s), short(.expected_step_s)
    )]
    TimeGap {
        /// The file.
        file: PathBuf,
        /// The row after the gap.
        at: RowRef,
        /// The step found (s).
        step_s: f64,
        /// The expected step 1/rate (s).
        expected_step_s: f64,
    },
    /// The first `t_s` step disagrees with `sinsbench.sample_rate_hz`.
    #[error(
        "{}: {at}: metadata says {meta_rate_hz} Hz (sinsbench.sample_rate_hz) but t_s advances {} s per row ({} Hz)",
        file.display(), short(.step_s), short(.implied_rate_hz)
    )]
    SampleRateMismatch {
        /// The file.
        file: PathBuf,
        /// The second row of the file.
        at: RowRef,
        /// Rate from the metadata (Hz).
        meta_rate_hz: f64,
        /// First step of `t_s` (s).
        step_s: f64,
        /// 1 / step (Hz).
        implied_rate_hz: f64,
    },
    /// A segment value is not among the labels (reader) or a segment index is out of range
    /// (writer).
    #[error("{}: {at}, column 'segment': {reason}", file.display())]
    BadSegment {
        /// The file.
        file: PathBuf,
        /// Where.
        at: RowRef,
        /// What is wrong.
        reason: String,
    },
    /// The dataset has no data rows.
    #[error("{}: empty dataset (no data rows)", file.display())]
    Empty {
        /// The file.
        file: PathBuf,
    },
    /// The writer was used inconsistently (batch columns do not match the declared
    /// [`crate::ColumnSet`], bad labels or metadata, use after an earlier error, ...).
    #[error("{}: invalid write: {reason}", file.display())]
    InvalidWrite {
        /// The file being written.
        file: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// Polars reported an error (used by the DataFrame helpers).
    #[cfg(feature = "polars")]
    #[error("{}: {source}", file.display())]
    Polars {
        /// The file.
        file: PathBuf,
        /// The polars error.
        #[source]
        source: polars::prelude::PolarsError,
    },
}

/// `x` rounded to 9 significant digits, printed in shortest form (0.009999999999999995 -> 0.01).
fn short(x: &f64) -> String {
    let x = *x;
    format!("{:.8e}", x)
        .parse::<f64>()
        .map_or_else(|_| x.to_string(), |r| r.to_string())
}

impl DataError {
    /// The dataset file the error is about.
    pub fn file(&self) -> &Path {
        match self {
            Self::Io { file, .. }
            | Self::NotADataset { file, .. }
            | Self::CorruptParquet { file, .. }
            | Self::MalformedCsv { file, .. }
            | Self::UnsupportedExtension { file }
            | Self::MissingColumn { file, .. }
            | Self::DuplicateColumn { file, .. }
            | Self::PartialColumnGroup { file, .. }
            | Self::WrongColumnType { file, .. }
            | Self::MissingMetadata { file, .. }
            | Self::InvalidMetadata { file, .. }
            | Self::UnsupportedSchemaVersion { file, .. }
            | Self::BadValue { file, .. }
            | Self::NonFinite { file, .. }
            | Self::Implausible { file, .. }
            | Self::TimeNotIncreasing { file, .. }
            | Self::TimeGap { file, .. }
            | Self::SampleRateMismatch { file, .. }
            | Self::BadSegment { file, .. }
            | Self::Empty { file }
            | Self::InvalidWrite { file, .. } => file,
            #[cfg(feature = "polars")]
            Self::Polars { file, .. } => file,
        }
    }

    pub(crate) fn io(file: &Path, action: &'static str, source: std::io::Error) -> Self {
        Self::Io {
            file: file.to_path_buf(),
            action,
            source,
        }
    }

    pub(crate) fn corrupt(file: &Path, reason: impl fmt::Display) -> Self {
        Self::CorruptParquet {
            file: file.to_path_buf(),
            reason: reason.to_string(),
        }
    }

    pub(crate) fn invalid_write(file: &Path, reason: impl Into<String>) -> Self {
        Self::InvalidWrite {
            file: file.to_path_buf(),
            reason: reason.into(),
        }
    }
}
