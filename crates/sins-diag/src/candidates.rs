//! Fitting the candidates of the catalogue to the gap.
//!
//! - Deterministic kinds (linear, or linearised like the thermal lag): GLS on components chosen
//!   by forward selection (the best single component first, then others while each adds a
//!   chi-square drop of at least `z_keep²`; the blind question is usually "which axis"), the
//!   chi-square drop of the retained model, its BIC improvement and a Bonferroni-corrected tail
//!   probability over every component of the catalogue.
//! - Random processes (bias random walks): a noise term `q V Vᵀ` added to the twin's
//!   covariance, `q` fitted per axis by maximum likelihood; evidence `2 Δ log L` with the
//!   boundary (`q ≥ 0`) halving the tail probability.

use crate::gls::Fit;
use crate::problem::Problem;
use crate::stats::chi2_isf;
use nalgebra::{DMatrix, DVector};

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

/// A random-walk candidate's fit on one bias axis.
#[derive(Clone, Debug)]
pub struct WalkFit {
    /// Fitted intensity (SI, rad/s/√s or m/s²/√s).
    pub intensity: f64,
    /// Its one-sigma from the likelihood (half the width of the `Δ(-2 log L) = 1` interval).
    pub sigma: f64,
    /// `2 (log L(q̂) - log L(0))`.
    pub dchi2: f64,
    /// `gᵀ S(q̂)⁻¹ g`: the residual chi-square with the noise term.
    pub residual_chi2: f64,
}

/// Likelihood of the gap with a noise term `q V Vᵀ` (whitened factor `v`) added.
struct WalkLikelihood {
    uu: DMatrix<f64>,
    uv: DMatrix<f64>,
    vv: DMatrix<f64>,
    ug: DVector<f64>,
    vg: DVector<f64>,
    gg: f64,
}

impl WalkLikelihood {
    fn new(p: &Problem, v: &DMatrix<f64>) -> Self {
        let g = &p.gls.g;
        Self {
            uu: p.u.transpose() * &p.u,
            uv: p.u.transpose() * v,
            vv: v.transpose() * v,
            ug: p.u.transpose() * g,
            vg: v.transpose() * g,
            gg: g.dot(g),
        }
    }

    /// `-2 log L(q)` up to a constant common to every `q`.
    fn m2ll(&self, a: f64) -> f64 {
        self.eval(a).0
    }

    /// `(-2 log L(q), gᵀ S(q)⁻¹ g)` with `q = a²`.
    fn eval(&self, a: f64) -> (f64, f64) {
        let (np, nv) = (self.uu.nrows(), self.vv.nrows());
        let q = a * a;
        let mut m = DMatrix::<f64>::identity(np + nv, np + nv);
        let mut top = m.view_mut((0, 0), (np, np));
        top += &self.uu;
        m.view_mut((0, np), (np, nv)).copy_from(&(&self.uv * a));
        m.view_mut((np, 0), (nv, np))
            .copy_from(&(self.uv.transpose() * a));
        let mut bottom = m.view_mut((np, np), (nv, nv));
        bottom += &self.vv * q;
        let mut b = DVector::zeros(np + nv);
        b.rows_mut(0, np).copy_from(&self.ug);
        b.rows_mut(np, nv).copy_from(&(&self.vg * a));
        // I + a PSD matrix: positive definite unless the data hold NaN.
        match m.cholesky() {
            Some(c) => {
                let logdet: f64 = c.l().diagonal().iter().map(|d| 2.0 * d.ln()).sum();
                let x = c.solve(&b);
                let quad = self.gg - b.dot(&x);
                (logdet + quad, quad)
            }
            None => (f64::INFINITY, f64::INFINITY),
        }
    }
}

/// Maximum-likelihood intensity of a random walk with whitened factor `v`; `typical` (SI)
/// sets the search range (1e-5 to 1e3 times it).
pub fn fit_walk(p: &Problem, v: &DMatrix<f64>, typical: f64) -> WalkFit {
    let lik = WalkLikelihood::new(p, v);
    let f0 = lik.m2ll(0.0);
    let grid: Vec<f64> = (-20..=12)
        .map(|k| typical * 10f64.powf(k as f64 / 4.0))
        .collect();
    let vals: Vec<f64> = grid.iter().map(|&a| lik.m2ll(a)).collect();
    let (kbest, &fbest) = vals
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .unwrap_or((0, &f0));
    if fbest >= f0 {
        // The maximum is at q = 0: sigma from where -2 log L has risen by 1.
        let up = grid
            .iter()
            .zip(&vals)
            .find(|(_, f)| **f > f0 + 1.0)
            .map_or(grid[grid.len() - 1], |(a, _)| *a);
        return WalkFit {
            intensity: 0.0,
            sigma: up,
            dchi2: 0.0,
            residual_chi2: lik.eval(0.0).1,
        };
    }
    // Golden section in log a around the best grid point.
    let (mut lo, mut hi) = (
        grid[kbest.saturating_sub(1)].ln(),
        grid[(kbest + 1).min(grid.len() - 1)].ln(),
    );
    let r = 0.618_033_988_749_895;
    for _ in 0..40 {
        let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if lik.m2ll(x1.exp()) < lik.m2ll(x2.exp()) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    let a_hat = (0.5 * (lo + hi)).exp();
    let f_hat = lik.m2ll(a_hat);
    // One-sigma interval: -2 log L = f_hat + 1 on either side (bisection in a).
    let cross = |mut inside: f64, mut outside: f64| {
        for _ in 0..60 {
            let mid = 0.5 * (inside + outside);
            if lik.m2ll(mid) < f_hat + 1.0 {
                inside = mid;
            } else {
                outside = mid;
            }
        }
        0.5 * (inside + outside)
    };
    let lower = if lik.m2ll(0.0) > f_hat + 1.0 {
        cross(a_hat, 0.0)
    } else {
        0.0
    };
    let mut far = a_hat * 2.0;
    while lik.m2ll(far) < f_hat + 1.0 && far < 1e6 * typical {
        far *= 2.0;
    }
    let upper = cross(a_hat, far);
    WalkFit {
        intensity: a_hat,
        sigma: 0.5 * (upper - lower),
        dchi2: (f0 - f_hat).max(0.0),
        residual_chi2: lik.eval(a_hat).1,
    }
}
