//! The overlapping Allan variance (IEEE Std 952-1997 / 1554-2005) from cumulative sums, its
//! equivalent degrees of freedom (Howe, Allan and Barnes 1981, as tabulated in NIST SP 1065)
//! and chi-square confidence intervals.
//!
//! With `x_k` the cumulative output (rad for a gyro, m/s for an accelerometer) after sample `k`
//! and `τ = m h`, the overlapping estimator is
//! `σ²(τ) = Σ_k (x_{k+2m} − 2 x_{k+m} + x_k)² / (2 τ² (N − 2m))` over the `N − 2m` second
//! differences of `N` phase points. A constant rate (Earth rate, gravity, a turn-on bias)
//! cancels exactly in every second difference. Estimates of several stretches are pooled by
//! adding their squared differences and counts (never by averaging deviations); their degrees
//! of freedom add, the stretches being independent.

use serde::{Deserialize, Serialize};
use sins_diag::chi2_isf;

/// The power-law noise type that sets the equivalent degrees of freedom of an estimate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum NoiseType {
    /// White phase noise (quantization: `σ² ∝ τ⁻²`).
    WhitePhase,
    /// White frequency noise (angle / velocity random walk: `σ² ∝ τ⁻¹`).
    WhiteFrequency,
    /// Flicker frequency noise (the flat bias-instability region; used for a Gauss-Markov
    /// bias near its Allan peak).
    FlickerFrequency,
    /// Random-walk frequency noise (rate random walk: `σ² ∝ τ`).
    RandomWalkFrequency,
}

/// Sum of the squared second differences `x_{k+2m} − 2x_{k+m} + x_k` of the phase points `x`
/// at lag `m`, and their count (`x.len() − 2m`; zero when there are too few points).
pub fn second_difference_sum(x: &[f64], m: usize) -> (f64, u64) {
    if m == 0 || x.len() <= 2 * m {
        return (0.0, 0);
    }
    let mut ss = 0.0;
    for k in 0..x.len() - 2 * m {
        let d = x[k + 2 * m] - 2.0 * x[k + m] + x[k];
        ss += d * d;
    }
    (ss, (x.len() - 2 * m) as u64)
}

/// Overlapping Allan variance (rate unit²) of the phase points `x` (cumulative output, one
/// point per sample boundary) at `τ = m h`; `None` without a single second difference.
pub fn overlapping_avar(x: &[f64], m: usize, h_s: f64) -> Option<f64> {
    let (ss, n) = second_difference_sum(x, m);
    let tau = m as f64 * h_s;
    (n > 0).then(|| ss / (2.0 * tau * tau * n as f64))
}

/// Equivalent degrees of freedom of the overlapping Allan variance of `n` phase points at
/// averaging factor `m` for the noise type (NIST SP 1065 table 5, after Howe, Allan and
/// Barnes). Never below 1 when at least one second difference exists, 0 otherwise.
pub fn edf(noise: NoiseType, n: u64, m: u64) -> f64 {
    if m == 0 || n <= 2 * m {
        return 0.0;
    }
    let (nf, mf) = (n as f64, m as f64);
    let e = match noise {
        NoiseType::WhitePhase => (nf + 1.0) * (nf - 2.0 * mf) / (2.0 * (nf - mf)),
        NoiseType::WhiteFrequency => {
            (3.0 * (nf - 1.0) / (2.0 * mf) - 2.0 * (nf - 2.0) / nf) * 4.0 * mf * mf
                / (4.0 * mf * mf + 5.0)
        }
        NoiseType::FlickerFrequency => {
            if m == 1 {
                2.0 * (nf - 2.0).powi(2) / (2.3 * nf - 4.9)
            } else {
                5.0 * nf * nf / (4.0 * mf * (nf + 3.0 * mf))
            }
        }
        NoiseType::RandomWalkFrequency => {
            (nf - 2.0) / mf * ((nf - 1.0).powi(2) - 3.0 * mf * (nf - 1.0) + 4.0 * mf * mf)
                / (nf - 3.0).powi(2)
        }
    };
    // Upper bound: the count of (correlated) second differences.
    e.clamp(1.0, (n - 2 * m) as f64)
}

/// Two-sided chi-square interval of a variance estimate with `edf` degrees of freedom at
/// coverage `coverage` (0.6827 for the 1-sigma-equivalent interval): `(lo, hi)` with
/// `lo = v·edf/χ²_{(1+c)/2}` and `hi = v·edf/χ²_{(1−c)/2}`.
pub fn chi2_interval(variance: f64, edf: f64, coverage: f64) -> (f64, f64) {
    if edf <= 0.0 || !variance.is_finite() {
        return (0.0, f64::INFINITY);
    }
    let tail = 0.5 * (1.0 - coverage);
    let upper_q = chi2_isf(tail, edf);
    let lower_q = chi2_isf(1.0 - tail, edf);
    (
        variance * edf / upper_q,
        if lower_q > 0.0 {
            variance * edf / lower_q
        } else {
            f64::INFINITY
        },
    )
}

/// The pooled second differences of one channel at one `τ`: squared sum, count, and each
/// stretch's `(phase points, averaging factor)` for its degrees of freedom.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PooledTau {
    /// Averaging time (s).
    pub tau_s: f64,
    /// Sum of squared second differences (unit² of the cumulative output).
    pub sum_sq: f64,
    /// Number of second differences.
    pub count: u64,
    /// Per contributing stretch: its index (in the order stretches were closed), phase points
    /// and averaging factor at its stride.
    pub stretches: Vec<(usize, u64, u64)>,
}

impl PooledTau {
    /// Add the second differences of stretch `index`.
    pub fn add(&mut self, index: usize, sum_sq: f64, count: u64, n_points: u64, m: u64) {
        if count == 0 {
            return;
        }
        self.sum_sq += sum_sq;
        self.count += count;
        self.stretches.push((index, n_points, m));
    }

    /// The pooled overlapping Allan variance (rate unit²); `None` without data.
    pub fn avar(&self) -> Option<f64> {
        (self.count > 0).then(|| self.sum_sq / (2.0 * self.tau_s * self.tau_s * self.count as f64))
    }

    /// Degrees of freedom of the pooled estimate for a noise type (sum over stretches).
    pub fn edf(&self, noise: NoiseType) -> f64 {
        self.stretches
            .iter()
            .map(|&(_, n, m)| edf(noise, n, m))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edf_of_white_frequency_at_m1_is_about_the_difference_count() {
        // m = 1: (3(N-1)/2 - 2(N-2)/N) 4/9 ≈ 2N/3 for large N (NIST SP 1065).
        let e = edf(NoiseType::WhiteFrequency, 10_001, 1);
        assert!((e / (2.0 * 10_000.0 / 3.0) - 1.0).abs() < 1e-3, "{e}");
    }

    #[test]
    fn chi2_interval_brackets_the_estimate_and_narrows_with_edf() {
        let (lo, hi) = chi2_interval(1.0, 10.0, 0.6827);
        assert!(lo < 1.0 && hi > 1.0);
        let (lo2, hi2) = chi2_interval(1.0, 1000.0, 0.6827);
        assert!(lo2 > lo && hi2 < hi);
        // Large edf: ±sqrt(2/edf) to first order.
        assert!((hi2 - lo2 - 2.0 * (2.0f64 / 1000.0).sqrt()).abs() < 0.01);
    }
}
