//! The 33 coefficients of eq (8) with their paper names and units (from `sins_config`), and the
//! conversion of SI values to the paper's units for the reports.

use sins_config::{PaperUnit, coefficient_table};
use sins_imu::{ImuErrorParams, ParamModel};
use std::sync::LazyLock;

/// Name, unit and SI factor of one coefficient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamInfo {
    /// The paper's name, e.g. `"TK_az"` (eq-8 state names).
    pub name: &'static str,
    /// The paper's unit, e.g. `"ppm/degC"`.
    pub unit: &'static str,
    /// SI value of one paper unit.
    pub si_per_unit: f64,
}

/// The 33 coefficients in the state order of eq (8).
pub static PARAMS: LazyLock<Vec<ParamInfo>> = LazyLock::new(|| {
    const UNITS: [PaperUnit; 7] = [
        PaperUnit::DegPerH,
        PaperUnit::Ppm,
        PaperUnit::Arcsec,
        PaperUnit::Ug,
        PaperUnit::UgPerDegC,
        PaperUnit::PpmPerDegC,
        PaperUnit::ArcsecPerDegC,
    ];
    coefficient_table(&ImuErrorParams::ideal(ParamModel::States42))
        .into_iter()
        .map(|c| ParamInfo {
            name: c.name,
            unit: c.unit,
            si_per_unit: UNITS
                .iter()
                .find(|u| u.label() == c.unit)
                .map_or(f64::NAN, |u| u.si()),
        })
        .collect()
});

/// Index (0..33, eq-8 order) of a coefficient name.
pub fn param_index(name: &str) -> Option<usize> {
    PARAMS.iter().position(|p| p.name == name)
}

/// Coefficient `k` (eq-8 order) of an SI value in its paper unit.
pub fn to_paper(k: usize, si: f64) -> f64 {
    si / PARAMS[k].si_per_unit
}

/// A coefficient vector (SI, eq-8 order, 21 or 33 entries) in paper units.
pub fn vec_to_paper(si: &[f64]) -> Vec<f64> {
    si.iter()
        .enumerate()
        .map(|(k, v)| to_paper(k, *v))
        .collect()
}

/// For each of the 12 temperature-dependent constant accelerometer coefficients (eq-8 index):
/// its temperature coefficient's index and the accelerometer whose temperature scales it. Eq (1)
/// multiplies column j of the temperature matrix by accelerometer j's temperature, so the
/// installation error `dM_a(i,j)` (coupling axis j into accelerometer i) goes with `T_j`.
pub const TEMPERATURE_PAIRS: [(usize, usize, usize); 12] = [
    (3, 21, 0),  // B_ax   <- TB_ax
    (4, 22, 1),  // B_ay   <- TB_ay
    (5, 23, 2),  // B_az   <- TB_az
    (12, 24, 0), // dK_ax  <- TK_ax
    (16, 25, 1), // dK_ay  <- TK_ay
    (20, 26, 2), // dK_az  <- TK_az
    (13, 27, 0), // dM_ayx <- TM_ayx (column x)
    (14, 28, 0), // dM_azx <- TM_azx (column x)
    (15, 29, 1), // dM_axy <- TM_axy (column y)
    (17, 30, 1), // dM_azy <- TM_azy (column y)
    (18, 31, 2), // dM_axz <- TM_axz (column z)
    (19, 32, 2), // dM_ayz <- TM_ayz (column z)
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_units_follow_the_filter_state_order() {
        assert_eq!(PARAMS.len(), 33);
        for (k, p) in PARAMS.iter().enumerate() {
            assert_eq!(p.name, sins_kf::STATE_NAMES[9 + k]);
            assert!(
                p.si_per_unit.is_finite() && p.si_per_unit > 0.0,
                "{}",
                p.name
            );
        }
        assert_eq!(to_paper(26, 3e-6), 3.0);
        // Each pair: the temperature coefficient carries the constant's name with a T prefix.
        for (c, t, j) in TEMPERATURE_PAIRS {
            let (cn, tn) = (PARAMS[c].name, PARAMS[t].name);
            let stem = &cn[cn.find('_').unwrap_or(0)..];
            assert!(tn.ends_with(stem), "{cn} vs {tn}");
            assert_eq!(cn.as_bytes()[cn.len() - 1], b"xyz"[j], "{cn} column");
        }
    }
}
