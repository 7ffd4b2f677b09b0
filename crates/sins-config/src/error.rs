//! The error type of every loader in this crate. Each variant names the file (`origin`), the key
//! (dotted path with array indices, e.g. `motion.segment[3].duration_s`) and, for TOML, the line.

use std::path::PathBuf;

/// Everything that can go wrong reading an experiment or parameter file.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// A file could not be read at all.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// A file could not be written.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// The parameter file extension is neither `.toml` nor `.json`.
    #[error("{}: unknown parameter file format (expected a .toml or .json extension)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// Syntax or structure error reported by the TOML / JSON / CSV reader (unknown keys, wrong
    /// types, missing required keys, malformed numbers).
    #[error("{origin}{}: {}{message}", location(*line, *column), key_prefix(key.as_deref()))]
    Parse {
        /// The file (or the origin given by the caller).
        origin: String,
        /// 1-based line, when known.
        line: Option<usize>,
        /// 1-based column, when known.
        column: Option<usize>,
        /// Dotted key path of the offending value, when it could be located.
        key: Option<String>,
        /// What the reader said.
        message: String,
    },
    /// A key that the schema does not know (a misspelling is never silently ignored).
    #[error("{origin}{}: unknown key `{key}` (expected one of: {expected})", location(*line, None))]
    UnknownKey {
        /// The file.
        origin: String,
        /// 1-based line, when known.
        line: Option<usize>,
        /// Dotted key path of the unknown key.
        key: String,
        /// The keys accepted at that place, comma separated.
        expected: String,
    },
    /// A required key is absent.
    #[error("{origin}: missing key `{key}`{}", note_suffix(note))]
    MissingKey {
        /// The file.
        origin: String,
        /// Dotted key path of the missing key.
        key: String,
        /// Why it is required or what it means (may be empty).
        note: String,
    },
    /// A value is well-formed but not acceptable (non-finite, negative duration, zero axis, ...).
    #[error("{origin}{}: `{key}`: {problem}", location(*line, None))]
    Invalid {
        /// The file.
        origin: String,
        /// 1-based line, when known.
        line: Option<usize>,
        /// Dotted key path of the value (or table) at fault.
        key: String,
        /// What is wrong with it.
        problem: String,
    },
    /// The file is of another kind than the one asked for (a parameter set given where a
    /// noise file belongs, ...): `"{path} is {found}, not {expected}"`.
    #[error("{} is {found}, not {expected}", path.display())]
    WrongKind {
        /// The file.
        path: PathBuf,
        /// What it is, e.g. "a parameter set (calibrate's output)".
        found: String,
        /// What was asked for, e.g. "a noise file (noise's output)".
        expected: String,
    },
    /// A key refers to a file that cannot be read.
    #[error(
        "{origin}{}: `{key}` refers to {}, which cannot be read: {source}",
        location(*line, None),
        path.display()
    )]
    MissingReference {
        /// The file holding the reference.
        origin: String,
        /// 1-based line of the reference, when known.
        line: Option<usize>,
        /// Dotted key path of the reference.
        key: String,
        /// The resolved path that was tried.
        path: PathBuf,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// An error inside a file referenced from this one (truth parameters, scheme CSV, ...).
    #[error("{origin}: in the file referenced by `{key}`: {source}")]
    Referenced {
        /// The referencing file.
        origin: String,
        /// Dotted key path of the reference.
        key: String,
        /// The error in the referenced file (it names that file itself).
        #[source]
        source: Box<ConfigError>,
    },
}

fn location(line: Option<usize>, column: Option<usize>) -> String {
    match (line, column) {
        (Some(l), Some(c)) => format!(":{l}:{c}"),
        (Some(l), None) => format!(":{l}"),
        _ => String::new(),
    }
}

fn key_prefix(key: Option<&str>) -> String {
    key.map(|k| format!("`{k}`: ")).unwrap_or_default()
}

fn note_suffix(note: &str) -> String {
    if note.is_empty() {
        String::new()
    } else {
        format!(" ({note})")
    }
}

/// 1-based line and column of byte offset `pos` in `text`.
pub(crate) fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let pos = pos.min(text.len());
    let before = text.get(..pos).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// 1-based line of byte offset `pos` in `text`.
pub(crate) fn line_of(text: &str, pos: usize) -> usize {
    line_col(text, pos).0
}
