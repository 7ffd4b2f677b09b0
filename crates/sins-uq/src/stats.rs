//! Statistics of the Monte Carlo: quantiles with their bootstrap errors, and global sensitivity
//! as first-order Sobol indices estimated from the full runs themselves (given data), with
//! bootstrap intervals.

use crate::draw::Stream;

/// Quantile `p` in [0, 1] of `values` (type 7; the harness's, shared with the release gate).
pub use sins_harness::shift::quantile;

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

/// First-order Sobol index `Var(E[y | x]) / Var(y)` of one input from given data (no sampling
/// design): the correlation ratio of `y` on `x` binned into `bins` equal-count bins of `x` (a
/// choice: one bin per level), corrected for the bias of binned means (the adjusted
/// η² = 1 - (1 - η²)(N - 1)/(N - M), clamped to [0, 1]). Model-free, so a bimodal response is
/// no harder than a smooth one; it needs no surrogate.
pub fn first_order_given_data(x: &[f64], y: &[f64], bins: usize, is_choice: bool) -> f64 {
    let n = y.len();
    if n < 3 {
        return f64::NAN;
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| x[a].total_cmp(&x[b]).then(a.cmp(&b)));
    let groups: Vec<Vec<usize>> = if is_choice {
        let mut g: Vec<Vec<usize>> = Vec::new();
        for &i in &order {
            match g.last_mut() {
                Some(last) if x[last[0]] == x[i] => last.push(i),
                _ => g.push(vec![i]),
            }
        }
        g
    } else {
        let m = bins.clamp(2, n);
        (0..m)
            .map(|b| order[b * n / m..(b + 1) * n / m].to_vec())
            .filter(|g| !g.is_empty())
            .collect()
    };
    let m = groups.len();
    if m < 2 || n <= m {
        return 0.0;
    }
    let mean = y.iter().sum::<f64>() / n as f64;
    let ss_total: f64 = y.iter().map(|v| (v - mean).powi(2)).sum();
    if ss_total <= 0.0 {
        return 0.0;
    }
    let ss_between: f64 = groups
        .iter()
        .map(|g| {
            let gm = g.iter().map(|&i| y[i]).sum::<f64>() / g.len() as f64;
            g.len() as f64 * (gm - mean).powi(2)
        })
        .sum();
    let eta2 = ss_between / ss_total;
    (1.0 - (1.0 - eta2) * (n as f64 - 1.0) / (n - m) as f64).clamp(0.0, 1.0)
}

/// Bins for [`first_order_given_data`] with `n` samples: about sqrt(n), at least 2.
pub fn default_bins(n: usize) -> usize {
    ((n as f64).sqrt().round() as usize).max(2)
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

/// [`first_order_given_data`] with a bias-corrected 90 % bootstrap percentile interval
/// (resamples of the (x, y) pairs, deterministic from `seed`).
pub fn first_order_bootstrap(
    x: &[f64],
    y: &[f64],
    is_choice: bool,
    resamples: usize,
    seed: u64,
) -> IndexInterval {
    let n = y.len();
    let bins = default_bins(n);
    let value = first_order_given_data(x, y, bins, is_choice);
    let mut s = Stream::new(seed, 1);
    let mut d = Vec::with_capacity(resamples);
    let (mut xb, mut yb) = (vec![0.0; n], vec![0.0; n]);
    for _ in 0..resamples {
        for k in 0..n {
            let i = ((s.uniform() * n as f64) as usize).min(n - 1);
            xb[k] = x[i];
            yb[k] = y[i];
        }
        d.push(first_order_given_data(&xb, &yb, bins, is_choice));
    }
    // Resampling with replacement duplicates points and so inflates the between-bin variance:
    // shift the percentile interval by the bootstrap's own bias.
    let bias = d.iter().sum::<f64>() / d.len().max(1) as f64 - value;
    let low = (quantile(&d, 0.05) - bias).clamp(0.0, 1.0);
    let high = (quantile(&d, 0.95) - bias).clamp(0.0, 1.0);
    IndexInterval {
        value,
        low: low.min(value),
        high: high.max(value),
    }
}

/// Permutation p-value of [`first_order_given_data`] against "y does not depend on x": the share
/// of `permutations` random reorderings of `x` (deterministic from `seed`) whose index reaches
/// the observed one, `(1 + hits) / (1 + permutations)`. Calibrated whatever the shape of `y`
/// (a bimodal response inflates the binned index's null spread far beyond normal theory).
pub fn first_order_permutation_p(
    x: &[f64],
    y: &[f64],
    is_choice: bool,
    permutations: usize,
    seed: u64,
) -> f64 {
    let bins = default_bins(y.len());
    let observed = first_order_given_data(x, y, bins, is_choice);
    let mut s = Stream::new(seed, 4);
    let mut xp = x.to_vec();
    let mut hits = 0;
    for _ in 0..permutations {
        for i in (1..xp.len()).rev() {
            let j = ((s.uniform() * (i + 1) as f64) as usize).min(i);
            xp.swap(i, j);
        }
        if first_order_given_data(&xp, y, bins, is_choice) >= observed {
            hits += 1;
        }
    }
    (1 + hits) as f64 / (1 + permutations) as f64
}

/// Benjamini-Hochberg: which of `p` are discoveries at false-discovery rate `q` (the largest
/// rank k with p_(k) <= k q / m, and every p at or below it).
pub fn benjamini_hochberg(p: &[f64], q: f64) -> Vec<bool> {
    let m = p.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let cut = order
        .iter()
        .enumerate()
        .filter(|(k, i)| p[**i] <= (k + 1) as f64 * q / m as f64)
        .map(|(_, i)| p[*i])
        .next_back();
    p.iter().map(|v| cut.is_some_and(|c| *v <= c)).collect()
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
    fn given_data_first_order_matches_analytic_shares() {
        // y = 3 x1 + x2 + 0 x3 + 0.05 e, x ~ U(0, 1): S1 = 0.75/V, S2 = 0.0833/V, S3 = 0,
        // V = 10/12 + 0.0025.
        let mut s = Stream::new(3, 0);
        let n = 2000;
        let x: Vec<[f64; 3]> = (0..n)
            .map(|_| [s.uniform(), s.uniform(), s.uniform()])
            .collect();
        let y: Vec<f64> = x
            .iter()
            .map(|r| 3.0 * r[0] + r[1] + 0.05 * s.normal())
            .collect();
        let v = 10.0 / 12.0 + 0.0025;
        let col = |j: usize| x.iter().map(|r| r[j]).collect::<Vec<_>>();
        let idx: Vec<IndexInterval> = (0..3)
            .map(|j| first_order_bootstrap(&col(j), &y, false, 200, 5))
            .collect();
        assert!((idx[0].value - 0.75 / v).abs() < 0.03, "{:?}", idx[0]);
        assert!(
            (idx[1].value - (1.0 / 12.0) / v).abs() < 0.02,
            "{:?}",
            idx[1]
        );
        assert!(idx[2].value < 0.01, "{:?}", idx[2]);
        for i in &idx {
            assert!(
                i.low <= i.value && i.value <= i.high && i.high - i.low < 0.1,
                "{i:?}"
            );
        }
        // A two-level choice that moves y by 4 sd: nearly all the variance.
        let c: Vec<f64> = (0..n).map(|i| (i % 2) as f64).collect();
        let yc: Vec<f64> = c.iter().map(|c| 4.0 * c + s.normal()).collect();
        let sc = first_order_given_data(&c, &yc, 2, true);
        assert!((sc - 4.0 / 5.0).abs() < 0.03, "{sc}");
    }

    #[test]
    fn benjamini_hochberg_matches_a_worked_example() {
        // m = 5, q = 0.1: thresholds 0.02, 0.04, 0.06, 0.08, 0.1; sorted p 0.001, 0.03, 0.05,
        // 0.2, 0.9: the largest passing rank is 3 (0.05 <= 0.06), so the three smallest.
        let p = [0.2, 0.05, 0.001, 0.9, 0.03];
        assert_eq!(
            benjamini_hochberg(&p, 0.1),
            [false, true, true, false, true]
        );
        assert_eq!(benjamini_hochberg(&[0.5, 0.6], 0.1), [false, false]);
    }

    #[test]
    fn permutation_p_is_calibrated_on_a_bimodal_response() {
        // y: two clusters 10 sd apart (the 30-state cells' ramp / stable split), x independent
        // of y, 32 samples as in the default study. Under the null, P(p <= 0.05) = 0.05: 300
        // trials give 15 rejections, binomial sd 3.8; the 5 sd band is [0, 34].
        let mut s = Stream::new(21, 0);
        let mut rejections = 0;
        for t in 0..300 {
            let y: Vec<f64> = (0..32)
                .map(|_| if s.uniform() < 0.5 { 0.0 } else { 10.0 } + s.normal())
                .collect();
            let x: Vec<f64> = (0..32).map(|_| s.uniform()).collect();
            if first_order_permutation_p(&x, &y, false, 99, t) <= 0.05 {
                rejections += 1;
            }
        }
        assert!(rejections <= 34, "{rejections} of 300 rejected at 5 %");
        // A real dependence is found: y = 3 x + noise, 32 samples.
        let x: Vec<f64> = (0..32).map(|_| s.uniform()).collect();
        let y: Vec<f64> = x.iter().map(|x| 3.0 * x + 0.3 * s.normal()).collect();
        assert!(first_order_permutation_p(&x, &y, false, 199, 1) < 0.01);
    }
}
