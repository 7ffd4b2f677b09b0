//! Errors of the gap tools.

use std::path::PathBuf;

/// What can go wrong in `diagnose` or `blind`.
#[derive(Debug, thiserror::Error)]
pub enum GapError {
    /// A dataset failed to open or read.
    #[error(transparent)]
    Data(#[from] sins_data::DataError),
    /// A parameter or experiment file failed to load.
    #[error(transparent)]
    Config(#[from] sins_config::ConfigError),
    /// The diagnosis failed.
    #[error(transparent)]
    Diag(#[from] sins_diag::DiagError),
    /// Writing the outputs failed.
    #[error(transparent)]
    Report(#[from] sins_report::ReportError),
    /// Simulation or calibration of a blind case failed.
    #[error(transparent)]
    Harness(#[from] sins_harness::HarnessError),
    /// A file operation failed.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The inputs do not fit together, or a sealed manifest was tampered with.
    #[error("{0}")]
    Invalid(String),
}

impl GapError {
    /// An I/O error at `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
