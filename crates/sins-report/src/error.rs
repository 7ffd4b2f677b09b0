//! Errors of the report.

use std::path::PathBuf;

/// What can go wrong while running or writing a report.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The harness (configuration, simulation, calibration, replay) failed.
    #[error(transparent)]
    Harness(#[from] sins_harness::HarnessError),
    /// A parameter or experiment file failed to load.
    #[error(transparent)]
    Config(#[from] sins_config::ConfigError),
    /// A dataset failed to read, or a track failed to write.
    #[error(transparent)]
    Data(#[from] sins_data::DataError),
    /// A Rerun recording failed to write.
    #[error(transparent)]
    Viz(#[from] sins_viz::VizError),
    /// A file or directory operation failed.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A polars operation failed.
    #[error("{what}: {source}")]
    Polars {
        /// What was being built.
        what: String,
        /// The polars error.
        source: polars::error::PolarsError,
    },
    /// An existing path where an output goes is not a previous output of the command; it is
    /// left untouched.
    #[error(
        "{path}: {why}; sinsbench leaves it untouched: choose another output directory or remove it"
    )]
    Refused {
        /// The existing path.
        path: PathBuf,
        /// What it is.
        why: String,
    },
    /// The inputs do not fit together.
    #[error("{0}")]
    Mismatch(String),
}

impl ReportError {
    /// An I/O error at `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
