//! Correlation between the Allan variances at different `τ` (they are computed from the same
//! data, so neighbouring octaves are strongly correlated; treating them as independent
//! understates every fitted sigma several-fold).
//!
//! For a long record (Whittle's approximation) the covariance of two quadratic-filter
//! estimates is `Cov(σ̂²_i, σ̂²_j) ∝ ∫ S_y(f)² G_i(f) G_j(f) df`, with `S_y` the one-sided rate
//! spectrum of the model and `G(f) = 2 sin⁴(π f τ)/(π f τ)²` the Allan filter
//! (`σ²(τ) = ∫ S_y G df`). Only the correlation coefficients `ρ_ij` are taken from it; the
//! variances themselves come from the equivalent degrees of freedom. Spectra of the terms
//! (one-sided, matching [`crate::model`]'s Allan variances): white `2N²`, quantization
//! `4π² Q² f²/f_h` up to the Nyquist frequency `f_h = 1/(2h)` (white phase), Gauss-Markov
//! `4σ²T/(1 + (2π f T)²)`, rate random walk `K²/(2π² f²)`. Beyond `π f τ = 4` the filter's
//! `sin⁴` is replaced by its mean 3/8 (the log grid does not resolve the oscillation there).

use nalgebra::DMatrix;

/// Frequencies (Hz) and quadrature weights of the log grid.
pub(crate) struct Grid {
    f: Vec<f64>,
    w: Vec<f64>,
    f_nyquist: f64,
}

const PER_DECADE: f64 = 40.0;

impl Grid {
    /// A grid from well below `1/τ_max` to the Nyquist frequency of samples every `h_s`.
    pub fn new(tau_max_s: f64, h_s: f64) -> Self {
        let f_hi = 0.5 / h_s;
        let f_lo = 1e-3 / tau_max_s.max(h_s);
        let n = ((f_hi / f_lo).log10() * PER_DECADE).ceil().max(2.0) as usize;
        let r = (f_hi / f_lo).ln() / n as f64;
        let f: Vec<f64> = (0..=n).map(|k| f_lo * (r * k as f64).exp()).collect();
        // ∫ g df = ∫ g f d(ln f): trapezoid in ln f.
        let w = (0..=n)
            .map(|k| f[k] * r * if k == 0 || k == n { 0.5 } else { 1.0 })
            .collect();
        Self {
            f,
            w,
            f_nyquist: f_hi,
        }
    }

    /// The Allan filter `G(f)` of `τ` on the grid.
    pub fn filter(&self, tau_s: f64) -> Vec<f64> {
        self.f
            .iter()
            .map(|&f| {
                let x = std::f64::consts::PI * f * tau_s;
                let s4 = if x > 4.0 { 0.375 } else { x.sin().powi(4) };
                2.0 * s4 / (x * x)
            })
            .collect()
    }

    /// The model's rate spectrum: `θ` in [`crate::model::TERMS`] order, the Gauss-Markov
    /// correlation time and a known quantization level `Q²`.
    pub fn spectrum(&self, theta: &[f64; 4], corr_s: f64, known_q2: f64) -> Vec<f64> {
        let pi = std::f64::consts::PI;
        self.f
            .iter()
            .map(|&f| {
                let q = 4.0 * pi * pi * (theta[0] + known_q2) * f * f / self.f_nyquist;
                let white = 2.0 * theta[1];
                let gm = if corr_s.is_finite() {
                    4.0 * theta[2] * corr_s / (1.0 + (2.0 * pi * f * corr_s).powi(2))
                } else {
                    0.0
                };
                let rrw = theta[3] / (2.0 * pi * pi * f * f);
                q + white + gm + rrw
            })
            .collect()
    }

    /// Correlation matrix of the Allan variances whose filters are `filters`, under `spectrum`.
    pub fn correlation(&self, filters: &[Vec<f64>], spectrum: &[f64]) -> DMatrix<f64> {
        let n = filters.len();
        let s2w: Vec<f64> = spectrum
            .iter()
            .zip(&self.w)
            .map(|(s, w)| s * s * w)
            .collect();
        let mut c = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in 0..=i {
                let v: f64 = (0..s2w.len())
                    .map(|k| s2w[k] * filters[i][k] * filters[j][k])
                    .sum();
                c[(i, j)] = v;
                c[(j, i)] = v;
            }
        }
        let d: Vec<f64> = (0..n)
            .map(|i| c[(i, i)].max(f64::MIN_POSITIVE).sqrt())
            .collect();
        for i in 0..n {
            for j in 0..n {
                c[(i, j)] /= d[i] * d[j];
            }
            c[(i, i)] = 1.0;
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::TERMS;

    #[test]
    fn spectra_integrate_to_the_terms_allan_variances() {
        let g = Grid::new(1e4, 0.005);
        for (j, tau) in [(1usize, 10.0), (2, 300.0), (3, 1000.0)] {
            let mut theta = [0.0; 4];
            theta[j] = 1.0;
            let s = g.spectrum(&theta, 500.0, 0.0);
            let gf = g.filter(tau);
            let avar: f64 = (0..s.len()).map(|k| s[k] * gf[k] * g.w[k]).sum();
            let want = TERMS[j].basis(tau, 500.0);
            assert!(
                (avar / want - 1.0).abs() < 0.05,
                "term {j}: {avar} vs {want}"
            );
        }
    }
}
