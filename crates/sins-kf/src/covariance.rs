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

/// Rows of the widest vector register (eight `f64` in AVX-512): a matrix's storage is padded
/// to a multiple of this.
const PAD_ROWS: usize = 16;

/// An `nrows x ncols` matrix of zeros whose storage below the last row (the padding up to a
/// multiple of [`PAD_ROWS`] rows) is zero too.
///
/// faer pads each column of a matrix to whole vector registers and leaves the padding as the
/// allocator returned it; its matrix products load whole registers of the left-hand side and
/// of the destination, padding included, and discard those lanes. Reused heap memory holds
/// old pointers and lengths, which read as subnormal numbers, and on Intel cores every
/// multiply with a subnormal operand takes a microcode assist: the propagation's 9-row product
/// took 26-30 µs per update instead of 1.8 µs on a Xeon. The discarded lanes never reach a
/// result, so zero padding changes no bit, only the time.
pub(crate) fn zero_padded(nrows: usize, ncols: usize) -> Mat<f64> {
    let mut m = Mat::zeros(nrows.next_multiple_of(PAD_ROWS), ncols);
    m.truncate(nrows, ncols);
    m
}

/// A copy of `src` in a [`zero_padded`] matrix.
fn padded_copy(src: faer::MatRef<'_, f64>) -> Mat<f64> {
    let mut m = zero_padded(src.nrows(), src.ncols());
    m.copy_from(src);
    m
}

/// Covariance `P` of the error state and scratch space for its updates (each matrix
/// [`zero_padded`]).
#[derive(Debug)]
pub(crate) struct Covariance {
    p: Mat<f64>,
    /// `[Φ_nn Φ_np]`, 9 x n.
    phi_rows: Mat<f64>,
    /// `[Φ_nn Φ_np] P`, 9 x n.
    x: Mat<f64>,
}

/// A clone keeps the padding zero (faer's clone does not).
impl Clone for Covariance {
    fn clone(&self) -> Self {
        Self {
            p: padded_copy(self.p.as_ref()),
            phi_rows: padded_copy(self.phi_rows.as_ref()),
            x: padded_copy(self.x.as_ref()),
        }
    }
}

impl Covariance {
    /// Diagonal covariance with the given 1-sigmas.
    pub(crate) fn from_sigmas(sigma: &[f64]) -> Self {
        let n = sigma.len();
        let mut p = zero_padded(n, n);
        for (i, s) in sigma.iter().enumerate() {
            p[(i, i)] = s * s;
        }
        Self {
            p,
            phi_rows: zero_padded(NAV_STATES, n),
            x: zero_padded(NAV_STATES, n),
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
        let mut pnn = zero_padded(NAV_STATES, NAV_STATES);
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
        let pht = padded_copy(self.p.as_ref().submatrix(0, VEL, n, N_MEAS));
        let mut s_inv_f = zero_padded(N_MEAS, N_MEAS);
        s_inv_f.copy_from(faer::MatRef::from_column_major_slice(
            s_inv.as_slice(),
            N_MEAS,
            N_MEAS,
        ));
        let mut k = zero_padded(n, N_MEAS);
        matmul(&mut k, Accum::Replace, &pht, &s_inv_f, 1.0, Par::Seq);
        let zv = SVector::<f64, N_MEAS>::from_column_slice(z);
        let x: Vec<f64> = (0..n)
            .map(|i| (0..N_MEAS).map(|j| k[(i, j)] * zv[j]).sum())
            .collect();
        // A = (I − K H) P = P − K (H P); H P = rows VEL..VEL+6 of P.
        let hp = padded_copy(self.p.as_ref().submatrix(VEL, 0, N_MEAS, n));
        let mut a = padded_copy(self.p.as_ref());
        matmul(&mut a, Accum::Add, &k, &hp, -1.0, Par::Seq);
        // P = A (I − K H)ᵀ + K R Kᵀ = A − (A Hᵀ) Kᵀ + K R Kᵀ.
        let aht = a.as_ref().submatrix(0, VEL, n, N_MEAS);
        let mut m = zero_padded(n, N_MEAS);
        for j in 0..N_MEAS {
            for i in 0..n {
                m[(i, j)] = k[(i, j)] * r[j] - aht[(i, j)];
            }
        }
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

    /// Every element of `m`'s storage, the padding below its last row included.
    fn storage(m: &Mat<f64>) -> Vec<f64> {
        assert_eq!(m.row_stride(), 1);
        let stride = m.col_stride() as usize;
        assert!(stride >= m.nrows());
        // SAFETY: the allocation holds `ncols` columns of `stride` elements; `zero_padded`
        // initialised all of them.
        unsafe { std::slice::from_raw_parts(m.as_ptr(), stride * m.ncols()) }.to_vec()
    }

    /// The padding of the covariance's matrices is zero after an update, a propagation and a
    /// clone, even when the heap they come from held other numbers: the products' discarded
    /// lanes must not multiply subnormal garbage (see [`zero_padded`]).
    #[test]
    fn the_padding_stays_zero() {
        for n in [15, 36, 42, 48] {
            // Dirty the heap: blocks of the sizes the covariance asks for, filled with a
            // subnormal number, then freed.
            let dirty: Vec<Vec<f64>> = (1..=64)
                .map(|k| vec![f64::from_bits(0x7f00_dead_beef); k * n])
                .collect();
            drop(dirty);
            let mut cov = Covariance::from_sigmas(&vec![0.1; n]);
            let phi_nn = Mat9::from_fn(|i, j| if i == j { 1.0 } else { 0.01 });
            let phi_np = Mat::from_fn(9, n - 9, |i, j| 0.1 * (i as f64 - j as f64));
            let decay = vec![1.0; n - 9];
            cov.propagate(
                &phi_nn,
                &phi_np,
                &Mat9::identity(),
                &decay,
                &vec![0.0; n - 9],
            );
            cov.update(&[0.1; N_MEAS], &[0.01; N_MEAS]).unwrap();
            let copy = cov.clone();
            for c in [&cov, &copy] {
                for m in [&c.p, &c.phi_rows, &c.x] {
                    let stride = m.col_stride() as usize;
                    assert_eq!(stride % PAD_ROWS, 0, "n = {n}");
                    let padding = storage(m)
                        .iter()
                        .enumerate()
                        .filter(|(k, v)| k % stride >= m.nrows() && **v != 0.0)
                        .count();
                    assert_eq!(
                        padding, 0,
                        "n = {n}: {padding} padding elements are not zero"
                    );
                }
            }
        }
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
