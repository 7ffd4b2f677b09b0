//! Errors of the noise identification.

use sins_diag::DiagError;

/// Everything that can stop a noise identification.
#[derive(Debug, thiserror::Error)]
pub enum NoiseIdError {
    /// The settings are unusable.
    #[error("noise identification settings: {0}")]
    Config(String),
    /// A run cannot be used (named run and reason).
    #[error("run '{run}': {reason}")]
    Run {
        /// Run name.
        run: String,
        /// What is wrong.
        reason: String,
    },
    /// Reading a run's samples failed.
    #[error(transparent)]
    Source(#[from] DiagError),
    /// Too little stationary data to identify anything.
    #[error("not enough stationary data: {0}")]
    NotEnoughData(String),
}
