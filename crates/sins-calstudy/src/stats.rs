//! Small statistics: median, normalised estimation error squared with a full covariance, and
//! χ² quantiles (for the NEES interval).

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

/// ln Γ(x) for x > 0 (Lanczos, g = 7, 9 terms; relative error ~1e-15).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let mut a = C[0];
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Regularised lower incomplete gamma function P(a, x) (series below a + 1, Lentz continued
/// fraction above).
fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let ln_front = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut ap, mut del, mut sum) = (a, 1.0 / a, 1.0 / a);
        for _ in 0..10_000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (sum.ln() + ln_front).exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        1.0 - (ln_front.exp() * h)
    }
}

/// χ² cumulative distribution with `dof` degrees of freedom at `x`.
pub fn chi2_cdf(x: f64, dof: f64) -> f64 {
    gamma_p(0.5 * dof, 0.5 * x)
}

/// The `p` quantile (0 < p < 1) of the χ² distribution with `dof` degrees of freedom
/// (bisection on [`chi2_cdf`] to 1e-12 relative).
pub fn chi2_quantile(p: f64, dof: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, dof + 20.0 * (2.0 * dof).sqrt() + 100.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if chi2_cdf(mid, dof) < p {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-12 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
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
