//! Errors of the calibration study.

use crate::reference::ReferenceError;

/// Why a study (or one of its calibrations) could not be completed.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// An experiment file could not be loaded.
    #[error(transparent)]
    Config(#[from] sins_config::ConfigError),
    /// A reference table (the paper's Table 1 or 3) is missing or malformed.
    #[error(transparent)]
    Reference(#[from] ReferenceError),
    /// The simulator rejected a scenario.
    #[error("scenario `{scenario}`: {source}")]
    Simulation {
        /// Scenario (run) name.
        scenario: String,
        /// The simulator's reason.
        source: sins_sim::SimError,
    },
    /// A calibration filter failed on a scenario.
    #[error("calibration of `{scenario}` ({states} states): {source}")]
    Calibration {
        /// Scenario (run) name, with the seed for Monte Carlo runs.
        scenario: String,
        /// 30 or 42.
        states: usize,
        /// The filter's reason.
        source: sins_kf::CalibrationError,
    },
    /// The study settings or the experiments do not fit together.
    #[error("{0}")]
    Setup(String),
}
