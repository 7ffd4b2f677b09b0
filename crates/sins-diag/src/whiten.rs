//! Whitening of one run's gap and signals by the Cholesky factor of its covariance, and the
//! projection of nuisance directions out of a whitened residual: what the time-local scan, the
//! rival time courses and the confounds share.

use crate::dense::LowerCholesky;
use crate::error::DiagError;
use nalgebra::{DMatrix, DVector};

/// Whitening by the Cholesky factor of one run's covariance.
pub(crate) struct RunWhitener {
    l: LowerCholesky,
}

impl RunWhitener {
    pub(crate) fn new(cov: &DMatrix<f64>) -> Result<Self, DiagError> {
        let l = LowerCholesky::new(cov).map_err(|e| {
            DiagError::Numerical(format!(
                "event scan: covariance not positive definite ({e})"
            ))
        })?;
        Ok(Self { l })
    }

    pub(crate) fn whiten_vec(&self, x: &DVector<f64>) -> DVector<f64> {
        self.whiten(&DMatrix::from_column_slice(x.len(), 1, x.as_slice()))
            .column(0)
            .into_owned()
    }

    pub(crate) fn whiten(&self, x: &DMatrix<f64>) -> DMatrix<f64> {
        self.l.whiten_rows(x, 0..x.nrows())
    }
}

/// An orthonormal basis of nuisance directions (whitened) and the residual projected off it.
pub(crate) struct Nuisance {
    pub(crate) q: Vec<DVector<f64>>,
    pub(crate) r: DVector<f64>,
}

impl Nuisance {
    pub(crate) fn new(r: DVector<f64>) -> Self {
        Self { q: Vec::new(), r }
    }

    /// Add a direction (Gram-Schmidt twice); the residual loses its component.
    pub(crate) fn add(&mut self, v: &DVector<f64>) {
        let mut u = v.clone();
        for _ in 0..2 {
            for q in &self.q {
                let c = q.dot(&u);
                u.axpy(-c, q, 1.0);
            }
        }
        let n = u.norm();
        if n > 1e-10 * v.norm().max(f64::MIN_POSITIVE) {
            u /= n;
            let c = u.dot(&self.r);
            self.r.axpy(-c, &u, 1.0);
            self.q.push(u);
        }
    }

    /// `(ŝᵀr̂⊥, |ŝ⊥|²)`.
    pub(crate) fn stat(&self, s: &[f64]) -> (f64, f64) {
        let sv = nalgebra::DVectorView::from_slice(s, s.len());
        let a = sv.dot(&self.r);
        let mut b = sv.dot(&sv);
        for q in &self.q {
            let c = sv.dot(q);
            b -= c * c;
        }
        (a, b.max(0.0))
    }
}

impl RunWhitener {
    /// `L x`: back from the whitened space.
    pub(crate) fn colour(&self, x: &DVector<f64>) -> DVector<f64> {
        self.l.colour(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nuisance_projection_removes_the_direction_from_both_sides() {
        let r = DVector::from_vec(vec![1.0, 2.0, 3.0, 4.0]);
        let mut n = Nuisance::new(r);
        n.add(&DVector::from_vec(vec![1.0, 0.0, 0.0, 0.0]));
        // A signal along the nuisance has no component left.
        let (a, b) = n.stat(&[2.0, 0.0, 0.0, 0.0]);
        assert!(a.abs() < 1e-15 && b.abs() < 1e-15);
        let (a, b) = n.stat(&[1.0, 1.0, 0.0, 0.0]);
        assert!((a - 2.0).abs() < 1e-15 && (b - 1.0).abs() < 1e-15);
    }
}
