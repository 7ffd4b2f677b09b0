//! Statistics of the Monte Carlo: quantiles with their bootstrap errors, and global sensitivity
//! through a ridge-regression surrogate fitted on the full runs (validated by leave-one-out) whose
//! Sobol indices are exact for an additive model, with bootstrap intervals.

use crate::draw::Stream;
use nalgebra::{DMatrix, DVector};

/// Quantile `p` in [0, 1] of `values` (linear interpolation between order statistics, type 7).
/// NaN for no values.
pub fn quantile(values: &[f64], p: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let h = (v.len() - 1) as f64 * p.clamp(0.0, 1.0);
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    v[lo] + (h - lo as f64) * (v[hi] - v[lo])
}

/// Mean and sample standard deviation (n - 1).
pub fn mean_sd(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}

/// Standard error of the quantiles `ps` of `values` by the bootstrap (`resamples` resamples,
/// deterministic from `seed`).
pub fn bootstrap_quantile_se(values: &[f64], ps: &[f64], resamples: usize, seed: u64) -> Vec<f64> {
    let n = values.len();
    let mut s = Stream::new(seed, 0);
    let mut draws: Vec<Vec<f64>> = vec![Vec::with_capacity(resamples); ps.len()];
    let mut buf = vec![0.0; n];
    for _ in 0..resamples {
        for b in buf.iter_mut() {
            *b = values[((s.uniform() * n as f64) as usize).min(n - 1)];
        }
        for (d, p) in draws.iter_mut().zip(ps) {
            d.push(quantile(&buf, *p));
        }
    }
    draws.iter().map(|d| mean_sd(d).1).collect()
}

/// A ridge-regression surrogate `y ≈ b0 + Σ b_i x_i` on standardised inputs.
#[derive(Clone, Debug)]
pub struct Surrogate {
    /// Coefficients on the standardised inputs.
    pub beta: Vec<f64>,
    /// Ridge penalty chosen by leave-one-out.
    pub lambda: f64,
    /// Leave-one-out R² (prediction of each full run from a fit without it).
    pub r2_loo: f64,
    /// In-sample R².
    pub r2: f64,
}

/// Standardises the columns of `x` (rows = samples); constant columns become zero.
pub fn standardise(x: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let p = x.first().map_or(0, Vec::len);
    let cols: Vec<(f64, f64)> = (0..p)
        .map(|j| mean_sd(&x.iter().map(|r| r[j]).collect::<Vec<_>>()))
        .collect();
    x.iter()
        .map(|r| {
            r.iter()
                .zip(&cols)
                .map(|(v, (m, s))| if *s > 0.0 { (v - m) / s } else { 0.0 })
                .collect()
        })
        .collect()
}

/// Ridge fit of `y` on standardised `z` with penalty `lambda`; returns (intercept, beta,
/// leave-one-out residuals, in-sample residuals).
fn ridge(z: &[Vec<f64>], y: &[f64], lambda: f64) -> Option<(f64, Vec<f64>, Vec<f64>, Vec<f64>)> {
    let (n, p) = (y.len(), z.first().map_or(0, Vec::len));
    let x = DMatrix::from_fn(n, p + 1, |i, j| if j == 0 { 1.0 } else { z[i][j - 1] });
    let yv = DVector::from_column_slice(y);
    let mut a = x.transpose() * &x;
    for j in 1..=p {
        a[(j, j)] += lambda;
    }
    let inv = a.try_inverse()?;
    let coef = &inv * x.transpose() * &yv;
    let fitted = &x * &coef;
    let hat_diag: Vec<f64> = (0..n)
        .map(|i| (x.row(i) * &inv * x.row(i).transpose())[(0, 0)])
        .collect();
    let resid: Vec<f64> = (0..n).map(|i| y[i] - fitted[i]).collect();
    let loo = resid
        .iter()
        .zip(&hat_diag)
        .map(|(r, h)| r / (1.0 - h).max(1e-9))
        .collect();
    Some((coef[0], coef.iter().skip(1).copied().collect(), loo, resid))
}

/// Fits the surrogate, choosing the ridge penalty on a grid by leave-one-out error.
pub fn fit_surrogate(z: &[Vec<f64>], y: &[f64]) -> Option<Surrogate> {
    let (_, sd) = mean_sd(y);
    let ss = sd * sd * (y.len() as f64 - 1.0);
    let mut best: Option<Surrogate> = None;
    for k in 0..12 {
        let lambda = if k == 0 { 0.0 } else { 0.05 * 2f64.powi(k) };
        let Some((_, beta, loo, res)) = ridge(z, y, lambda) else {
            continue;
        };
        let press: f64 = loo.iter().map(|r| r * r).sum();
        let rss: f64 = res.iter().map(|r| r * r).sum();
        let s = Surrogate {
            beta,
            lambda,
            r2_loo: if ss > 0.0 { 1.0 - press / ss } else { 0.0 },
            r2: if ss > 0.0 { 1.0 - rss / ss } else { 0.0 },
        };
        if best.as_ref().is_none_or(|b| s.r2_loo > b.r2_loo) {
            best = Some(s);
        }
    }
    best
}

/// First-order Sobol index of each group of standardised inputs under an additive linear
/// surrogate: `Var(Σ_{i∈g} β_i z_i) / Var(y)` with the inputs' sample covariance, so that
/// one-hot columns of one choice are taken together. For an additive model the total index
/// equals the first-order one; what the surrogate does not explain (1 - R²) is interaction,
/// per-element draws and sensor-noise seeds.
pub fn group_indices(z: &[Vec<f64>], y: &[f64], beta: &[f64], groups: &[Vec<usize>]) -> Vec<f64> {
    let (_, sd) = mean_sd(y);
    let var_y = sd * sd;
    groups
        .iter()
        .map(|g| {
            let part: Vec<f64> = z
                .iter()
                .map(|r| g.iter().map(|&i| beta[i] * r[i]).sum())
                .collect();
            let (_, s) = mean_sd(&part);
            if var_y > 0.0 {
                (s * s / var_y).min(1.0)
            } else {
                0.0
            }
        })
        .collect()
}

/// A Sobol index with its bootstrap interval.
#[derive(Clone, Debug, PartialEq)]
pub struct IndexInterval {
    /// Point estimate.
    pub value: f64,
    /// 5 % bootstrap quantile.
    pub low: f64,
    /// 95 % bootstrap quantile.
    pub high: f64,
}

/// Group indices with bootstrap intervals (the surrogate refitted, penalty fixed, on each
/// resample of the full runs).
pub fn group_indices_bootstrap(
    z: &[Vec<f64>],
    y: &[f64],
    fit: &Surrogate,
    groups: &[Vec<usize>],
    resamples: usize,
    seed: u64,
) -> Vec<IndexInterval> {
    let point = group_indices(z, y, &fit.beta, groups);
    let n = y.len();
    let mut s = Stream::new(seed, 1);
    let mut draws: Vec<Vec<f64>> = vec![Vec::new(); groups.len()];
    for _ in 0..resamples {
        let idx: Vec<usize> = (0..n)
            .map(|_| ((s.uniform() * n as f64) as usize).min(n - 1))
            .collect();
        let zb: Vec<Vec<f64>> = idx.iter().map(|&i| z[i].clone()).collect();
        let yb: Vec<f64> = idx.iter().map(|&i| y[i]).collect();
        if let Some((_, beta, _, _)) = ridge(&zb, &yb, fit.lambda) {
            for (d, v) in draws.iter_mut().zip(group_indices(&zb, &yb, &beta, groups)) {
                d.push(v);
            }
        }
    }
    point
        .into_iter()
        .zip(draws)
        .map(|(value, d)| IndexInterval {
            value,
            low: quantile(&d, 0.05),
            high: quantile(&d, 0.95),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantile_interpolates_order_statistics() {
        let v = [4.0, 1.0, 3.0, 2.0, 5.0];
        assert_eq!(quantile(&v, 0.5), 3.0);
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 1.0), 5.0);
        assert!((quantile(&v, 0.1) - 1.4).abs() < 1e-12);
    }

    #[test]
    fn bootstrap_se_of_median_matches_normal_theory() {
        // Median of n normal deviates: se ≈ sqrt(pi/2) σ / sqrt(n).
        let mut s = Stream::new(7, 3);
        let v: Vec<f64> = (0..400).map(|_| s.normal()).collect();
        let se = bootstrap_quantile_se(&v, &[0.5], 400, 11)[0];
        let theory = (std::f64::consts::PI / 2.0).sqrt() / 20.0;
        assert!((se / theory - 1.0).abs() < 0.3, "se {se} theory {theory}");
    }

    #[test]
    fn sobol_of_additive_model_matches_analytic_shares() {
        // y = 3 x1 + 1 x2 + 0 x3 + small noise, x ~ U(0,1): shares 9/10.x, 1/10.x, 0.
        let mut s = Stream::new(3, 0);
        let x: Vec<Vec<f64>> = (0..300)
            .map(|_| vec![s.uniform(), s.uniform(), s.uniform()])
            .collect();
        let y: Vec<f64> = x
            .iter()
            .map(|r| 3.0 * r[0] + r[1] + 0.05 * s.normal())
            .collect();
        let z = standardise(&x);
        let fit = fit_surrogate(&z, &y).expect("fit");
        assert!(fit.r2_loo > 0.98, "LOO R² {}", fit.r2_loo);
        let groups = vec![vec![0], vec![1], vec![2]];
        let idx = group_indices_bootstrap(&z, &y, &fit, &groups, 100, 5);
        let var_noise = 0.05f64.powi(2);
        let total = 10.0 / 12.0 + var_noise;
        assert!((idx[0].value - 0.75 / total).abs() < 0.06, "{:?}", idx[0]);
        assert!(
            (idx[1].value - (1.0 / 12.0) / total).abs() < 0.03,
            "{:?}",
            idx[1]
        );
        assert!(idx[2].value < 0.01 && idx[2].low <= idx[2].value && idx[2].value <= idx[2].high);
        assert!(idx[0].low < idx[0].value && idx[0].value < idx[0].high);
    }
}
