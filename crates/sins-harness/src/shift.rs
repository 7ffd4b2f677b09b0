//! The shift between two independent samples, free of any distribution: the Hodges-Lehmann
//! estimate (the median of every difference `candidate − baseline`) and its confidence bounds
//! from the exact Mann-Whitney distribution (Lehmann, *Nonparametrics*, 1975, ch. 2; Hollander,
//! Wolfe & Chicken, *Nonparametric Statistical Methods*, 2014, §4.3).
//!
//! With `n` baseline and `m` candidate values, the `n·m` differences sorted give the bounds:
//! the one-sided lower bound at level `α` is the `k`-th smallest difference, `k` the largest
//! count with `P(U ≤ k − 1) ≤ α` for the Mann-Whitney statistic `U` under "no shift". The bound
//! holds for any continuous distribution of the values (the run-to-run spread of a maximum
//! horizontal error is skewed, so a t interval would not). The law of `U` is computed exactly
//! (the rank sums of `n` of `n + m` ranks) up to [`EXACT_MAX`] values in all, and by its normal
//! approximation with a continuity correction beyond.

/// Largest `n + m` for which the law of `U` is computed exactly.
pub const EXACT_MAX: usize = 200;

/// The shift of the candidate's values over the baseline's (their unit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shift {
    /// Hodges-Lehmann estimate: the median of the pairwise differences.
    pub estimate: f64,
    /// One-sided lower bound at the level asked for (−∞ when the samples are too small to
    /// give one at that level).
    pub lower: f64,
    /// One-sided upper bound at the same level (+∞ when too small).
    pub upper: f64,
}

/// The shift of `candidate` over `baseline` with one-sided bounds at level `alpha` each (so
/// `[lower, upper]` covers the true shift with probability at least `1 − 2 alpha`). `None`
/// when a sample is empty or holds a value that is not finite.
pub fn shift(baseline: &[f64], candidate: &[f64], alpha: f64) -> Option<Shift> {
    let (n, m) = (baseline.len(), candidate.len());
    if n == 0 || m == 0 || baseline.iter().chain(candidate).any(|v| !v.is_finite()) {
        return None;
    }
    let mut d: Vec<f64> = candidate
        .iter()
        .flat_map(|y| baseline.iter().map(move |x| y - x))
        .collect();
    d.sort_by(f64::total_cmp);
    let nm = d.len();
    let estimate = median_of_sorted(&d);
    let k = bound_rank(n, m, alpha);
    let (lower, upper) = if k == 0 {
        (f64::NEG_INFINITY, f64::INFINITY)
    } else {
        (d[k - 1], d[nm - k])
    };
    Some(Shift {
        estimate,
        lower,
        upper,
    })
}

/// The median of values sorted in increasing order (NaN when there are none).
pub fn median_of_sorted(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => sorted[n / 2],
        _ => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}

/// Quantile `p` in [0, 1] of the finite `values` (linear interpolation between order
/// statistics, type 7). NaN for no finite values. The one quantile of the workspace's studies
/// (`sins-uq` re-exports it).
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

/// The largest `k` with `P(U ≤ k − 1) ≤ alpha` under no shift (0 when even `P(U = 0)`
/// exceeds `alpha`). Remembered per thread for the last few `(n, m, alpha)`: a gate compares
/// every cell at one level, and `gate --power` thousands of draws of one size.
pub fn bound_rank(n: usize, m: usize, alpha: f64) -> usize {
    /// `(n, m, alpha's bits)` and its bound rank.
    type Known = ((usize, usize, u64), usize);
    thread_local! {
        static KNOWN: std::cell::RefCell<Vec<Known>> =
            const { std::cell::RefCell::new(Vec::new()) };
    }
    let key = (n, m, alpha.to_bits());
    if let Some(k) = KNOWN.with(|c| c.borrow().iter().find(|e| e.0 == key).map(|e| e.1)) {
        return k;
    }
    let k = bound_rank_uncached(n, m, alpha);
    KNOWN.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() >= 16 {
            c.remove(0);
        }
        c.push((key, k));
    });
    k
}

fn bound_rank_uncached(n: usize, m: usize, alpha: f64) -> usize {
    let half = n * m / 2;
    if n + m <= EXACT_MAX {
        let cdf = exact_cdf(n, m);
        return cdf.iter().take_while(|p| **p <= alpha).count().min(half);
    }
    (0..half)
        .take_while(|&u| normal_cdf(n, m, u) <= alpha)
        .count()
}

/// `P(U ≤ u)` for `u = 0 ..= n·m` under no shift, exactly: `U` is the rank sum of the
/// candidate's values less its least value, and the number of `m`-subsets of `n + m` ranks
/// with each sum is counted by dynamic programming (as f64: C(200, 100) ≈ 9e58 fits).
fn exact_cdf(n: usize, m: usize) -> Vec<f64> {
    let total = n + m;
    let max_sum = m * total;
    // ways[k][s]: subsets of size k of the ranks seen so far with rank sum s (ranks 0-based).
    let mut ways = vec![vec![0.0f64; max_sum + 1]; m + 1];
    ways[0][0] = 1.0;
    for r in 0..total {
        for k in (1..=m.min(r + 1)).rev() {
            let (lo, hi) = ways.split_at_mut(k);
            let prev = &lo[k - 1];
            for s in r..=max_sum {
                hi[0][s] += prev[s - r];
            }
        }
    }
    let least = m * (m - 1) / 2;
    let counts = &ways[m][least..=least + n * m];
    let all: f64 = counts.iter().sum();
    let mut acc = 0.0;
    counts
        .iter()
        .map(|c| {
            acc += c;
            acc / all
        })
        .collect()
}

/// `P(U ≤ u)` by the normal approximation with a continuity correction.
fn normal_cdf(n: usize, m: usize, u: usize) -> f64 {
    let (n, m) = (n as f64, m as f64);
    let mean = n * m / 2.0;
    let sd = (n * m * (n + m + 1.0) / 12.0).sqrt();
    let z = (u as f64 + 0.5 - mean) / sd;
    statrs::function::erf::erfc(-z / std::f64::consts::SQRT_2) / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_exact_law_matches_the_textbook_tables() {
        // n = m = 4: 70 arrangements, P(U = 0) = 1/70, P(U <= 1) = 2/70, P(U <= 2) = 4/70.
        let c = exact_cdf(4, 4);
        assert!((c[0] - 1.0 / 70.0).abs() < 1e-15);
        assert!((c[1] - 2.0 / 70.0).abs() < 1e-15);
        assert!((c[2] - 4.0 / 70.0).abs() < 1e-15);
        assert!((c[16] - 1.0).abs() < 1e-15);
        // Symmetric about nm/2.
        for u in 0..16 {
            assert!((c[u] - (1.0 - c[15 - u])).abs() < 1e-12, "{u}");
        }
        // n = m = 8, one-sided 0.025: the critical U is 13 (tables), so k = 14.
        assert_eq!(bound_rank(8, 8, 0.025), 14);
        // Unequal sizes, n = 5, m = 7, by enumerating all 792 arrangements: P(U <= 6) =
        // 0.0366, P(U <= 7) = 0.0530, so at one-sided 0.05 the critical U is 6 and k = 7.
        assert_eq!(bound_rank(5, 7, 0.05), 7);
        // Too few for the level: n = m = 3, P(U = 0) = 0.05 > 0.01.
        assert_eq!(bound_rank(3, 3, 0.01), 0);
    }

    #[test]
    fn the_normal_approximation_agrees_with_the_exact_law_where_both_apply() {
        for (n, m) in [(40, 40), (60, 90)] {
            let c = exact_cdf(n, m);
            for q in [0.001, 0.01, 0.05] {
                let exact = c.iter().take_while(|p| **p <= q).count();
                let mut approx = 0;
                while normal_cdf(n, m, approx) <= q {
                    approx += 1;
                }
                // Within 1 % of the rank (the normal tail is a little light at 0.001).
                assert!(
                    (exact.abs_diff(approx) as f64) <= 0.01 * exact as f64,
                    "{n} {m} {q}: {exact} {approx}"
                );
            }
        }
    }
}
