//! The ASME V&V 20 comparison of one Table 5 cell: comparison error E = S - D and the validation
//! uncertainty u_val = sqrt(u_num² + u_input² + u_D²).

use serde::{Deserialize, Serialize};

/// Coverage factor of the verdict: |E| within 2 u_val (about 95 % for a normal error).
pub const COVERAGE_K: f64 = 2.0;

/// The V&V 20 figures of one cell (the cell's unit: nmi or %).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Validation {
    /// Simulation result S: the Monte Carlo median.
    pub s: f64,
    /// Experimental value D: the paper's.
    pub d: f64,
    /// Comparison error E = S - D.
    pub e: f64,
    /// Numerical uncertainty: the Monte Carlo error of the median (bootstrap) and the replay's
    /// error-free floor, in quadrature.
    pub u_num: f64,
    /// Input uncertainty: the standard deviation of the cell over the Monte Carlo of the
    /// assumptions and sensor-noise seeds.
    pub u_input: f64,
    /// Experimental uncertainty: the standard deviation of the paper's three experiments in the
    /// same column (the paper's own scatter).
    pub u_d: f64,
    /// u_val = sqrt(u_num² + u_input² + u_D²).
    pub u_val: f64,
    /// |E| / u_val.
    pub ratio: f64,
    /// True when |E| <= [`COVERAGE_K`] u_val.
    pub consistent: bool,
}

impl Validation {
    /// The comparison of simulation median `s` with paper value `d`.
    pub fn new(s: f64, d: f64, u_num: f64, u_input: f64, u_d: f64) -> Self {
        let e = s - d;
        let u_val = (u_num * u_num + u_input * u_input + u_d * u_d).sqrt();
        let ratio = if u_val > 0.0 {
            e.abs() / u_val
        } else {
            f64::INFINITY
        };
        Self {
            s,
            d,
            e,
            u_num,
            u_input,
            u_d,
            u_val,
            ratio,
            consistent: ratio <= COVERAGE_K,
        }
    }

    /// One line: consistent, or the model error interval E ± k u_val.
    pub fn verdict(&self) -> String {
        if self.consistent {
            format!("consistent: |E| = {:.2} u_val", self.ratio)
        } else {
            format!(
                "model error: |E| = {:.1} u_val, delta_model in [{:.3}, {:.3}]",
                self.ratio,
                self.e - COVERAGE_K * self.u_val,
                self.e + COVERAGE_K * self.u_val
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_uncertainty_adds_in_quadrature() {
        let v = Validation::new(5.0, 2.0, 0.0, 1.2, 0.9);
        assert!((v.u_val - 1.5).abs() < 1e-12);
        assert!((v.e - 3.0).abs() < 1e-12);
        assert!((v.ratio - 2.0).abs() < 1e-12 && v.consistent);
        let w = Validation::new(86.0, 3.38, 0.1, 1.0, 0.2);
        assert!(!w.consistent && w.verdict().starts_with("model error"));
    }
}
