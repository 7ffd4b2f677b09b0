//! Small statistics: median, normalised estimation error squared with a full covariance, and
//! χ² quantiles (for the NEES interval).

use statrs::distribution::{ChiSquared, ContinuousCDF};

/// Median of the finite values (mean of the middle two for an even count); NaN when none.
pub fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Normalised estimation error squared `eᵀ P⁻¹ e` for an error `e` (length n) and a row-major
/// n × n covariance `p`. The covariance is scaled to a correlation matrix first (the
/// coefficients' SI magnitudes span ten decades) and solved by Cholesky; `None` when it is not
/// positive definite or the sizes disagree.
pub fn nees(error: &[f64], p: &[f64]) -> Option<f64> {
    let n = error.len();
    if p.len() != n * n {
        return None;
    }
    let d: Vec<f64> = (0..n).map(|i| p[i * n + i].sqrt()).collect();
    if d.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
        return None;
    }
    // Cholesky R = L Lᵀ of the correlation matrix, lower triangle in place.
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut s = p[i * n + j] / (d[i] * d[j]);
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            if i == j {
                if s.is_nan() || s <= 0.0 {
                    return None;
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    // Forward substitution L y = z with z = D⁻¹ e; NEES = |y|².
    let mut y = vec![0.0; n];
    for i in 0..n {
        let mut s = error[i] / d[i];
        for k in 0..i {
            s -= l[i * n + k] * y[k];
        }
        y[i] = s / l[i * n + i];
    }
    Some(y.iter().map(|v| v * v).sum())
}

/// χ² cumulative distribution with `dof` (> 0) degrees of freedom at `x`.
pub fn chi2_cdf(x: f64, dof: f64) -> f64 {
    ChiSquared::new(dof).map_or(f64::NAN, |d| d.cdf(x))
}

/// The `p` quantile (0 < p < 1) of the χ² distribution with `dof` (> 0) degrees of freedom
/// (NaN outside those ranges).
pub fn chi2_quantile(p: f64, dof: f64) -> f64 {
    match ChiSquared::new(dof) {
        Ok(d) if (0.0..=1.0).contains(&p) => d.inverse_cdf(p),
        _ => f64::NAN,
    }
}

/// Two-sided `level` (e.g. 0.95) interval of the mean of `n` independent NEES values of a
/// `dim`-dimensional consistent estimator: `n · mean ~ χ²(n · dim)`, so the bounds are the
/// χ²(n · dim) quantiles divided by n.
pub fn nees_mean_interval(dim: usize, n: usize, level: f64) -> [f64; 2] {
    let dof = (dim * n) as f64;
    let tail = 0.5 * (1.0 - level);
    let n = n as f64;
    [
        chi2_quantile(tail, dof) / n,
        chi2_quantile(1.0 - tail, dof) / n,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chi2_quantiles_match_the_tables() {
        // Standard table values (Abramowitz & Stegun 26.4 / NIST).
        for (p, dof, want) in [
            (0.025, 10.0, 3.246_973),
            (0.975, 10.0, 20.483_18),
            (0.95, 1.0, 3.841_459),
            (0.025, 100.0, 74.221_93),
            (0.975, 100.0, 129.561_2),
        ] {
            let got = chi2_quantile(p, dof);
            assert!(
                (got - want).abs() < 2e-5 * want,
                "{p} {dof}: {got} vs {want}"
            );
        }
        // χ²(2) is exponential: quantile = −2 ln(1 − p).
        let got = chi2_quantile(0.9, 2.0);
        assert!((got + 2.0 * 0.1f64.ln()).abs() < 1e-9);
    }

    #[test]
    fn nees_of_a_correlated_pair_matches_the_closed_form() {
        // P = [[4, 2ρ·2·3 ...]]: σ = (2, 3), ρ = 0.5; eᵀP⁻¹e = (z1² − 2ρ z1 z2 + z2²)/(1 − ρ²).
        let (s1, s2, rho) = (2.0, 3.0, 0.5);
        let p = [s1 * s1, rho * s1 * s2, rho * s1 * s2, s2 * s2];
        let e = [1.0, -2.0];
        let (z1, z2) = (e[0] / s1, e[1] / s2);
        let want = (z1 * z1 - 2.0 * rho * z1 * z2 + z2 * z2) / (1.0 - rho * rho);
        let got = nees(&e, &p).expect("positive definite");
        assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        assert!(nees(&e, &[1.0, 2.0, 2.0, 1.0]).is_none(), "indefinite");
        assert_eq!(median(&[3.0, 1.0, f64::NAN, 2.0, 10.0]), 2.5);
    }
}
