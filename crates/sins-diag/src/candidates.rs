//! Fitting the candidates of the catalogue to the gap.
//!
//! - Deterministic kinds (linear, or linearised like the thermal lag): GLS on components chosen
//!   by forward selection (the best single component first, then others while each adds a
//!   chi-square drop of at least `z_keep²`; the blind question is usually "which axis"), the
//!   chi-square drop of the retained model, its BIC improvement and a Bonferroni-corrected tail
//!   probability over every component of the catalogue.
//! - Random processes (bias random walks): see [`crate::walk`].

use crate::gls::Fit;
use crate::problem::Problem;
use crate::stats::chi2_isf;
use nalgebra::DMatrix;

/// A deterministic candidate's fit.
#[derive(Clone, Debug)]
pub struct RegressionFit {
    /// Components kept (indices into the candidate's components).
    pub retained: Vec<usize>,
    /// Fit of the retained components (same order).
    pub fit: Fit,
    /// One-sigma of each component fitted alone (candidate unit; infinite if unidentifiable).
    pub sigma_alone: Vec<f64>,
}

/// Fit the candidate whose whitened columns are `first..first + n` of `p.a`.
pub fn fit_regression(p: &Problem, first: usize, n: usize, z_keep: f64) -> RegressionFit {
    let cols: Vec<usize> = (first..first + n).collect();
    let sigma_alone: Vec<f64> = cols
        .iter()
        .map(|&c| {
            let a = p.a.columns(c, 1).into_owned();
            let g = p.gls.gram(&a, &a)[(0, 0)];
            if g > 0.0 {
                1.0 / g.sqrt()
            } else {
                f64::INFINITY
            }
        })
        .collect();
    // Forward selection: add the component that lowers the chi-square most while the drop is
    // worth at least `z_keep²` (a |z| of `z_keep` for the added component); components with no
    // signal at all cannot be fitted.
    let usable: Vec<usize> = (0..n).filter(|&k| sigma_alone[k].is_finite()).collect();
    let (retained, current) = forward_select(p, first, &usable, Vec::new(), z_keep * z_keep);
    let fit = current.unwrap_or_else(|| p.gls.fit(&select(&p.a, first, &[])));
    RegressionFit {
        retained,
        fit,
        sigma_alone,
    }
}

/// Forward selection among `usable` components of the candidate at `first`, starting from
/// `retained`: add the component that lowers the chi-square most while it lowers it by at least
/// `min_gain` (the first component of an empty start is always added). Returns the components
/// and the fit of all of them (`None` when there is none).
pub fn forward_select(
    p: &Problem,
    first: usize,
    usable: &[usize],
    mut retained: Vec<usize>,
    min_gain: f64,
) -> (Vec<usize>, Option<Fit>) {
    let mut current: Option<Fit> =
        (!retained.is_empty()).then(|| p.gls.fit(&select(&p.a, first, &retained)));
    loop {
        let best = usable
            .iter()
            .filter(|k| !retained.contains(k))
            .map(|&k| {
                let mut trial = retained.clone();
                trial.push(k);
                let fit = p.gls.fit(&select(&p.a, first, &trial));
                (k, fit)
            })
            .max_by(|a, b| a.1.dchi2.total_cmp(&b.1.dchi2));
        let Some((k, fit)) = best else { break };
        let gain = fit.dchi2 - current.as_ref().map_or(0.0, |f| f.dchi2);
        if current.is_some() && gain < min_gain {
            break;
        }
        retained.push(k);
        current = Some(fit);
    }
    (retained, current)
}

/// Columns `first + k` for `k` in `which`.
pub fn select(a: &DMatrix<f64>, first: usize, which: &[usize]) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(a.nrows(), which.len());
    for (j, &k) in which.iter().enumerate() {
        out.set_column(j, &a.column(first + k));
    }
    out
}

/// Magnitude detected with 90 % probability by a chi-square test of one degree of freedom at
/// tail probability `p_single`, for a one-sigma `sigma`.
pub fn detectable(sigma: f64, p_single: f64) -> f64 {
    (chi2_isf(p_single, 1.0).sqrt() + 1.281_551_565_545) * sigma
}
