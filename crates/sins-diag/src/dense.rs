//! The one conversion point between the crate's two linear-algebra libraries: nalgebra holds
//! every matrix of the diagnosis; faer factors the twin's dense covariances (Cholesky) and
//! solves with the factors, where it is several times faster at the sizes of a 15 h run (450 fit
//! times per run, a few hundred signal columns). Nothing else in the crate names faer.

use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Mat, Par, Side};
use nalgebra::{DMatrix, DVector};
use std::ops::Range;

/// The lower Cholesky factor `L` of a symmetric positive-definite matrix `D = L Lᵀ`.
pub(crate) struct LowerCholesky {
    l: Mat<f64>,
}

impl LowerCholesky {
    /// Factor `d`; the error names why it is not positive definite.
    pub(crate) fn new(d: &DMatrix<f64>) -> Result<Self, String> {
        let n = d.nrows();
        let m = Mat::<f64>::from_fn(n, n, |i, j| d[(i, j)]);
        let llt = m.llt(Side::Lower).map_err(|e| format!("{e:?}"))?;
        Ok(Self {
            l: llt.L().to_owned(),
        })
    }

    /// The order of `D`.
    pub(crate) fn n(&self) -> usize {
        self.l.nrows()
    }

    /// `L⁻¹ x[rows, ..]`: the rows `rows` of `x` (as many as the order of `D`) whitened.
    pub(crate) fn whiten_rows(&self, x: &DMatrix<f64>, rows: Range<usize>) -> DMatrix<f64> {
        let n = rows.len();
        let mut b = Mat::<f64>::from_fn(n, x.ncols(), |i, j| x[(rows.start + i, j)]);
        solve_lower_triangular_in_place(self.l.as_ref(), b.as_mut(), Par::Seq);
        DMatrix::from_fn(n, x.ncols(), |i, j| b[(i, j)])
    }

    /// `L x`: from the whitened space back.
    pub(crate) fn colour(&self, x: &DVector<f64>) -> DVector<f64> {
        let n = x.len();
        DVector::from_fn(n, |i, _| (0..=i).map(|j| self.l[(i, j)] * x[j]).sum())
    }

    /// `L⁻¹ L⁻ᵀ`: the image of `D⁻¹` in whitened space.
    pub(crate) fn inverse_gram(&self) -> DMatrix<f64> {
        let n = self.n();
        let mut x = Mat::<f64>::identity(n, n);
        solve_lower_triangular_in_place(self.l.as_ref(), x.as_mut(), Par::Seq);
        let mut g = Mat::<f64>::zeros(n, n);
        faer::linalg::matmul::matmul(
            g.as_mut(),
            faer::Accum::Replace,
            x.as_ref(),
            x.transpose(),
            1.0,
            Par::Seq,
        );
        DMatrix::from_fn(n, n, |i, j| g[(i, j)])
    }
}
