//! Generalised least squares with the twin's covariance
//! `S = blockdiag(D_r) + U Uᵀ`: per-run noise covariances `D_r` (time-correlated, independent
//! between runs) plus the calibration uncertainty shared by all runs (`U` = the responses to a
//! one-sigma change of each coefficient). Each run is whitened by the Cholesky factor of its
//! `D_r`; the shared part is handled by Woodbury's identity, so that
//! `⟨x, y⟩_S = x̂ᵀŷ - (R⁻¹Ûᵀx̂)ᵀ(R⁻¹Ûᵀŷ)` with `R Rᵀ = I + ÛᵀÛ`, and
//! `log det S = Σ log det D_r + log det(I + ÛᵀÛ)`.

use crate::dense::LowerCholesky;
use crate::error::DiagError;
use nalgebra::{DMatrix, DVector};

/// Per-run whitening `x ↦ L_r⁻¹ x` with `L_r L_rᵀ = D_r`.
pub struct Whitener {
    factors: Vec<LowerCholesky>,
    offsets: Vec<usize>,
}

impl Whitener {
    /// Factor the per-run covariances (stacked in the given order).
    pub fn new(covs: &[DMatrix<f64>]) -> Result<Self, DiagError> {
        let mut factors = Vec::with_capacity(covs.len());
        let mut offsets = Vec::with_capacity(covs.len() + 1);
        let mut off = 0;
        for (r, d) in covs.iter().enumerate() {
            let n = d.nrows();
            let l = LowerCholesky::new(d).map_err(|e| {
                DiagError::Numerical(format!("run {r}: covariance not positive definite ({e})"))
            })?;
            offsets.push(off);
            off += n;
            factors.push(l);
        }
        offsets.push(off);
        Ok(Self { factors, offsets })
    }

    /// Total number of rows.
    pub fn n(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0)
    }

    /// Rows of run `r`.
    pub fn rows(&self, r: usize) -> std::ops::Range<usize> {
        self.offsets[r]..self.offsets[r + 1]
    }

    /// `G_r = L_r⁻¹ L_r⁻ᵀ` of each run (the whitened-space image of `D_r⁻¹`).
    pub fn inverse_grams(&self) -> Vec<DMatrix<f64>> {
        self.factors
            .iter()
            .map(LowerCholesky::inverse_gram)
            .collect()
    }

    /// Whiten the columns of `x` (rows stacked like the covariances).
    pub fn whiten(&self, x: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = x.clone();
        for (r, l) in self.factors.iter().enumerate() {
            let rows = self.rows(r);
            let n = rows.len();
            out.rows_mut(rows.start, n)
                .copy_from(&l.whiten_rows(x, rows.clone()));
        }
        out
    }
}

/// The GLS metric of one problem: whitened gap and whitened shared nuisance columns.
pub struct Gls {
    /// Whitened gap.
    pub g: DVector<f64>,
    u: DMatrix<f64>,
    r_inv: DMatrix<f64>,
    /// Number of data.
    pub n: usize,
}

/// A GLS fit of some columns.
#[derive(Clone, Debug)]
pub struct Fit {
    /// Estimates (one per column; 0 for unidentifiable directions).
    pub theta: DVector<f64>,
    /// Covariance of the estimates (pseudo-inverse of the Gram matrix).
    pub cov: DMatrix<f64>,
    /// Chi-square drop `θᵀ G θ`.
    pub dchi2: f64,
    /// Rank of the Gram matrix.
    pub rank: usize,
}

impl Gls {
    /// The metric for whitened gap `g` and whitened one-sigma nuisance columns `u`.
    pub fn new(g: DVector<f64>, u: DMatrix<f64>) -> Result<Self, DiagError> {
        let p = u.ncols();
        let m = DMatrix::<f64>::identity(p, p) + u.transpose() * &u;
        let chol = m.cholesky().ok_or_else(|| {
            DiagError::Numerical("calibration-uncertainty capacitance not positive definite".into())
        })?;
        let r_inv = chol
            .l()
            .solve_lower_triangular(&DMatrix::identity(p, p))
            .unwrap_or_else(|| DMatrix::identity(p, p));
        Ok(Self {
            n: g.len(),
            g,
            u,
            r_inv,
        })
    }

    /// `W = Û R⁻ᵀ`, with `(I + ÛÛᵀ)⁻¹ = I - W Wᵀ`.
    pub fn woodbury_w(&self) -> DMatrix<f64> {
        &self.u * self.r_inv.transpose()
    }

    /// `R⁻¹ Ûᵀ x`.
    fn proj(&self, x: &DMatrix<f64>) -> DMatrix<f64> {
        &self.r_inv * (self.u.transpose() * x)
    }

    /// `⟨a, b⟩_S` for whitened column sets.
    pub fn gram(&self, a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
        a.transpose() * b - self.proj(a).transpose() * self.proj(b)
    }

    /// The whitened gap as a one-column matrix.
    pub fn gap(&self) -> DMatrix<f64> {
        DMatrix::from_column_slice(self.g.len(), 1, self.g.as_slice())
    }

    /// `gᵀ S⁻¹ g`.
    pub fn chi2(&self) -> f64 {
        let g = self.gap();
        self.gram(&g, &g)[(0, 0)]
    }

    /// GLS fit of the whitened columns `a` to the gap.
    pub fn fit(&self, a: &DMatrix<f64>) -> Fit {
        let gm = self.gram(a, a);
        let b = self.gram(a, &self.gap()).column(0).into_owned();
        let (pinv, rank) = pseudo_inverse(&gm);
        let theta = &pinv * &b;
        Fit {
            dchi2: theta.dot(&b),
            theta,
            cov: pinv,
            rank,
        }
    }
}

impl Gls {
    /// Chi-square drop of fitting the whitened columns `a` to the whitened target `y` (instead
    /// of the gap).
    pub fn fit_to(&self, a: &DMatrix<f64>, y: &DMatrix<f64>) -> f64 {
        let gm = self.gram(a, a);
        let b = self.gram(a, y).column(0).into_owned();
        let (pinv, _) = pseudo_inverse(&gm);
        (&pinv * &b).dot(&b)
    }
}

/// Pseudo-inverse of a symmetric positive semi-definite matrix (eigenvalues below 1e-10 of the
/// largest dropped) and its rank.
pub fn pseudo_inverse(m: &DMatrix<f64>) -> (DMatrix<f64>, usize) {
    let n = m.nrows();
    if n == 0 {
        return (DMatrix::zeros(0, 0), 0);
    }
    // Scale to unit diagonal for conditioning.
    let d: Vec<f64> = (0..n)
        .map(|i| {
            let v = m[(i, i)];
            if v > 0.0 { 1.0 / v.sqrt() } else { 0.0 }
        })
        .collect();
    let scaled = DMatrix::from_fn(n, n, |i, j| m[(i, j)] * d[i] * d[j]);
    let eig = scaled.symmetric_eigen();
    let max = eig.eigenvalues.iter().cloned().fold(0.0, f64::max);
    let mut inv = DMatrix::zeros(n, n);
    let mut rank = 0;
    for (k, &l) in eig.eigenvalues.iter().enumerate() {
        if l > 1e-10 * max && l > 0.0 {
            rank += 1;
            let v = eig.eigenvectors.column(k);
            inv += v * v.transpose() / l;
        }
    }
    (
        DMatrix::from_fn(n, n, |i, j| inv[(i, j)] * d[i] * d[j]),
        rank,
    )
}
