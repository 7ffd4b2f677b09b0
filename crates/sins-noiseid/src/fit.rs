//! Weighted least-squares fit of the Allan variance by the noise terms.
//!
//! - **Weights**: an overlapping Allan variance with `ν` equivalent degrees of freedom is
//!   `σ² χ²_ν/ν`, variance `V = 2σ⁴/ν`, taken at the *model's* value `M` (iterated six times
//!   from the data's own value), which removes the downward bias of weighting by the noisy
//!   estimate itself; `ν` is computed for the noise type of the term that dominates `M` at that
//!   `τ` (white phase, white frequency, flicker frequency near a Gauss-Markov peak, random-walk
//!   frequency). The points of one channel are correlated (same data at every `τ`): the fit
//!   is generalised least squares with `Cov_ij = ρ_ij √(V_i V_j)`, `ρ` from the model's
//!   spectrum ([`crate::spectrum`]); channels (axes) are independent blocks. A known offset
//!   (quantization at rest) adds an independent `(0.05 × offset)²` for its model error, and
//!   the degrees of freedom are those of the fitted noise, not of the offset.
//! - **Non-negativity**: every subset of the enabled terms is solved unconstrained; the
//!   feasible subset (all `θ > 0`) of least weighted residual wins (an exact non-negative least
//!   squares for four terms). A term left out is reported as 0 with a one-sided 95 % upper
//!   bound `max(θ_f, 0) + 1.645 σ_f` from the fit with it forced in.
//! - **Covariance** of `θ`: the inverse normal matrix of the final generalised fit (the
//!   covariance taken as known); the Gauss-Markov σ² also carries the correlation time's
//!   uncertainty, `(∂θ/∂ ln T)² σ²_{ln T}` from the neighbouring grid fits.
//! - **Gauss-Markov correlation time**: profile of `−2 ln L = Σ (y − M)²/V + ln V` (Gaussian
//!   approximation of the chi-square likelihood, `V = 2M²/ν`) over a log grid; the minimum is
//!   refined by a parabola in `ln T` and its 1-sigma is `√(2/∂²(−2 ln L)/∂(ln T)²)`
//!   (infinite when the minimum lies on the edge of the grid or the curve is flat).

use crate::allan::PooledTau;
use crate::model::{TERMS, Term};
use crate::spectrum::Grid;
use nalgebra::{DMatrix, DVector};

/// One Allan-variance point of a fit.
pub(crate) struct Point<'a> {
    /// Averaging time (s).
    pub tau_s: f64,
    /// Pooled estimate (rate unit²).
    pub avar: f64,
    /// Known part of the model (the quantization of a gyro at rest).
    pub offset: f64,
    /// Independent block (axis) the point belongs to.
    pub block: usize,
    /// Its second differences (degrees of freedom).
    pub pooled: &'a PooledTau,
}

/// The points of a fit with what does not depend on the parameters.
pub(crate) struct FitData<'a> {
    points: Vec<Point<'a>>,
    grid: Grid,
    filters: Vec<Vec<f64>>,
    blocks: Vec<Vec<usize>>,
}

impl<'a> FitData<'a> {
    /// Prepare `points` (samples every `h_s`).
    pub fn new(points: Vec<Point<'a>>, h_s: f64) -> Self {
        let tau_max = points.iter().map(|p| p.tau_s).fold(h_s, f64::max);
        let grid = Grid::new(tau_max, h_s);
        let filters = points.iter().map(|p| grid.filter(p.tau_s)).collect();
        let nb = points.iter().map(|p| p.block + 1).max().unwrap_or(0);
        let blocks = (0..nb)
            .map(|b| {
                (0..points.len())
                    .filter(|&i| points[i].block == b)
                    .collect()
            })
            .collect();
        Self {
            points,
            grid,
            filters,
            blocks,
        }
    }
}

/// A fit at one correlation time.
#[derive(Clone, Debug)]
pub(crate) struct LinearFit {
    /// Parameters `θ` in [`TERMS`] order (0 for terms left out).
    pub theta: [f64; 4],
    /// 1-sigma of each `θ` (0 for terms left out).
    pub sigma: [f64; 4],
    /// One-sided 95 % upper bound of each enabled term left out.
    pub upper95: [Option<f64>; 4],
    /// `−2 ln L` (Gaussian approximation).
    pub m2ll: f64,
    /// Generalised residual sum of squares.
    pub chi2: f64,
    /// Model Allan variance at each point.
    pub model: Vec<f64>,
}

const Z95: f64 = 1.644_853_626_951_472_2;

/// Relative 1-sigma of a known offset (the quantization model of a gyro at rest: the
/// realised sawtooth average departs from its expectation by a few per cent, see
/// `tests/it/analytic.rs`); independent between points.
const OFFSET_UNCERTAINTY: f64 = 0.05;

struct Solved {
    theta: [f64; 4],
    cov_diag: [f64; 4],
    sse: f64,
}

/// Unweighted least squares of the whitened `rows`, `y` on the terms in `subset`.
fn solve(rows: &DMatrix<f64>, y: &DVector<f64>, subset: &[usize]) -> Option<Solved> {
    let (n, p) = (rows.nrows(), subset.len());
    if p == 0 || n < p {
        return None;
    }
    let mut a = DMatrix::<f64>::zeros(n, p);
    for (j, &t) in subset.iter().enumerate() {
        a.set_column(j, &rows.column(t));
    }
    let scale: Vec<f64> = (0..p).map(|j| a.column(j).norm()).collect();
    if scale.iter().any(|s| *s <= 0.0 || !s.is_finite()) {
        return None;
    }
    for (j, s) in scale.iter().enumerate() {
        a.column_mut(j).scale_mut(1.0 / s);
    }
    let chol = (a.transpose() * &a).cholesky()?;
    let x = chol.solve(&(a.transpose() * y));
    let inv = chol.inverse();
    let r = &a * &x - y;
    let mut theta = [0.0; 4];
    let mut cov_diag = [0.0; 4];
    for (j, &t) in subset.iter().enumerate() {
        theta[t] = x[j] / scale[j];
        cov_diag[t] = inv[(j, j)] / (scale[j] * scale[j]);
    }
    Some(Solved {
        theta,
        cov_diag,
        sse: r.norm_squared(),
    })
}

/// Whitened design, data and `ln det` of the covariance at the current model.
struct Whitened {
    rows: DMatrix<f64>,
    y: DVector<f64>,
    ln_det: f64,
}

fn whiten(
    data: &FitData<'_>,
    basis: &[[f64; 4]],
    model: &[f64],
    theta: Option<&[f64; 4]>,
    corr_s: f64,
) -> Whitened {
    let pts = &data.points;
    let n = pts.len();
    let mut rows = DMatrix::<f64>::zeros(n, 4);
    let mut y = DVector::<f64>::zeros(n);
    let mut ln_det = 0.0;
    let th = theta.copied().unwrap_or([0.0, 1.0, 0.0, 0.0]);
    for idx in &data.blocks {
        let spec = data.grid.spectrum(&th, corr_s, 0.0);
        let filters: Vec<Vec<f64>> = idx.iter().map(|&i| data.filters[i].clone()).collect();
        let rho = data.grid.correlation(&filters, &spec);
        let sd: Vec<f64> = idx
            .iter()
            .map(|&i| {
                let p = &pts[i];
                let m = (model[i] - p.offset)
                    .max(1e-9 * p.avar)
                    .max(f64::MIN_POSITIVE);
                let nu = p.pooled.edf(dominant(&basis[i], theta).noise_type());
                (2.0 / nu).sqrt() * m
            })
            .collect();
        let nb = idx.len();
        let mut v = DMatrix::<f64>::from_fn(nb, nb, |a, b| rho[(a, b)] * sd[a] * sd[b]);
        for (a, &i) in idx.iter().enumerate() {
            v[(a, a)] += (OFFSET_UNCERTAINTY * pts[i].offset).powi(2);
        }
        // A little diagonal loading keeps nearly collinear octaves positive definite.
        for a in 0..nb {
            v[(a, a)] *= 1.0 + 1e-9;
        }
        let chol = match v.clone().cholesky() {
            Some(c) => c,
            None => {
                // Fall back to independent points.
                let d = DMatrix::from_diagonal(&DVector::from_fn(nb, |a, _| sd[a] * sd[a]));
                match d.cholesky() {
                    Some(c) => c,
                    None => continue,
                }
            }
        };
        let l = chol.l();
        ln_det += 2.0 * (0..nb).map(|a| l[(a, a)].ln()).sum::<f64>();
        let mut a_b = DMatrix::<f64>::from_fn(nb, 4, |a, j| basis[idx[a]][j]);
        let mut y_b = DVector::<f64>::from_fn(nb, |a, _| pts[idx[a]].avar - pts[idx[a]].offset);
        l.solve_lower_triangular_mut(&mut a_b);
        l.solve_lower_triangular_mut(&mut y_b);
        for (a, &i) in idx.iter().enumerate() {
            rows.set_row(i, &a_b.row(a));
            y[i] = y_b[a];
        }
    }
    Whitened { rows, y, ln_det }
}

/// Fit the enabled terms at correlation time `correlation_s`.
pub(crate) fn fit_fixed(data: &FitData<'_>, enabled: [bool; 4], correlation_s: f64) -> LinearFit {
    let points = &data.points;
    let basis: Vec<[f64; 4]> = points
        .iter()
        .map(|p| std::array::from_fn(|j| TERMS[j].basis(p.tau_s, correlation_s)))
        .collect();
    let on: Vec<usize> = (0..4).filter(|&j| enabled[j]).collect();
    let mut model: Vec<f64> = points.iter().map(|p| p.avar).collect();
    let mut best: Option<(Solved, Vec<usize>)> = None;
    let mut w = whiten(data, &basis, &model, None, correlation_s);
    for _ in 0..6 {
        best = None;
        for mask in 1u32..(1 << on.len()) {
            let subset: Vec<usize> = on
                .iter()
                .enumerate()
                .filter(|(k, _)| mask & (1 << k) != 0)
                .map(|(_, &t)| t)
                .collect();
            let Some(s) = solve(&w.rows, &w.y, &subset) else {
                continue;
            };
            if subset
                .iter()
                .any(|&t| s.theta[t] <= 0.0 || s.theta[t].is_nan())
            {
                continue;
            }
            if best.as_ref().is_none_or(|(b, _)| s.sse < b.sse) {
                best = Some((s, subset));
            }
        }
        for (i, p) in points.iter().enumerate() {
            let fitted: f64 = best
                .as_ref()
                .map_or(0.0, |(b, _)| (0..4).map(|j| b.theta[j] * basis[i][j]).sum());
            model[i] = p.offset + fitted;
        }
        let theta = best.as_ref().map_or([0.0; 4], |b| b.0.theta);
        w = whiten(data, &basis, &model, Some(&theta), correlation_s);
    }
    // Final pass at the final covariance.
    let (theta, sigma, active, chi2) = match &best {
        Some((_, sub)) => match solve(&w.rows, &w.y, sub) {
            Some(s) => (
                s.theta,
                std::array::from_fn(|j| s.cov_diag[j].max(0.0).sqrt()),
                sub.clone(),
                s.sse,
            ),
            None => ([0.0; 4], [0.0; 4], Vec::new(), w.y.norm_squared()),
        },
        None => ([0.0; 4], [0.0; 4], Vec::new(), w.y.norm_squared()),
    };
    let mut upper95 = [None; 4];
    for &t in on.iter().filter(|t| !active.contains(t)) {
        let mut forced = active.clone();
        forced.push(t);
        forced.sort_unstable();
        upper95[t] = Some(match solve(&w.rows, &w.y, &forced) {
            Some(s) => s.theta[t].max(0.0) + Z95 * s.cov_diag[t].max(0.0).sqrt(),
            None => f64::INFINITY,
        });
    }
    LinearFit {
        theta,
        sigma,
        upper95,
        m2ll: chi2 + w.ln_det,
        chi2,
        model,
    }
}

/// The fitted term that dominates the model at a point (white before the first fit).
fn dominant(row: &[f64; 4], theta: Option<&[f64; 4]>) -> Term {
    let Some(theta) = theta else {
        return Term::White;
    };
    let mut best = (Term::White, 0.0);
    for (j, t) in TERMS.iter().enumerate() {
        let v = theta[j] * row[j];
        if v > best.1 {
            best = (*t, v);
        }
    }
    best.0
}

/// A fit with the Gauss-Markov correlation time profiled.
#[derive(Clone, Debug)]
pub(crate) struct ProfiledFit {
    /// The fit at the best correlation time.
    pub fit: LinearFit,
    /// Best correlation time (s; infinite when the Gauss-Markov term is off or zero).
    pub correlation_s: f64,
    /// 1-sigma of `ln T` (infinite when not identified).
    pub ln_correlation_sigma: f64,
}

/// Fit with the correlation time profiled over `grid_s` (log spaced, increasing).
pub(crate) fn fit_profiled(data: &FitData<'_>, enabled: [bool; 4], grid_s: &[f64]) -> ProfiledFit {
    if !enabled[2] || grid_s.len() < 3 {
        return ProfiledFit {
            fit: fit_fixed(data, enabled, f64::INFINITY),
            correlation_s: f64::INFINITY,
            ln_correlation_sigma: f64::INFINITY,
        };
    }
    let fits: Vec<LinearFit> = grid_s
        .iter()
        .map(|&t| fit_fixed(data, enabled, t))
        .collect();
    let mut k = 0;
    for (i, f) in fits.iter().enumerate() {
        if f.m2ll < fits[k].m2ll {
            k = i;
        }
    }
    let edge = k == 0 || k + 1 == grid_s.len();
    let (ln_t, ln_sigma) = if edge {
        (grid_s[k].ln(), f64::INFINITY)
    } else {
        let dx = (grid_s[k + 1] / grid_s[k]).ln();
        let (lm, l0, lp) = (fits[k - 1].m2ll, fits[k].m2ll, fits[k + 1].m2ll);
        let d2 = (lm - 2.0 * l0 + lp) / (dx * dx);
        if d2 > 0.0 {
            let shift = -dx * (lp - lm) / (2.0 * (lp - 2.0 * l0 + lm));
            (grid_s[k].ln() + shift.clamp(-dx, dx), (2.0 / d2).sqrt())
        } else {
            (grid_s[k].ln(), f64::INFINITY)
        }
    };
    let t = ln_t.exp();
    let mut fit = fit_fixed(data, enabled, t);
    // The correlation time's uncertainty into the Gauss-Markov σ².
    if ln_sigma.is_finite() {
        let dx = (grid_s[k + 1] / grid_s[k]).ln();
        let slope = (fits[k + 1].theta[2] - fits[k - 1].theta[2]) / (2.0 * dx);
        fit.sigma[2] = (fit.sigma[2].powi(2) + (slope * ln_sigma).powi(2)).sqrt();
    }
    if fit.theta[2] > 0.0 {
        ProfiledFit {
            fit,
            correlation_s: t,
            ln_correlation_sigma: ln_sigma,
        }
    } else {
        ProfiledFit {
            fit,
            correlation_s: f64::INFINITY,
            ln_correlation_sigma: f64::INFINITY,
        }
    }
}
