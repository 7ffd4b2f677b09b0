//! The Allan variance of each noise term the twin uses, as a function of `τ`, each linear in
//! one non-negative parameter `θ` (IEEE Std 952 annex C).

use crate::allan::NoiseType;
use serde::{Deserialize, Serialize};

/// A noise term of the fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Term {
    /// Quantization with white remainder: `3 Q²/τ²`, `θ = Q²`, `Q = q/√12` (rad for a gyro).
    Quantization,
    /// White rate noise (angle / velocity random walk): `N²/τ`, `θ = N²`.
    White,
    /// First-order Gauss-Markov bias of stationary σ and correlation time `T`:
    /// `σ² (T/τ)² (2τ/T − 3 + 4e^{−τ/T} − e^{−2τ/T})`, `θ = σ²`.
    GaussMarkov,
    /// Rate random walk: `K² τ / 3`, `θ = K²`.
    RateRandomWalk,
}

/// All terms in the fit's parameter order.
pub const TERMS: [Term; 4] = [
    Term::Quantization,
    Term::White,
    Term::GaussMarkov,
    Term::RateRandomWalk,
];

/// The Allan variance of a unit Gauss-Markov process (σ = 1) with correlation time
/// `correlation_s` at `τ` (a series below `τ/T = 0.01`, where the closed form cancels).
pub fn gauss_markov_unit_avar(tau_s: f64, correlation_s: f64) -> f64 {
    if !correlation_s.is_finite() {
        return 0.0;
    }
    let x = tau_s / correlation_s;
    if x < 1e-2 {
        x * (2.0 / 3.0 - x * (0.5 - x * (7.0 / 30.0 - x / 12.0)))
    } else {
        (2.0 * x - 3.0 + 4.0 * (-x).exp() - (-2.0 * x).exp()) / (x * x)
    }
}

impl Term {
    /// The term's Allan variance per unit `θ` at `τ` (the correlation time matters only for
    /// [`Term::GaussMarkov`]).
    pub fn basis(self, tau_s: f64, correlation_s: f64) -> f64 {
        match self {
            Term::Quantization => 3.0 / (tau_s * tau_s),
            Term::White => 1.0 / tau_s,
            Term::GaussMarkov => gauss_markov_unit_avar(tau_s, correlation_s),
            Term::RateRandomWalk => tau_s / 3.0,
        }
    }

    /// The power-law type whose degrees of freedom apply where this term dominates.
    pub fn noise_type(self) -> NoiseType {
        match self {
            Term::Quantization => NoiseType::WhitePhase,
            Term::White => NoiseType::WhiteFrequency,
            Term::GaussMarkov => NoiseType::FlickerFrequency,
            Term::RateRandomWalk => NoiseType::RandomWalkFrequency,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_markov_series_joins_the_closed_form_and_matches_sins_sim() {
        let x: f64 = 0.0099999;
        let series = gauss_markov_unit_avar(x, 1.0);
        let closed = (2.0 * x - 3.0 + 4.0 * (-x).exp() - (-2.0 * x).exp()) / (x * x);
        assert!((series / closed - 1.0).abs() < 1e-7, "{series} {closed}");
        for x in [0.05, 1.0, 1.89, 10.0] {
            let ours = gauss_markov_unit_avar(x * 3600.0, 3600.0).sqrt();
            let sim = sins_sim::noise::gauss_markov_allan_deviation(1.0, 3600.0, x * 3600.0);
            assert!((ours - sim).abs() < 1e-12, "{x}");
        }
        // Short τ: a rate random walk of K² = 2σ²/T.
        let t = 1e-4;
        assert!((gauss_markov_unit_avar(t, 1.0) / (2.0 * t / 3.0) - 1.0).abs() < 1e-4);
    }
}
