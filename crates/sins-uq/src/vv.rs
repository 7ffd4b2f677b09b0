//! The ASME V&V 20 comparison of one Table 5 cell: comparison error E = S - D, the validation
//! uncertainty u_val = sqrt(u_num² + u_input² + u_D²) and the model-error interval
//! δ_model ∈ [E − k u_val, E + k u_val]. The word says what that interval supports: a cell is
//! *validated* only when the interval contains zero and is informative against the quantity
//! itself (k u_val < |D|: the comparison could have told a model error the size of the paper's
//! figure); with k u_val ≥ |D| it is *not informative*, whatever E is (a 3.4 nmi cell with
//! u_val = 30 nmi bounds the model error only to ±60 nmi); with |E| > k u_val it is a *model
//! error* of that interval.

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
    /// What the comparison supports (see the module's doc).
    #[serde(default)]
    pub word: VvWord,
}

/// The word of a V&V 20 comparison.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VvWord {
    /// The model-error interval contains zero and is narrower than the quantity: k u_val < |D|.
    Validated,
    /// k u_val ≥ |D|: the comparison cannot bound a model error the size of the quantity.
    #[default]
    NotInformative,
    /// |E| > k u_val: the interval excludes zero.
    ModelError,
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
        let consistent = ratio <= COVERAGE_K;
        let word = if !consistent {
            VvWord::ModelError
        } else if COVERAGE_K * u_val < d.abs() {
            VvWord::Validated
        } else {
            VvWord::NotInformative
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
            consistent,
            word,
        }
    }

    /// The model-error interval `[E − k u_val, E + k u_val]` (the cell's unit).
    pub fn delta_model(&self) -> (f64, f64) {
        (
            self.e - COVERAGE_K * self.u_val,
            self.e + COVERAGE_K * self.u_val,
        )
    }

    /// One line: the word, the model-error interval and why.
    pub fn verdict(&self) -> String {
        let (lo, hi) = self.delta_model();
        match self.word {
            VvWord::Validated => format!(
                "validated: delta_model in [{lo:.3}, {hi:.3}] (|E| = {:.2} u_val; 2 u_val = {:.3} < |D| = {:.3})",
                self.ratio,
                COVERAGE_K * self.u_val,
                self.d.abs()
            ),
            VvWord::NotInformative => format!(
                "not informative: u_val {:.3} against D {:.3} (delta_model in [{lo:.3}, {hi:.3}] bounds nothing the size of D)",
                self.u_val, self.d
            ),
            VvWord::ModelError => format!(
                "model error: delta_model in [{lo:.3}, {hi:.3}] (|E| = {:.1} u_val)",
                self.ratio
            ),
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
        assert_eq!(v.delta_model(), (0.0, 6.0));
    }

    #[test]
    fn the_word_needs_an_interval_narrower_than_the_quantity() {
        // The replica's 30-state cell: |E| within 2 u_val, but u_val = 30 nmi on 3.38 nmi.
        let wide = Validation::new(4.5, 3.38, 0.1, 30.0, 0.2);
        assert!(wide.consistent);
        assert_eq!(wide.word, VvWord::NotInformative);
        assert!(wide.verdict().starts_with("not informative: u_val 30.0"));
        // The same E with u_val = 0.8: 2 u_val = 1.6 < 3.38, the interval [-0.48, 2.72].
        let tight = Validation::new(4.5, 3.38, 0.0, 0.8, 0.0);
        assert_eq!(tight.word, VvWord::Validated);
        let (lo, hi) = tight.delta_model();
        assert!((lo + 0.48).abs() < 1e-12 && (hi - 2.72).abs() < 1e-12);
        // E beyond 2 u_val: a model error whatever the width.
        let off = Validation::new(86.0, 3.38, 0.1, 1.0, 0.2);
        assert_eq!(off.word, VvWord::ModelError);
        assert!(
            off.verdict()
                .starts_with("model error: delta_model in [80.")
        );
        // Exactly at the edge (2 u_val = |D|) is not informative.
        let edge = Validation::new(3.0, 2.0, 0.0, 1.0, 0.0);
        assert_eq!(edge.word, VvWord::NotInformative);
    }
}
