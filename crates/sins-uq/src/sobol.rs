//! Grouped Sobol indices by the pick-freeze design (Saltelli et al. 2010, "Variance based
//! sensitivity analysis of model output", Comput. Phys. Commun. 181).
//!
//! Row `j` of matrix A is main sample `j` (already run); row `j` of matrix B is an independent
//! draw (`Slot::Resample`); row `j` of `A_B^g` is A's row with the inputs of group `g` taken
//! from B's row. With `f` the cell's value and `V` the variance of `f` over A and B:
//! - first order `S_g = mean(f(B) (f(A_B^g) - f(A))) / V` (Saltelli 2010, table 2 (b));
//! - total `ST_g = mean((f(A) - f(A_B^g))^2) / (2 V)` (Jansen 1999).
//!
//! Groups are the assumption file's `group`s that vary, plus [`NOISE_GROUP`]: the sensor-noise
//! realisation (every run's noise seed). The per-element draws (vibration phases) travel with
//! the group of their assumption. The design costs `(groups + 1) N` extra samples.

use crate::assumptions::AssumptionSet;
use crate::draw::Stream;
use crate::sample::{PICK_FREEZE_B, SampleOutcome, pick_freeze_study};
use crate::stats::{IndexInterval, quantile};
use serde::{Deserialize, Serialize};

pub use crate::draw::{NOISE_GROUP, groups, mixed_draw};

/// First-order and total index of one group, each with a 90 % bootstrap interval.
#[derive(Clone, Debug, PartialEq)]
pub struct PickFreeze {
    /// First-order index (Saltelli 2010).
    pub first: IndexInterval,
    /// Total index (Jansen).
    pub total: IndexInterval,
}

fn estimate(fa: &[f64], fb: &[f64], fab: &[f64], rows: &[usize]) -> (f64, f64) {
    let n = rows.len() as f64;
    let all: Vec<f64> = rows.iter().flat_map(|&j| [fa[j], fb[j]]).collect();
    let mean = all.iter().sum::<f64>() / all.len() as f64;
    let v = all.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (all.len() as f64 - 1.0);
    if v.is_nan() || v <= 0.0 {
        return (0.0, 0.0);
    }
    let s = rows.iter().map(|&j| fb[j] * (fab[j] - fa[j])).sum::<f64>() / n / v;
    let st = rows.iter().map(|&j| (fa[j] - fab[j]).powi(2)).sum::<f64>() / (2.0 * n * v);
    (s, st)
}

/// The indices of one group from the cell's values on A, B and `A_B^g` (row-aligned), with
/// percentile intervals from `resamples` bootstrap resamples of the rows (deterministic from
/// `seed`). Estimates are not clipped: a first-order index below 0 says the design is too small.
pub fn pick_freeze(fa: &[f64], fb: &[f64], fab: &[f64], resamples: usize, seed: u64) -> PickFreeze {
    let n = fa.len().min(fb.len()).min(fab.len());
    let rows: Vec<usize> = (0..n).collect();
    let (s, st) = estimate(fa, fb, fab, &rows);
    let mut stream = Stream::new(seed, 2);
    let (mut ds, mut dt) = (Vec::new(), Vec::new());
    let mut pick = vec![0; n];
    for _ in 0..resamples {
        for p in &mut pick {
            *p = ((stream.uniform() * n as f64) as usize).min(n.saturating_sub(1));
        }
        let (a, b) = estimate(fa, fb, fab, &pick);
        ds.push(a);
        dt.push(b);
    }
    let interval = |value: f64, d: &[f64]| IndexInterval {
        value,
        low: quantile(d, 0.05).min(value),
        high: quantile(d, 0.95).max(value),
    };
    PickFreeze {
        first: interval(s, &ds),
        total: interval(st, &dt),
    }
}

/// One group's indices for one cell, as the summary shows them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GroupIndex {
    /// Group name.
    pub group: String,
    /// First-order index (pick-freeze) and its 90 % bootstrap interval.
    pub first_order: [f64; 3],
    /// Total index (pick-freeze) and its 90 % bootstrap interval.
    pub total: [f64; 3],
}

/// One row of the design: the outcomes of A, B and every group's `A_B^g`.
pub type DesignRow<'a> = (&'a SampleOutcome, &'a SampleOutcome, Vec<&'a SampleOutcome>);

/// The rows of the design present in `outcomes`, for every index that has all of them, in
/// index order.
pub fn design_rows<'a>(set: &AssumptionSet, outcomes: &'a [SampleOutcome]) -> Vec<DesignRow<'a>> {
    let find = |study: &str, j: usize| outcomes.iter().find(|o| o.study == study && o.index == j);
    let n_groups = groups(set).len();
    (0..set.pick_freeze_samples.min(set.samples))
        .filter_map(|j| {
            let a = find("replica", j)?;
            let b = find(PICK_FREEZE_B, j)?;
            let mixes = (0..n_groups)
                .map(|g| find(&pick_freeze_study(g), j))
                .collect::<Option<Vec<_>>>()?;
            Some((a, b, mixes))
        })
        .collect()
}

/// Grouped indices of the cell whose (transformed) value `value` gives, over the design's `rows`
/// ([`design_rows`]); empty with fewer than 2 rows.
pub fn group_indices(
    set: &AssumptionSet,
    rows: &[DesignRow],
    value: &dyn Fn(&SampleOutcome) -> f64,
    resamples: usize,
    seed: u64,
) -> Vec<GroupIndex> {
    if rows.len() < 2 {
        return Vec::new();
    }
    let fa: Vec<f64> = rows.iter().map(|r| value(r.0)).collect();
    let fb: Vec<f64> = rows.iter().map(|r| value(r.1)).collect();
    groups(set)
        .into_iter()
        .enumerate()
        .map(|(g, group)| {
            let fab: Vec<f64> = rows.iter().map(|r| value(r.2[g])).collect();
            let r = pick_freeze(&fa, &fb, &fab, resamples, seed ^ ((g as u64 + 1) << 24));
            let triple = |i: &IndexInterval| [i.value, i.low, i.high];
            GroupIndex {
                group,
                first_order: triple(&r.first),
                total: triple(&r.total),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ishigami function, a = 7, b = 0.1, x ~ U(-pi, pi)^3: analytic indices S = (0.314, 0.442,
    /// 0), ST = (0.558, 0.442, 0.244) (Saltelli et al. 2008, Global Sensitivity Analysis, 3.6).
    #[test]
    fn ishigami_indices_match_the_analytic_values() {
        let f =
            |x: [f64; 3]| x[0].sin() + 7.0 * x[1].sin().powi(2) + 0.1 * x[2].powi(4) * x[0].sin();
        let mut s = Stream::new(9, 0);
        let mut u = || (s.uniform() * 2.0 - 1.0) * std::f64::consts::PI;
        let n = 20_000;
        let a: Vec<[f64; 3]> = (0..n).map(|_| [u(), u(), u()]).collect();
        let b: Vec<[f64; 3]> = (0..n).map(|_| [u(), u(), u()]).collect();
        let fa: Vec<f64> = a.iter().map(|x| f(*x)).collect();
        let fb: Vec<f64> = b.iter().map(|x| f(*x)).collect();
        let want = [(0.314, 0.558), (0.442, 0.442), (0.0, 0.244)];
        for (g, (s1, st)) in want.iter().enumerate() {
            let fab: Vec<f64> = (0..n)
                .map(|j| {
                    let mut x = a[j];
                    x[g] = b[j][g];
                    f(x)
                })
                .collect();
            let r = pick_freeze(&fa, &fb, &fab, 100, 3);
            assert!((r.first.value - s1).abs() < 0.03, "S{g} {:?}", r.first);
            assert!((r.total.value - st).abs() < 0.03, "ST{g} {:?}", r.total);
            assert!(
                r.first.low <= s1 + 0.01 && *s1 - 0.01 <= r.first.high,
                "{:?}",
                r.first
            );
            assert!(
                r.total.low <= st + 0.01 && *st - 0.01 <= r.total.high,
                "{:?}",
                r.total
            );
        }
    }
}
