//! Settings of a noise identification.

use crate::error::NoiseIdError;
use serde::{Deserialize, Serialize};

/// How stationary data are chosen and the Allan variance fitted.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct NoiseIdConfig {
    /// Segment labels whose samples are stationary (default `alignment`, `stationary`).
    pub labels: Vec<String>,
    /// Longest averaging time as a fraction of the longest stretch (default 0.25: the
    /// overlapping estimator still has about four degrees of freedom per stretch there, and a
    /// Gauss-Markov bias of an hour's correlation needs `τ` of an hour to show).
    pub max_tau_fraction: f64,
    /// Stretches shorter than this are not used (s; default 60).
    pub min_stretch_s: f64,
    /// Range of the correlation-time grid of the Gauss-Markov bias (s; default 10 to 10⁵).
    pub correlation_grid_s: [f64; 2],
    /// Points of that grid, log spaced (default 49, twelve per decade).
    pub correlation_grid_points: usize,
    /// Also fit a rate random walk (default true), in a second fit with the twin's terms plus
    /// `K`; only `K` is taken from it (the twin has no rate random walk, and on runs of a few
    /// hours `K` and a Gauss-Markov bias of long correlation explain the same rising slope).
    pub fit_rate_random_walk: bool,
    /// Coverage of the Allan-deviation intervals (default 0.6827, 1-sigma equivalent).
    pub coverage: f64,
    /// The stillness detector that finds still stretches in unlabelled runs and motion inside
    /// labelled ones.
    pub stillness: crate::still::StillnessConfig,
    /// Leave out the start of every run when the still stretches show a turn-on transient
    /// (default true; [`crate::identify_noise`]).
    pub leave_out_turn_on: bool,
}

impl Default for NoiseIdConfig {
    fn default() -> Self {
        Self {
            labels: vec!["alignment".into(), "stationary".into()],
            max_tau_fraction: 0.25,
            min_stretch_s: 60.0,
            correlation_grid_s: [10.0, 1e5],
            correlation_grid_points: 49,
            fit_rate_random_walk: true,
            coverage: 0.682_689_492_137_085_9,
            stillness: crate::still::StillnessConfig::default(),
            leave_out_turn_on: true,
        }
    }
}

impl NoiseIdConfig {
    /// Refuse settings that cannot work.
    pub fn validate(&self) -> Result<(), NoiseIdError> {
        let bad = |m: String| Err(NoiseIdError::Config(m));
        if self.labels.is_empty() {
            return bad("no stationary segment label given".into());
        }
        if !(self.max_tau_fraction > 0.0 && self.max_tau_fraction <= 0.5) {
            return bad(format!(
                "max_tau_fraction must be in (0, 0.5], got {}",
                self.max_tau_fraction
            ));
        }
        if !(self.min_stretch_s.is_finite() && self.min_stretch_s >= 0.0) {
            return bad(format!(
                "min_stretch_s must be >= 0, got {}",
                self.min_stretch_s
            ));
        }
        let [lo, hi] = self.correlation_grid_s;
        if !(lo > 0.0 && hi > lo && hi.is_finite()) || self.correlation_grid_points < 3 {
            return bad(format!(
                "correlation grid must be 0 < lo < hi with at least 3 points, got {lo}..{hi} s, {} points",
                self.correlation_grid_points
            ));
        }
        if !(self.coverage > 0.0 && self.coverage < 1.0) {
            return bad(format!("coverage must be in (0, 1), got {}", self.coverage));
        }
        Ok(())
    }

    /// The log-spaced correlation-time grid (s).
    pub fn correlation_grid(&self) -> Vec<f64> {
        let [lo, hi] = self.correlation_grid_s;
        let n = self.correlation_grid_points;
        (0..n)
            .map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
            .collect()
    }
}
