//! Is the winner's magnitude the same in every run?
//!
//! An effect of the catalogue is a physical coefficient of the IMU: calibration run and
//! navigation runs share it. An effect outside the catalogue can still project onto one
//! candidate's signature in the stacked data, but the projection then depends on each run's
//! motion and temperatures, and the magnitude it implies differs from run to run. The test is
//! the likelihood ratio of one magnitude per run against one for all: the chi-square drop of
//! fitting the retained components with separate columns per run (each masked to its run's
//! rows, the shared calibration uncertainty kept in the metric) over the common fit,
//! `χ²(k (R − 1))` under a constant magnitude (the rank difference counts only the runs that
//! see the component), divided by the residual's quasi-likelihood inflation.

use crate::candidates::select;
use crate::problem::Problem;
use crate::report::{ConstancyTest, RunEstimate};
use crate::stats::chi2_sf;
use nalgebra::DMatrix;

/// What the test needs of the winner.
pub struct Winner<'a> {
    /// First column of the candidate in `Problem::a`.
    pub first: usize,
    /// Retained components.
    pub retained: &'a [usize],
    /// Their labels (all components of the kind).
    pub labels: &'a [&'static str],
    /// The linearisation point of the problem's columns (candidate units, per retained
    /// component; zero unless refined).
    pub offset: &'a [f64],
}

/// The constancy test of winner `w` on problem `p` whose runs are named `runs` (in stacking
/// order), `inflation ≥ 1` the quasi-likelihood factor, `level` the test level.
pub fn constancy(
    p: &Problem,
    w: &Winner<'_>,
    runs: &[String],
    inflation: f64,
    level: f64,
) -> Option<ConstancyTest> {
    let k = w.retained.len();
    if k == 0 || runs.len() < 2 {
        return None;
    }
    let common = select(&p.a, w.first, w.retained);
    let common_fit = p.gls.fit(&common);
    let mut sep = DMatrix::zeros(p.a.nrows(), k * runs.len());
    for r in 0..runs.len() {
        let rows = p.whitener.rows(r);
        for j in 0..k {
            sep.view_mut((rows.start, r * k + j), (rows.len(), 1))
                .copy_from(&common.view((rows.start, j), (rows.len(), 1)));
        }
    }
    let sep_fit = p.gls.fit(&sep);
    let dof = sep_fit.rank.saturating_sub(common_fit.rank);
    let dchi2 = (sep_fit.dchi2 - common_fit.dchi2).max(0.0) / inflation.max(1.0);
    let p_value = if dof == 0 {
        1.0
    } else {
        chi2_sf(dchi2, dof as f64)
    };
    let gram = p.gls.gram(&sep, &sep);
    let scale = gram.diagonal().iter().copied().fold(0.0, f64::max);
    let per_run = runs
        .iter()
        .enumerate()
        .map(|(r, name)| {
            let i = r * k;
            let seen = gram[(i, i)] > 1e-12 * scale;
            RunEstimate {
                run: name.clone(),
                label: w
                    .labels
                    .get(w.retained[0])
                    .copied()
                    .unwrap_or("?")
                    .to_string(),
                value: seen.then(|| sep_fit.theta[i] + w.offset[0]),
                sigma: seen.then(|| sep_fit.cov[(i, i)].max(0.0).sqrt()),
            }
        })
        .collect();
    Some(ConstancyTest {
        dchi2,
        dof,
        p_value,
        consistent: p_value > level,
        per_run,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::RunFitData;
    use nalgebra::DVector;

    /// A run of `n` rows with unit white noise `e`, one candidate column `col` and gap
    /// `theta · col + e`.
    fn run(name: &str, col: &DVector<f64>, theta: f64, e: &[f64]) -> RunFitData {
        let n = col.len();
        RunFitData {
            run: name.into(),
            gap: col * theta + DVector::from_column_slice(e),
            cov: DMatrix::identity(n, n),
            params: DMatrix::zeros(n, 0),
            columns: DMatrix::from_column_slice(n, 1, col.as_slice()),
            walks: vec![DMatrix::zeros(n, 0); 6],
        }
    }

    fn test_of(thetas: [f64; 2]) -> ConstancyTest {
        let n = 40;
        let col = DVector::from_fn(n, |i, _| (i as f64 * 0.3).sin() + 0.5);
        // Fixed small "noise" (|e| < 0.5) so the result is exact and repeatable.
        let e: Vec<f64> = (0..n)
            .map(|i| 0.4 * ((i * 7 % 11) as f64 / 10.0 - 0.5))
            .collect();
        let (a, b) = (run("a", &col, thetas[0], &e), run("b", &col, thetas[1], &e));
        let p = Problem::new(&[&a, &b]).expect("problem");
        let w = Winner {
            first: 0,
            retained: &[0],
            labels: &["x"],
            offset: &[0.0],
        };
        constancy(&p, &w, &["a".into(), "b".into()], 1.0, 1e-3).expect("test")
    }

    #[test]
    fn one_magnitude_in_both_runs_is_constant_and_opposite_ones_are_not() {
        let same = test_of([3.0, 3.0]);
        assert_eq!(same.dof, 1);
        assert!(same.consistent && same.dchi2 < 1e-20, "{same:?}");
        let opposite = test_of([3.0, -3.0]);
        // Separate fits recover ±3 exactly (same noise in both runs, so both are off by the
        // same amount); the drop over the common fit is (θ_a − θ_b)² / (2 σ²), σ² = 1/|col|².
        let (va, vb) = (
            opposite.per_run[0].value.expect("seen"),
            opposite.per_run[1].value.expect("seen"),
        );
        assert!((va - vb - 6.0).abs() < 1e-9, "{opposite:?}");
        let s = opposite.per_run[0].sigma.expect("seen");
        assert!((opposite.dchi2 - 36.0 / (2.0 * s * s)).abs() < 1e-6 * opposite.dchi2);
        assert!(
            !opposite.consistent && opposite.p_value < 1e-10,
            "{opposite:?}"
        );
    }
}
