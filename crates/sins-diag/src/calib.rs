//! The calibration's uncertainty as the twin sees it: a factor `F` of the covariance of the
//! coefficients the parameter set uses (`Σ = F Fᵀ`), so that the position responses `S` to the
//! coefficients turn into one-sigma columns `S F` common to all runs.

use crate::columns::{PARAM_SLOTS, param_vector, slots_of};
use crate::error::DiagError;
use crate::sensitivity::ColumnId;
use nalgebra::DMatrix;
use sins_imu::ImuErrorParams;

/// Coefficients and the factor of their covariance.
#[derive(Clone, Debug)]
pub struct ParamUncertainty {
    /// The coefficients (columns of the sensitivities).
    pub ids: Vec<ColumnId>,
    /// `F` (`ids.len()` rows), with `F Fᵀ` the covariance (SI).
    pub factor: DMatrix<f64>,
}

/// The uncertainty of `params` from a full covariance (row-major, eq 8 order, 21 or 33
/// coefficients as the model uses; e.g. `sins_kf`'s `param_covariance`) or, failing that, from
/// independent one-sigmas. `None` when neither is given.
pub fn uncertainty(
    params: &ImuErrorParams,
    sigma: Option<&ImuErrorParams>,
    covariance: Option<&[f64]>,
) -> Result<Option<ParamUncertainty>, DiagError> {
    let used: Vec<usize> = slots_of(params.model).map(|(i, _)| i).collect();
    if let Some(c) = covariance {
        let n = used.len();
        if c.len() != n * n {
            return Err(DiagError::input(
                "",
                format!(
                    "calibration covariance has {} entries, the {}-coefficient model needs {}",
                    c.len(),
                    n,
                    n * n
                ),
            ));
        }
        let m = DMatrix::from_row_slice(n, n, c);
        let sym = (&m + m.transpose()) * 0.5;
        let eig = sym.symmetric_eigen();
        let keep: Vec<usize> = (0..n).filter(|&k| eig.eigenvalues[k] > 0.0).collect();
        let mut factor = DMatrix::zeros(n, keep.len());
        for (j, &k) in keep.iter().enumerate() {
            factor.set_column(j, &(eig.eigenvectors.column(k) * eig.eigenvalues[k].sqrt()));
        }
        return Ok(Some(ParamUncertainty {
            ids: used.iter().map(|&i| ColumnId::Param(i)).collect(),
            factor,
        }));
    }
    let Some(sigma) = sigma else {
        return Ok(None);
    };
    let sv = param_vector(sigma);
    let ids: Vec<usize> = used.into_iter().filter(|&i| sv[i] > 0.0).collect();
    let mut factor = DMatrix::zeros(ids.len(), ids.len());
    for (j, &i) in ids.iter().enumerate() {
        factor[(j, j)] = sv[i];
    }
    debug_assert!(ids.iter().all(|&i| i < PARAM_SLOTS.len()));
    Ok(Some(ParamUncertainty {
        ids: ids.into_iter().map(ColumnId::Param).collect(),
        factor,
    }))
}
