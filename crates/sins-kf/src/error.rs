//! Errors of the calibration filter.

use sins_nav::alignment::AlignmentError;

/// Why a calibration could not be run or completed.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CalibrationError {
    /// A setting is out of range.
    #[error("invalid calibration setting `{field}`: {reason}")]
    Config {
        /// The setting.
        field: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// The initial estimate has a non-finite coefficient or cannot be inverted.
    #[error("invalid initial parameter set: {0}")]
    InitialParams(String),
    /// A sample has a non-finite increment, or lacks temperatures the 42-state model needs.
    #[error("sample at t = {t_s} s is unusable: {reason}")]
    BadSample {
        /// Sample time (s).
        t_s: f64,
        /// What is wrong.
        reason: &'static str,
    },
    /// Samples are not evenly spaced at the configured interval.
    #[error(
        "sample at t = {t_s} s follows the previous one after {gap_s} s, expected {expected_s} s"
    )]
    TimeGap {
        /// Sample time (s).
        t_s: f64,
        /// Actual spacing (s).
        gap_s: f64,
        /// Configured sample interval (s).
        expected_s: f64,
    },
    /// The stationary alignment failed.
    #[error("alignment failed: {0}")]
    Alignment(#[from] AlignmentError),
    /// The navigation velocity keeps growing faster than sensor noise and coefficient errors
    /// within their prior allow: the IMU is moving, so the data are not a turntable run at the
    /// configured site (or the coefficient errors are far beyond the configured prior).
    #[error(
        "not a turntable run at the site: horizontal velocity innovation {innovation_mps:.3} m/s per update, far beyond what sensor noise and coefficient errors explain (limit {limit_mps} m/s), for {duration_s:.0} s up to t = {t_s:.1} s"
    )]
    NotStationary {
        /// Time of detection (s).
        t_s: f64,
        /// Last horizontal velocity innovation (m/s).
        innovation_mps: f64,
        /// How long the limit was exceeded (s).
        duration_s: f64,
        /// The configured limit (m/s).
        limit_mps: f64,
    },
    /// The filter produced a non-finite or singular result (diverged).
    #[error("filter diverged at t = {t_s} s: {reason}")]
    Diverged {
        /// Time (s).
        t_s: f64,
        /// What failed.
        reason: &'static str,
    },
    /// The data ended before the first filter update.
    #[error("data too short: {got_s:.1} s given, alignment and one update need {needed_s:.1} s")]
    TooShort {
        /// Data given (s).
        got_s: f64,
        /// Data needed (s).
        needed_s: f64,
    },
}
