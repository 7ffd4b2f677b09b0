//! Chi-square tail probabilities and quantiles, and the normal CDF, from `statrs`, guarded
//! for every argument the diagnosis can pass (no panic on a degenerate one).

use statrs::distribution::{ChiSquared, ContinuousCDF};

/// Probability that a chi-square variable of `dof` degrees of freedom exceeds `x` (1 for
/// `x ≤ 0`; a degenerate `dof ≤ 0` is the point mass at 0).
pub fn chi2_sf(x: f64, dof: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 1.0;
    }
    match chi2(dof) {
        Some(d) => d.sf(x).clamp(0.0, 1.0),
        None => 0.0,
    }
}

/// The value a chi-square variable of `dof` degrees of freedom exceeds with probability `p`
/// (0 for `p ≥ 1`, infinite for `p ≤ 0`). Computed as the quantile at `1 − p`, so a `p`
/// below about 1e-15 is not resolved (the diagnosis's smallest is a Bonferroni level near
/// 1e-6).
pub fn chi2_isf(p: f64, dof: f64) -> f64 {
    if p.is_nan() {
        return f64::NAN;
    }
    if p >= 1.0 {
        return 0.0;
    }
    match chi2(dof) {
        Some(d) if p > 0.0 => d.inverse_cdf(1.0 - p),
        Some(_) => f64::INFINITY,
        None => 0.0,
    }
}

/// Standard normal cumulative distribution at `x`.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * statrs::function::erf::erfc(-x / std::f64::consts::SQRT_2)
}

fn chi2(dof: f64) -> Option<ChiSquared> {
    (dof > 0.0 && dof.is_finite())
        .then(|| ChiSquared::new(dof).ok())
        .flatten()
}

/// Standard normals from a fixed linear congruential generator (Box-Muller), for the tests.
#[cfg(test)]
pub(crate) fn test_normals(n: usize, mut state: u64) -> Vec<f64> {
    let mut uniform = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let (u, v) = (uniform(), uniform());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chi_square_tails_match_tables() {
        // Standard table values.
        assert!((chi2_isf(0.05, 1.0) - 3.841_458_820_694_124).abs() < 1e-9);
        assert!((chi2_isf(0.001, 3.0) - 16.266_236_196_238_1).abs() < 1e-8);
        assert!((chi2_sf(10.0, 10.0) - 0.440_493_285_065_212_6).abs() < 1e-12);
        // A Bonferroni level of the time-local scan: 0.05 over 47 916 tests.
        let q = chi2_isf(0.05 / 47_916.0, 1.0);
        assert!(
            (chi2_sf(q, 1.0) * 47_916.0 / 0.05 - 1.0).abs() < 1e-6,
            "{q}"
        );
        // Large dof: close to normal; the median is about dof (1 - 2/(9 dof))^3.
        let n: f64 = 3000.0;
        let med = n * (1.0 - 2.0 / (9.0 * n)).powi(3);
        assert!((chi2_sf(med, n) - 0.5).abs() < 1e-3);
        // Far tails stay positive and ordered (p-values of strong events).
        assert!(chi2_sf(2000.0, 1.0) < chi2_sf(1000.0, 1.0));
        assert!(
            (normal_cdf(1.281_551_565_544_600_4) - 0.9).abs() < 1e-9,
            "{}",
            normal_cdf(1.281_551_565_544_600_4)
        );
        assert!((normal_cdf(-1.959_963_984_540_054) - 0.025).abs() < 1e-9);
    }

    #[test]
    fn degenerate_arguments_do_not_panic() {
        assert_eq!(chi2_sf(-1.0, 3.0), 1.0);
        assert_eq!(chi2_sf(1.0, 0.0), 0.0);
        assert_eq!(chi2_isf(1.5, 2.0), 0.0);
        assert_eq!(chi2_isf(0.0, 2.0), f64::INFINITY);
        assert_eq!(chi2_isf(0.1, f64::NAN), 0.0);
        assert!(chi2_isf(f64::NAN, 1.0).is_nan());
    }
}
