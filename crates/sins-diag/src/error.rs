//! Errors of the diagnosis.

use sins_nav::AlignmentError;
use sins_replay::ReplayError;

/// Everything that can stop a diagnosis.
#[derive(Debug, thiserror::Error)]
pub enum DiagError {
    /// The input is unusable (named run and reason).
    #[error("run '{run}': {reason}")]
    Input {
        /// Run name (empty for the whole input).
        run: String,
        /// What is wrong.
        reason: String,
    },
    /// The sample source failed while being read.
    #[error("run '{run}': reading the samples failed: {reason}")]
    Source {
        /// Run name.
        run: String,
        /// The source's own message.
        reason: String,
    },
    /// The coarse alignment of the data is degenerate.
    #[error(transparent)]
    Alignment(#[from] AlignmentError),
    /// The replay of a run failed.
    #[error(transparent)]
    Replay(#[from] ReplayError),
    /// A covariance that must be positive definite is not.
    #[error("numerical failure: {0}")]
    Numerical(String),
}

impl DiagError {
    /// An input error for `run`.
    pub fn input(run: &str, reason: impl Into<String>) -> Self {
        DiagError::Input {
            run: run.to_string(),
            reason: reason.into(),
        }
    }
}
