//! Errors of an import: each names the file and the key, line, record or byte offset.

use std::fmt;
use std::path::PathBuf;

/// Where in a source file a record sits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SourcePos {
    /// 0-based index of the data record.
    pub record: u64,
    /// 1-based line (text formats).
    pub line: Option<u64>,
    /// Byte offset of the record's first byte (binary format; for gzip sources, in the
    /// decompressed stream).
    pub byte: Option<u64>,
}

impl fmt::Display for SourcePos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, self.byte) {
            (Some(l), _) => write!(f, "line {l} (record {})", self.record),
            (None, Some(b)) => write!(f, "byte offset {b} (record {})", self.record),
            (None, None) => write!(f, "record {}", self.record),
        }
    }
}

/// Everything that can go wrong reading a recording.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The description file is malformed or inconsistent.
    #[error("{}: {key}: {reason}", file.display())]
    Description {
        /// The description file (or the source, for the PSINS header).
        file: PathBuf,
        /// The key (e.g. `gyro.unit`) or the position in the file.
        key: String,
        /// What is wrong and what to do.
        reason: String,
    },
    /// A record of the source cannot be read.
    #[error("{}: {at}: {reason}", file.display())]
    Record {
        /// The source file.
        file: PathBuf,
        /// Where.
        at: SourcePos,
        /// What is wrong.
        reason: String,
    },
    /// A field of a record is not a usable number.
    #[error("{}: {at}: {column}: '{text}' {reason}", file.display())]
    Value {
        /// The source file.
        file: PathBuf,
        /// Where.
        at: SourcePos,
        /// The column (as the description names it).
        column: Box<str>,
        /// The text found.
        text: Box<str>,
        /// Why it was refused.
        reason: &'static str,
    },
    /// Time stamps go backwards (or repeat).
    #[error(
        "{}: {at}: time stamp {t_s} s is not after the previous record's {prev_t_s} s \
         (record {prev_record}); stamps must increase",
        file.display()
    )]
    TimeBackwards {
        /// The source file.
        file: PathBuf,
        /// The record that goes back.
        at: SourcePos,
        /// The previous record's index.
        prev_record: u64,
        /// Its time (s).
        prev_t_s: f64,
        /// This record's time (s).
        t_s: f64,
    },
    /// A gap longer than the bridge limit with `on_gap = "refuse"`.
    #[error(
        "{}: {at}: {missing} samples missing before this record (t = {t_s} s, previous \
         {prev_t_s} s): more than time.max_bridge_samples = {limit}; set time.on_gap = \
         \"split\" to import the stretches either side as separate datasets, or raise the limit",
        file.display()
    )]
    Gap {
        /// The source file.
        file: PathBuf,
        /// The record after the gap.
        at: SourcePos,
        /// Samples missing.
        missing: u64,
        /// The previous record's time (s).
        prev_t_s: f64,
        /// This record's time (s).
        t_s: f64,
        /// The bridge limit.
        limit: u64,
    },
    /// An operating-system I/O error.
    #[error("{}: I/O error while {action}: {source}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// What was being done.
        action: &'static str,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// Writing the dataset failed (its own error names the output file and row).
    #[error(transparent)]
    Data(#[from] sins_data::DataError),
}

impl ImportError {
    /// A description error.
    pub(crate) fn desc(file: &std::path::Path, key: &str, reason: impl Into<String>) -> Self {
        Self::Description {
            file: file.to_path_buf(),
            key: key.to_string(),
            reason: reason.into(),
        }
    }
}
