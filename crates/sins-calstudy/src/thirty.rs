//! The 30-state filter (no temperature coefficients) on the Table 1 data: its constant
//! accelerometer coefficients absorb the temperature terms at roughly the mean accelerometer
//! temperature of the run, `B + TB (T̄ − T_ref)`, instead of the truth at the reference.

use crate::run::CalibrationRun;
use crate::units::{PARAMS, TEMPERATURE_PAIRS, to_paper};
use serde::Serialize;
use sins_imu::{ImuErrorParams, ParamModel};
use sins_kf::params_to_vec;

/// One temperature-dependent constant of the 30-state estimate (paper units).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LeakEntry {
    /// Coefficient name, e.g. `"B_az"`.
    pub name: String,
    /// Paper unit.
    pub unit: String,
    /// Truth at the reference temperature (the constant of the truth IMU).
    pub truth_at_reference: f64,
    /// 30-state estimate.
    pub estimate_30: f64,
    /// 30-state estimate − truth at the reference.
    pub error_30: f64,
    /// 30-state 1-sigma.
    pub sigma_30: f64,
    /// 42-state estimate on the same data − truth.
    pub error_42: f64,
    /// 42-state 1-sigma.
    pub sigma_42: f64,
    /// Name of the temperature coefficient that drives this constant, e.g. `"TB_az"`.
    pub temperature_coefficient: String,
    /// Its true value (paper unit per degC).
    pub temperature_coefficient_value: f64,
    /// Accelerometer (0 x, 1 y, 2 z) whose temperature scales it.
    pub accel: usize,
    /// `T_coef · (T̄ − T_ref)`: the shift expected if the constant sits at the mean temperature T̄
    /// of that accelerometer over the filter run.
    pub expected_shift: f64,
    /// Temperature the 30-state constant effectively corresponds to:
    /// `T_ref + error_30 / T_coef` (degC).
    pub effective_temp_degc: f64,
    /// 1-sigma of that temperature from the 30-state sigma: `sigma_30 / |T_coef|` (degC).
    pub effective_temp_sigma_degc: f64,
}

/// One gyro coefficient of the 30-state estimate (paper units): not temperature dependent in
/// the truth, but free to absorb part of the unmodelled temperature terms.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GyroLeakEntry {
    /// Coefficient name, e.g. `"dK_gz"`.
    pub name: String,
    /// Paper unit.
    pub unit: String,
    /// 30-state estimate − truth.
    pub error_30: f64,
    /// 30-state 1-sigma.
    pub sigma_30: f64,
    /// 42-state estimate − truth on the same data.
    pub error_42: f64,
    /// 42-state 1-sigma.
    pub sigma_42: f64,
}

/// The 30-state leak study.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ThirtyStateStudy {
    /// Seed of the data (the Table 1 run's own seed).
    pub seed: u64,
    /// Reference temperature of the truth IMU (degC).
    pub reference_temp_degc: f64,
    /// Mean thermometer reading of each accelerometer over the filter run (degC).
    pub mean_filter_temp_degc: [f64; 3],
    /// The 12 accelerometer constants that carry a temperature term (bias, scale, installation).
    pub entries: Vec<LeakEntry>,
    /// The 9 gyro coefficients.
    pub gyro: Vec<GyroLeakEntry>,
    /// Largest |error/sigma| of the 9 gyro coefficients of the 30-state run.
    pub gyro_max_abs_z: f64,
    /// Median effective temperature of the three biases and three scale factors (degC).
    pub median_effective_temp_degc: f64,
    /// Inverse-variance weighted mean of the 12 effective temperatures (degC).
    pub weighted_effective_temp_degc: f64,
    /// Its 1-sigma (degC).
    pub weighted_effective_temp_sigma_degc: f64,
}

impl ThirtyStateStudy {
    /// Compare a 30-state and a 42-state run of the same data with the 42-state truth.
    pub fn new(
        seed: u64,
        run30: &CalibrationRun,
        run42: &CalibrationRun,
        truth: &ImuErrorParams,
    ) -> Self {
        let t = params_to_vec(truth, ParamModel::States42);
        let e30 = params_to_vec(&run30.result.params, ParamModel::States30);
        let s30 = params_to_vec(&run30.result.sigma, ParamModel::States30);
        let e42 = params_to_vec(&run42.result.params, ParamModel::States42);
        let s42 = params_to_vec(&run42.result.sigma, ParamModel::States42);
        let tref = truth.reference_temperature_degc;
        let mean = run30.mean_filter_temp_degc;
        let entries: Vec<LeakEntry> = TEMPERATURE_PAIRS
            .iter()
            .map(|&(c, tc, j)| {
                let err = to_paper(c, e30[c] - t[c]);
                // Per-degC coefficient in the constant's paper unit.
                let coef = to_paper(c, t[tc]);
                LeakEntry {
                    name: PARAMS[c].name.to_owned(),
                    unit: PARAMS[c].unit.to_owned(),
                    truth_at_reference: to_paper(c, t[c]),
                    estimate_30: to_paper(c, e30[c]),
                    error_30: err,
                    sigma_30: to_paper(c, s30[c]),
                    error_42: to_paper(c, e42[c] - t[c]),
                    sigma_42: to_paper(c, s42[c]),
                    temperature_coefficient: PARAMS[tc].name.to_owned(),
                    temperature_coefficient_value: to_paper(tc, t[tc]),
                    accel: j,
                    expected_shift: coef * (mean[j] - tref),
                    effective_temp_degc: tref + err / coef,
                    effective_temp_sigma_degc: to_paper(c, s30[c]) / coef.abs(),
                }
            })
            .collect();
        let gyro: Vec<GyroLeakEntry> = (0..3)
            .chain(6..12)
            .map(|k| GyroLeakEntry {
                name: PARAMS[k].name.to_owned(),
                unit: PARAMS[k].unit.to_owned(),
                error_30: to_paper(k, e30[k] - t[k]),
                sigma_30: to_paper(k, s30[k]),
                error_42: to_paper(k, e42[k] - t[k]),
                sigma_42: to_paper(k, s42[k]),
            })
            .collect();
        let gyro_max_abs_z = gyro
            .iter()
            .map(|g| (g.error_30 / g.sigma_30).abs())
            .fold(0.0, f64::max);
        let bs: Vec<f64> = entries[..6].iter().map(|e| e.effective_temp_degc).collect();
        let (mut wsum, mut w) = (0.0, 0.0);
        for e in &entries {
            let wi = e.effective_temp_sigma_degc.powi(-2);
            wsum += wi * e.effective_temp_degc;
            w += wi;
        }
        Self {
            seed,
            reference_temp_degc: tref,
            mean_filter_temp_degc: mean,
            median_effective_temp_degc: crate::stats::median(&bs),
            weighted_effective_temp_degc: wsum / w,
            weighted_effective_temp_sigma_degc: w.sqrt().recip(),
            entries,
            gyro,
            gyro_max_abs_z,
        }
    }
}
