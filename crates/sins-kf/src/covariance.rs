//! The filter covariance and its two operations, exploiting the structure of eq (6): the
//! coefficients are constant, so `Φ = [[Φ_nn, Φ_np], [0, I]]` and a propagation only changes the
//! 9 navigation rows and columns (`O(9 n²)` instead of `O(n³)`); the measurements of eqs (9)-(11)
//! pick the six velocity and position states.

use crate::moments::mat9_to_faer;
use crate::states::{NAV_STATES, VEL};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use nalgebra::{SMatrix, SVector};
use sins_nav::error_model::Mat9;

/// Number of measurements: δV (3) and δL, δλ, δh.
pub(crate) const N_MEAS: usize = 6;

/// Covariance `P` of the error state and scratch space for its updates.
#[derive(Clone, Debug)]
pub(crate) struct Covariance {
    p: Mat<f64>,
    /// `[Φ_nn Φ_np]`, 9 x n.
    phi_rows: Mat<f64>,
    /// `[Φ_nn Φ_np] P`, 9 x n.
    x: Mat<f64>,
}

impl Covariance {
    /// Diagonal covariance with the given 1-sigmas.
    pub(crate) fn from_sigmas(sigma: &[f64]) -> Self {
        let n = sigma.len();
        let p = Mat::from_fn(n, n, |i, j| if i == j { sigma[i] * sigma[i] } else { 0.0 });
        Self {
            p,
            phi_rows: Mat::zeros(NAV_STATES, n),
            x: Mat::zeros(NAV_STATES, n),
        }
    }

    /// Number of states.
    pub(crate) fn n(&self) -> usize {
        self.p.nrows()
    }

    /// Variance of state `i`.
    pub(crate) fn variance(&self, i: usize) -> f64 {
        self.p[(i, i)]
    }

    /// 1-sigma of state `i`.
    pub(crate) fn sigma(&self, i: usize) -> f64 {
        self.p[(i, i)].max(0.0).sqrt()
    }

    /// Covariance of states `i` and `j`.
    pub(crate) fn entry(&self, i: usize, j: usize) -> f64 {
        self.p[(i, j)]
    }

    /// True when every diagonal entry is finite and non-negative.
    pub(crate) fn is_healthy(&self) -> bool {
        (0..self.n()).all(|i| {
            let d = self.p[(i, i)];
            d.is_finite() && d >= 0.0
        })
    }

    /// `P ← Φ P Φᵀ + Q` with `Φ = [[phi_nn, phi_np], [0, D]]`, `D = diag(decay)` (1 for the
    /// constant coefficients, `e^{−T/τ}` for Gauss-Markov states), navigation noise `q_nn` and
    /// diagonal noise `q_params` of the other states.
    pub(crate) fn propagate(
        &mut self,
        phi_nn: &Mat9,
        phi_np: &Mat<f64>,
        q_nn: &Mat9,
        decay: &[f64],
        q_params: &[f64],
    ) {
        let n = self.n();
        let np = n - NAV_STATES;
        self.phi_rows
            .as_mut()
            .submatrix_mut(0, 0, NAV_STATES, NAV_STATES)
            .copy_from(mat9_to_faer(phi_nn));
        self.phi_rows
            .as_mut()
            .submatrix_mut(0, NAV_STATES, NAV_STATES, np)
            .copy_from(phi_np);
        // X = [Φ_nn Φ_np] P (9 x n): the new navigation rows of Φ P.
        matmul(
            &mut self.x,
            Accum::Replace,
            &self.phi_rows,
            &self.p,
            1.0,
            Par::Seq,
        );
        // New P_nn = X [Φ_nn Φ_np]ᵀ; new P_np = X_p (the coefficient columns of X).
        let mut pnn = Mat::<f64>::zeros(NAV_STATES, NAV_STATES);
        matmul(
            &mut pnn,
            Accum::Replace,
            &self.x,
            self.phi_rows.transpose(),
            1.0,
            Par::Seq,
        );
        for i in 0..NAV_STATES {
            for j in 0..NAV_STATES {
                self.p[(i, j)] = 0.5 * (pnn[(i, j)] + pnn[(j, i)]) + q_nn[(i, j)];
            }
            for j in NAV_STATES..n {
                let v = self.x[(i, j)] * decay[j - NAV_STATES];
                self.p[(i, j)] = v;
                self.p[(j, i)] = v;
            }
        }
        if decay.iter().any(|&d| d != 1.0) {
            for i in NAV_STATES..n {
                for j in NAV_STATES..n {
                    self.p[(i, j)] *= decay[i - NAV_STATES] * decay[j - NAV_STATES];
                }
            }
        }
        for (k, q) in q_params.iter().enumerate() {
            self.p[(NAV_STATES + k, NAV_STATES + k)] += q;
        }
    }

    /// Measurement update with `z = H x + v`, `H` selecting δV and the position errors, and
    /// diagonal measurement variances `r`. Returns the state estimate (the prior is zero: the
    /// filter runs closed-loop) and the gain `K` (n x 6), or `None` if the innovation covariance
    /// is not positive definite. Joseph form.
    pub(crate) fn update(
        &mut self,
        z: &[f64; N_MEAS],
        r: &[f64; N_MEAS],
    ) -> Option<(Vec<f64>, Mat<f64>)> {
        let n = self.n();
        let mut s = SMatrix::<f64, N_MEAS, N_MEAS>::zeros();
        for i in 0..N_MEAS {
            for j in 0..N_MEAS {
                s[(i, j)] = self.p[(VEL + i, VEL + j)];
            }
            s[(i, i)] += r[i];
        }
        let s_inv = s.cholesky()?.inverse();
        // K = P Hᵀ S⁻¹ (n x 6); P Hᵀ = columns VEL..VEL+6 of P.
        let pht = self.p.as_ref().submatrix(0, VEL, n, N_MEAS).to_owned();
        let s_inv_f = Mat::from_fn(N_MEAS, N_MEAS, |i, j| s_inv[(i, j)]);
        let mut k = Mat::<f64>::zeros(n, N_MEAS);
        matmul(&mut k, Accum::Replace, &pht, &s_inv_f, 1.0, Par::Seq);
        let zv = SVector::<f64, N_MEAS>::from_column_slice(z);
        let x: Vec<f64> = (0..n)
            .map(|i| (0..N_MEAS).map(|j| k[(i, j)] * zv[j]).sum())
            .collect();
        // A = (I − K H) P = P − K (H P); H P = rows VEL..VEL+6 of P.
        let hp = self.p.as_ref().submatrix(VEL, 0, N_MEAS, n).to_owned();
        let mut a = self.p.clone();
        matmul(&mut a, Accum::Add, &k, &hp, -1.0, Par::Seq);
        // P = A (I − K H)ᵀ + K R Kᵀ = A − (A Hᵀ) Kᵀ + K R Kᵀ.
        let aht = a.as_ref().submatrix(0, VEL, n, N_MEAS).to_owned();
        let kr = Mat::from_fn(n, N_MEAS, |i, j| k[(i, j)] * r[j]);
        let mut m = kr;
        m -= &aht;
        matmul(&mut a, Accum::Add, &m, k.transpose(), 1.0, Par::Seq);
        for i in 0..n {
            for j in 0..i {
                let v = 0.5 * (a[(i, j)] + a[(j, i)]);
                a[(i, j)] = v;
                a[(j, i)] = v;
            }
        }
        self.p = a;
        Some((x, k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dense_reference(p: &Mat<f64>, phi: &Mat<f64>) -> Mat<f64> {
        phi * p * phi.transpose()
    }

    #[test]
    fn structured_propagation_equals_the_dense_product() {
        let n = 15;
        let mut cov = Covariance::from_sigmas(&vec![1.0; n]);
        // A correlated P.
        let l = Mat::from_fn(n, n, |i, j| {
            if j <= i {
                0.1 * ((i * 7 + j * 3) % 5) as f64 + if i == j { 1.0 } else { 0.0 }
            } else {
                0.0
            }
        });
        cov.p = &l * l.transpose();
        let p0 = cov.p.clone();
        let phi_nn = Mat9::from_fn(|i, j| {
            if i == j {
                1.0
            } else {
                0.01 * (i + 2 * j) as f64
            }
        });
        let phi_np = Mat::from_fn(9, n - 9, |i, j| 0.1 * (i as f64 - j as f64));
        let decay: Vec<f64> = (0..n - 9)
            .map(|k| if k % 2 == 0 { 1.0 } else { 0.9 })
            .collect();
        cov.propagate(&phi_nn, &phi_np, &Mat9::zeros(), &decay, &vec![0.0; n - 9]);
        let mut phi = Mat::<f64>::identity(n, n);
        for k in 0..n - 9 {
            phi[(9 + k, 9 + k)] = decay[k];
        }
        phi.as_mut()
            .submatrix_mut(0, 0, 9, 9)
            .copy_from(mat9_to_faer(&phi_nn));
        phi.as_mut()
            .submatrix_mut(0, 9, 9, n - 9)
            .copy_from(&phi_np);
        let want = dense_reference(&p0, &phi);
        for i in 0..n {
            for j in 0..n {
                assert!((cov.p[(i, j)] - want[(i, j)]).abs() < 1e-12, "({i},{j})");
            }
        }
    }
}
