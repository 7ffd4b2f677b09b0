//! Bias random walks as candidates: a noise term `q V Vᵀ` added to the twin's covariance, `q`
//! fitted per axis by maximum likelihood (evidence `2 Δ log L`, the boundary `q ≥ 0` halving
//! the tail probability), and a whiteness test of the fit.
//!
//! A noise term with a free intensity can absorb almost any slow signature: a bias step or a
//! bias oscillation is "explained" by a walk whose increments happen to add up to it. A walk,
//! though, has independent increments. Under the fitted walk the smoothed increments
//! `ŵ = a Vᵀ S⁻¹ g` (unit-intensity latent increments, `S = I + U Uᵀ + a² V Vᵀ` in the whitened
//! space) are Gaussian with covariance `C = a² Vᵀ S⁻¹ V`; standardised by `diag(C)` they should
//! show no outlier (a step is one increment many sigmas out) and no lag-one correlation beyond
//! what `C` itself implies (an oscillation or a smooth drift correlates neighbouring
//! increments). [`WalkShape`] holds both statistics; a walk that fails them does not pass.

use crate::problem::Problem;
use crate::stats::chi2_sf;
use nalgebra::{DMatrix, DVector};

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
    /// Whiteness of the smoothed increments at `q̂` (`None` when `q̂ = 0`).
    pub shape: Option<WalkShape>,
}

/// Whiteness statistics of a walk fit's smoothed increments (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkShape {
    /// Largest |z| of a standardised smoothed increment.
    pub max_abs_z: f64,
    /// Increments tested.
    pub increments: usize,
    /// The lag-one sum `Σ z_j z_(j+1)` over neighbouring increments of the same run, less its
    /// mean under the walk, over its standard deviation under the walk.
    pub lag1_z: f64,
    /// Stationarity: the mean squared standardised increment of each run's first half less
    /// that of its second half, summed over runs, over its standard deviation under the walk
    /// (exact for Gaussian increments with covariance `C`). A walk's increments have the same
    /// variance throughout; a turn-on transient concentrates them at the start.
    pub stationarity_z: f64,
    /// Cross-run alignment: the largest `|Σ_r z_(r,j)| / √R` over increment indices `j` (time
    /// since the start of navigation) held by at least two runs. Independent walks do not
    /// move together in every run at the same time; an effect tied to turn-on does.
    pub aligned_z: f64,
    /// Tail probability of the most extreme of the four statistics under the walk: Bonferroni
    /// over the increments for the largest |z| and the alignment, Gaussian for the lag-one sum
    /// and the stationarity, times four for the four tests.
    pub p_value: f64,
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

    /// The capacitance `I + BᵀB` of `S = I + B Bᵀ`, `B = [U, aV]`.
    fn capacitance(&self, a: f64) -> DMatrix<f64> {
        let (np, nv) = (self.uu.nrows(), self.vv.nrows());
        let mut m = DMatrix::<f64>::identity(np + nv, np + nv);
        let mut top = m.view_mut((0, 0), (np, np));
        top += &self.uu;
        m.view_mut((0, np), (np, nv)).copy_from(&(&self.uv * a));
        m.view_mut((np, 0), (nv, np))
            .copy_from(&(self.uv.transpose() * a));
        let mut bottom = m.view_mut((np, np), (nv, nv));
        bottom += &self.vv * (a * a);
        m
    }

    /// `Bᵀ g`.
    fn btg(&self, a: f64) -> DVector<f64> {
        let np = self.uu.nrows();
        let mut b = DVector::zeros(np + self.vv.nrows());
        b.rows_mut(0, np).copy_from(&self.ug);
        b.rows_mut(np, self.vv.nrows()).copy_from(&(&self.vg * a));
        b
    }

    /// `(-2 log L(q), gᵀ S(q)⁻¹ g)` with `q = a²`.
    fn eval(&self, a: f64) -> (f64, f64) {
        let b = self.btg(a);
        // I + a PSD matrix: positive definite unless the data hold NaN.
        match self.capacitance(a).cholesky() {
            Some(c) => {
                let logdet: f64 = c.l().diagonal().iter().map(|d| 2.0 * d.ln()).sum();
                let x = c.solve(&b);
                let quad = self.gg - b.dot(&x);
                (logdet + quad, quad)
            }
            None => (f64::INFINITY, f64::INFINITY),
        }
    }

    /// The smoothed unit-intensity increments `ŵ = a Vᵀ S⁻¹ g` and their covariance under the
    /// walk, `C = a² Vᵀ S⁻¹ V` (Woodbury with `B = [U, aV]`: `S⁻¹ = I − B (I + BᵀB)⁻¹ Bᵀ`).
    fn smoothed(&self, a: f64) -> Option<(DVector<f64>, DMatrix<f64>)> {
        let (np, nv) = (self.uu.nrows(), self.vv.nrows());
        let chol = self.capacitance(a).cholesky()?;
        let mut btv = DMatrix::zeros(np + nv, nv);
        btv.rows_mut(0, np).copy_from(&self.uv);
        btv.rows_mut(np, nv).copy_from(&(&self.vv * a));
        let btg = self.btg(a);
        let vsg = &self.vg - btv.transpose() * chol.solve(&btg);
        let vsv = &self.vv - btv.transpose() * chol.solve(&btv);
        Some((vsg * a, vsv * (a * a)))
    }

    /// The whiteness statistics at intensity `a²` (see [`WalkShape`]).
    fn shape(&self, a: f64, blocks: &[usize]) -> Option<WalkShape> {
        let (w, c) = self.smoothed(a)?;
        whiteness(&w, &c, blocks)
    }
}

/// Whiteness of increments `w` with covariance `c` under the walk (columns in runs of
/// `blocks` widths, the first of each its aligned constant, left out of the lag-one pairs).
pub fn whiteness(w: &DVector<f64>, c: &DMatrix<f64>, blocks: &[usize]) -> Option<WalkShape> {
    let n = w.len();
    let scale = c.diagonal().iter().copied().fold(0.0, f64::max);
    if n == 0 || scale <= 0.0 || blocks.iter().sum::<usize>() != n {
        return None;
    }
    // Increments the data resolve (a variance at least 1e-6 of the best resolved one).
    let live: Vec<bool> = (0..n).map(|j| c[(j, j)] > 1e-6 * scale).collect();
    let sd: Vec<f64> = (0..n).map(|j| c[(j, j)].max(0.0).sqrt()).collect();
    let z: Vec<f64> = (0..n)
        .map(|j| if live[j] { w[j] / sd[j] } else { 0.0 })
        .collect();
    let increments = live.iter().filter(|&&l| l).count();
    let max_abs_z = z.iter().map(|x| x.abs()).fold(0.0, f64::max);
    // Lag-one pairs within a run, after its aligned constant, both resolved.
    let mut pairs = Vec::new();
    let mut first = 0;
    for &b in blocks {
        for j in first + 1..(first + b).saturating_sub(1) {
            if live[j] && live[j + 1] {
                pairs.push((j, j + 1));
            }
        }
        first += b;
    }
    let corr = |i: usize, j: usize| c[(i, j)] / (sd[i] * sd[j]);
    let t: f64 = pairs.iter().map(|&(i, j)| z[i] * z[j]).sum();
    let mean: f64 = pairs.iter().map(|&(i, j)| corr(i, j)).sum();
    // Var(zᵀ L z) = 2 tr(L R L R) with L the symmetric pair matrix (½ on each pair): with
    // (L R)_(i,·) = ½ Σ_(k ~ i) R_(k,·), tr((LR)²) = Σ_(i,j) (LR)_(ij) (LR)_(ji).
    let mut lr = DMatrix::<f64>::zeros(n, n);
    for &(i, j) in &pairs {
        for k in 0..n {
            if live[k] {
                lr[(i, k)] += 0.5 * corr(j, k);
                lr[(j, k)] += 0.5 * corr(i, k);
            }
        }
    }
    let var = 2.0 * lr.component_mul(&lr.transpose()).sum();
    let lag1_z = if var > 0.0 {
        (t - mean) / var.sqrt()
    } else {
        0.0
    };
    let p_max = (chi2_sf(max_abs_z * max_abs_z, 1.0) * increments.max(1) as f64).min(1.0);
    let p_lag = if pairs.is_empty() {
        1.0
    } else {
        chi2_sf(lag1_z * lag1_z, 1.0)
    };
    let stationarity_z = stationarity(&z, c, &live, &sd, blocks);
    let (aligned_z, aligned_tests) = alignment(&z, &live, blocks);
    let p_stat = chi2_sf(stationarity_z * stationarity_z, 1.0);
    let p_align = (chi2_sf(aligned_z * aligned_z, 1.0) * aligned_tests.max(1) as f64).min(1.0);
    Some(WalkShape {
        max_abs_z,
        increments,
        lag1_z,
        stationarity_z,
        aligned_z,
        p_value: (4.0 * p_max.min(p_lag).min(p_stat).min(p_align)).min(1.0),
    })
}

/// Runs' increments (after each run's aligned constant) that the data resolve, as index lists.
fn run_increments(live: &[bool], blocks: &[usize]) -> Vec<Vec<usize>> {
    let mut first = 0;
    blocks
        .iter()
        .map(|&b| {
            let idx = (first + 1..first + b).filter(|&j| live[j]).collect();
            first += b;
            idx
        })
        .collect()
}

/// See [`WalkShape::stationarity_z`]: with `ρ` the correlation of the standardised increments,
/// `Var(Σ_A z²) = 2 Σ_(A×A) ρ²`, so `Var(mean_A z² − mean_B z²)` follows exactly.
fn stationarity(z: &[f64], c: &DMatrix<f64>, live: &[bool], sd: &[f64], blocks: &[usize]) -> f64 {
    let rho2 = |i: usize, j: usize| (c[(i, j)] / (sd[i] * sd[j])).powi(2);
    let (mut d, mut var) = (0.0, 0.0);
    for idx in run_increments(live, blocks) {
        if idx.len() < 4 {
            continue;
        }
        let (a, b) = idx.split_at(idx.len() / 2);
        let (na, nb) = (a.len() as f64, b.len() as f64);
        let mean = |s: &[usize]| s.iter().map(|&j| z[j] * z[j]).sum::<f64>() / s.len() as f64;
        d += mean(a) - mean(b);
        let sum = |x: &[usize], y: &[usize]| -> f64 {
            x.iter()
                .map(|&i| y.iter().map(|&j| rho2(i, j)).sum::<f64>())
                .sum()
        };
        var += 2.0 * (sum(a, a) / (na * na) + sum(b, b) / (nb * nb) - 2.0 * sum(a, b) / (na * nb));
    }
    if var > 0.0 { d / var.sqrt() } else { 0.0 }
}

/// See [`WalkShape::aligned_z`]; also the number of indices tested.
fn alignment(z: &[f64], live: &[bool], blocks: &[usize]) -> (f64, usize) {
    let runs = run_increments(live, blocks);
    let mut first = 0;
    let offsets: Vec<usize> = blocks
        .iter()
        .map(|&b| {
            let o = first + 1;
            first += b;
            o
        })
        .collect();
    let longest = blocks
        .iter()
        .map(|b| b.saturating_sub(1))
        .max()
        .unwrap_or(0);
    let (mut top, mut tests) = (0.0f64, 0);
    if runs.len() < 2 {
        return (0.0, 0);
    }
    for j in 0..longest {
        let members: Vec<f64> = offsets
            .iter()
            .zip(blocks)
            .filter(|(o, b)| j + 1 < **b && live[**o + j])
            .map(|(o, _)| z[*o + j])
            .collect();
        if members.len() >= 2 {
            tests += 1;
            top = top.max(members.iter().sum::<f64>().abs() / (members.len() as f64).sqrt());
        }
    }
    (top, tests)
}

/// Maximum-likelihood intensity of a random walk with whitened factor `v` (columns in runs of
/// `blocks` widths, each run's first column its aligned constant, then its increments in time
/// order); `typical` (SI) sets the search range (1e-5 to 1e3 times it).
pub fn fit_walk(p: &Problem, v: &DMatrix<f64>, blocks: &[usize], typical: f64) -> WalkFit {
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
            shape: None,
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
        shape: lik.shape(a_hat, blocks),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::test_normals as normals;

    #[test]
    fn independent_increments_are_white_and_the_lag_statistic_is_exact_for_unit_covariance() {
        // One run: the aligned constant, then 120 increments; C = I.
        let n = 121;
        let w = DVector::from_vec(normals(n, 7));
        let c = DMatrix::<f64>::identity(n, n);
        let s = whiteness(&w, &c, &[n]).expect("shape");
        // With R = I: E = 0, Var = 2 tr((LR)²) = number of pairs (119).
        let t: f64 = (1..n - 1).map(|j| w[j] * w[j + 1]).sum();
        assert!((s.lag1_z - t / 119f64.sqrt()).abs() < 1e-12, "{s:?}");
        assert_eq!(s.increments, n);
        assert!(s.p_value > 0.01, "{s:?}");
    }

    #[test]
    fn a_step_and_an_oscillation_are_not_walks() {
        let n = 121;
        let c = DMatrix::<f64>::identity(n, n) * 4.0;
        let noise = normals(n, 3);
        // A step: one increment of 8 sigma among walk-like ones.
        let mut step = DVector::from_fn(n, |j, _| 2.0 * noise[j]);
        step[60] = 16.0;
        let s = whiteness(&step, &c, &[n]).expect("shape");
        assert!(s.max_abs_z >= 8.0 && s.p_value < 1e-6, "{s:?}");
        // A 45 min oscillation sampled every 20 min: neighbours anticorrelated (cos 160°).
        let phase = std::f64::consts::TAU * 20.0 / 45.0;
        let osc = DVector::from_fn(n, |j, _| 2.0 * (phase * j as f64).cos() + 0.5 * noise[j]);
        let s = whiteness(&osc, &c, &[n]).expect("shape");
        assert!(
            s.max_abs_z < 3.0 && s.lag1_z < -4.5 && s.p_value < 1e-4,
            "{s:?}"
        );
        // Two runs: pairs never straddle a run boundary nor include an aligned constant.
        let two = whiteness(&osc, &c, &[61, 60]).expect("shape");
        assert!(two.lag1_z < -4.5, "{two:?}");
    }

    #[test]
    fn correlated_increments_are_judged_against_their_own_correlation() {
        // Increments with a true lag-one correlation of 0.5 (an MA(1) process): white relative to
        // that C, not relative to the identity.
        let n = 201;
        let e = normals(n + 1, 11);
        let w = DVector::from_fn(n, |j, _| (e[j] + e[j + 1]) / 2f64.sqrt());
        let c = DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => 1.0,
            1 => 0.5,
            _ => 0.0,
        });
        let s = whiteness(&w, &c, &[n]).expect("shape");
        assert!(s.lag1_z.abs() < 3.0, "{s:?}");
        let naive = whiteness(&w, &DMatrix::identity(n, n), &[n]).expect("shape");
        assert!(naive.lag1_z > 4.0, "{naive:?}");
    }

    #[test]
    fn increments_bunched_at_turn_on_in_every_run_are_neither_stationary_nor_independent() {
        // Two runs of 60 increments (after each aligned constant), C = I.
        let (b, n) = (61, 122);
        let c = DMatrix::<f64>::identity(n, n);
        let noise = normals(n, 5);
        // A walk: white unit increments; the statistics are N(0, 1).
        let walk = DVector::from_vec(noise.clone());
        let s = whiteness(&walk, &c, &[b, b]).expect("shape");
        assert!(s.stationarity_z.abs() < 3.0 && s.aligned_z < 4.0, "{s:?}");
        // Exact stationarity variance for C = I: 2 (1/30 + 1/30) per run, two runs.
        let d: f64 = [0, b]
            .iter()
            .map(|&o| {
                let m = |r: std::ops::Range<usize>| {
                    r.clone().map(|j| walk[o + j] * walk[o + j]).sum::<f64>() / r.len() as f64
                };
                m(1..31) - m(31..61)
            })
            .sum();
        assert!((s.stationarity_z - d / (2.0 * 2.0 * (2.0 / 30.0f64)).sqrt()).abs() < 1e-12);
        // A turn-on transient: the first increments of each run large and of one sign.
        let mut tr = DVector::from_vec(noise.iter().map(|x| 0.5 * x).collect());
        for o in [0, b] {
            for j in 1..9 {
                tr[o + j] += 4.0 / (j as f64).sqrt();
            }
        }
        let s = whiteness(&tr, &c, &[b, b]).expect("shape");
        assert!(s.stationarity_z > 3.0, "{s:?}");
        assert!(s.aligned_z > 4.0 && s.p_value < 1e-3, "{s:?}");
    }
}
