//! Errors of the UQ engine.

/// What can go wrong while drawing, building or running a sample.
#[derive(Debug, thiserror::Error)]
pub enum UqError {
    /// An assumption or candidate is inconsistent (named).
    #[error("assumption '{name}': {message}")]
    Assumption {
        /// The assumption or candidate.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The simulation, calibration or replay of a sample failed.
    #[error("sample {sample} of '{candidate}': {source}")]
    Pipeline {
        /// Candidate (or "replica" for the main Monte Carlo).
        candidate: String,
        /// Sample index.
        sample: usize,
        /// The harness error (boxed: it is large and rare).
        #[source]
        source: Box<sins_harness::HarnessError>,
    },
    /// Too few samples for a statistic.
    #[error("{what}: needs at least {needed} samples, got {got}")]
    TooFewSamples {
        /// The statistic.
        what: String,
        /// Samples needed.
        needed: usize,
        /// Samples given.
        got: usize,
    },
}
