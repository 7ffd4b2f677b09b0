//! Errors of the harness.

use std::path::PathBuf;

/// What can go wrong in the harness; every variant names the file or item at fault.
#[derive(Debug, thiserror::Error)]
pub enum HarnessError {
    /// A file could not be read or written (the readers of the harness's files in `sins-config`
    /// report it).
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A configuration, threshold or summary file is malformed.
    #[error("{path}: {message}")]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the key or row.
        message: String,
    },
    /// The simulator refused a scenario.
    #[error("simulation of '{run}': {source}")]
    Simulation {
        /// Run name.
        run: String,
        /// The simulator's error.
        source: sins_sim::SimError,
    },
    /// A replay failed.
    #[error("replay of '{run}' with parameter set '{set}': {source}")]
    Replay {
        /// Run or dataset name.
        run: String,
        /// Parameter set key.
        set: String,
        /// The replay's error.
        source: sins_replay::ReplayError,
    },
    /// A calibration failed.
    #[error("calibration of '{run}' ({states} states): {source}")]
    Calibration {
        /// Run name.
        run: String,
        /// 30 or 42.
        states: usize,
        /// The filter's error.
        source: sins_kf::CalibrationError,
    },
    /// A parameter set cannot be inverted for compensation.
    #[error("parameter set '{set}' is singular (I + E not invertible)")]
    SingularParams {
        /// Parameter set key.
        set: String,
    },
    /// The data and the parameter set do not fit together.
    #[error("{0}")]
    Mismatch(String),
    /// A worker thread could not be started (the system's thread limit).
    #[error("cannot start a worker thread: {0}")]
    Thread(std::io::Error),
}
