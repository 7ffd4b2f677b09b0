//! The paper's least-squares baseline (Table 3): 30-state calibrations at stable chamber
//! temperatures, then a straight line of each temperature-dependent constant against the mean
//! temperature of the accelerometer that scales it; the slopes are TB, TK and TM.

use crate::error::StudyError;
use crate::lsfit::{LineFit, fit_line};
use crate::run::CalibrationRun;
use crate::units::{PARAMS, TEMPERATURE_PAIRS, to_paper, vec_to_paper};
use serde::Serialize;
use sins_imu::{ImuErrorParams, ParamModel};
use sins_kf::params_to_vec;
use sins_sim::Scenario;

/// One temperature point: a 30-state calibration at a stable chamber temperature.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LsPoint {
    /// Run name.
    pub run: String,
    /// Seed.
    pub seed: u64,
    /// Chamber set point (degC).
    pub chamber_degc: f64,
    /// Mean thermometer reading of each accelerometer over the filter run (degC).
    pub mean_temp_degc: [f64; 3],
    /// The 21 constant coefficients (paper units, eq-8 order).
    pub estimate: Vec<f64>,
    /// Their 1-sigma.
    pub sigma: Vec<f64>,
    /// Largest |estimate − truth at this temperature| / sigma over the 21 coefficients (the
    /// truth at T is `C + T_coef (T̄_j − T_ref)`): the point calibrations are consistent.
    pub max_abs_z: f64,
}

/// One temperature coefficient from the line fit (paper units).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LsCoefficient {
    /// Temperature coefficient name, e.g. `"TK_ay"`.
    pub name: String,
    /// Its paper unit.
    pub unit: String,
    /// The constant it is the slope of, e.g. `"dK_ay"`.
    pub constant: String,
    /// Regressor: the accelerometer whose temperature scales it (`"T_x"`, `"T_y"`, `"T_z"`).
    pub regressor: String,
    /// Slope of the fit: the estimated temperature coefficient.
    pub slope: f64,
    /// Its 1-sigma propagated from the four calibrations' sigmas.
    pub slope_sigma: f64,
    /// The fitted constant at the truth's reference temperature.
    pub constant_at_reference: f64,
    /// RMS of the four points about the line (constant's unit).
    pub residual_rms: f64,
}

/// The four-temperature least-squares baseline.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LsStudy {
    /// Experiment name.
    pub experiment: String,
    /// The temperature points.
    pub points: Vec<LsPoint>,
    /// The 12 fitted temperature coefficients in eq-8 order.
    pub coefficients: Vec<LsCoefficient>,
    /// Calibrated (simulated) time, summed over the points (h).
    pub calibrated_h: f64,
    /// Settling time per point before its calibration (h, not simulated).
    pub settling_h: f64,
    /// Total calibration time: calibrated + settling at every point (h).
    pub total_h: f64,
}

/// Check that a baseline scenario holds its chamber at one temperature and return it.
pub fn stable_chamber_degc(sc: &Scenario) -> Result<f64, StudyError> {
    if sc.thermal.chamber.is_empty() {
        Ok(sc.thermal.chamber_start_degc)
    } else {
        Err(StudyError::Setup(format!(
            "least-squares run `{}`: the chamber must hold one temperature (no [[thermal.chamber]] segments)",
            sc.name
        )))
    }
}

impl LsStudy {
    /// Fit the baseline from its runs (same order as `scenarios`), the truth IMU, the calibrated
    /// duration of each point (h) and the settling time per point (h).
    pub fn new(
        experiment: String,
        scenarios: &[Scenario],
        runs: &[CalibrationRun],
        truth: &ImuErrorParams,
        calibrated_h: f64,
        settling_h: f64,
    ) -> Result<Self, StudyError> {
        let t = params_to_vec(truth, ParamModel::States42);
        let tref = truth.reference_temperature_degc;
        let mut points = Vec::with_capacity(runs.len());
        let mut est_si = Vec::with_capacity(runs.len());
        let mut sig_si = Vec::with_capacity(runs.len());
        for (sc, run) in scenarios.iter().zip(runs) {
            let e = params_to_vec(&run.result.params, ParamModel::States30);
            let s = params_to_vec(&run.result.sigma, ParamModel::States30);
            let mut at_t = t[..21].to_vec();
            for &(c, tc, j) in &TEMPERATURE_PAIRS {
                at_t[c] += t[tc] * (run.mean_filter_temp_degc[j] - tref);
            }
            let max_abs_z = (0..21)
                .map(|k| ((e[k] - at_t[k]) / s[k]).abs())
                .fold(0.0, f64::max);
            points.push(LsPoint {
                run: sc.name.clone(),
                seed: sc.seed,
                chamber_degc: stable_chamber_degc(sc)?,
                mean_temp_degc: run.mean_filter_temp_degc,
                estimate: vec_to_paper(&e),
                sigma: vec_to_paper(&s),
                max_abs_z,
            });
            est_si.push(e);
            sig_si.push(s);
        }
        let mut coefficients = Vec::with_capacity(12);
        let mut pairs = TEMPERATURE_PAIRS;
        pairs.sort_by_key(|p| p.1);
        for (c, tc, j) in pairs {
            let x: Vec<f64> = points.iter().map(|p| p.mean_temp_degc[j]).collect();
            let y: Vec<f64> = est_si.iter().map(|e| e[c]).collect();
            let s: Vec<f64> = sig_si.iter().map(|e| e[c]).collect();
            let fit: LineFit = fit_line(&x, &y, Some(&s)).ok_or_else(|| {
                StudyError::Setup(format!(
                    "least-squares fit of {}: needs at least two distinct temperatures",
                    PARAMS[c].name
                ))
            })?;
            coefficients.push(LsCoefficient {
                name: PARAMS[tc].name.to_owned(),
                unit: PARAMS[tc].unit.to_owned(),
                constant: PARAMS[c].name.to_owned(),
                regressor: format!("T_{}", ["x", "y", "z"][j]),
                slope: to_paper(tc, fit.slope),
                slope_sigma: to_paper(tc, fit.slope_sigma),
                constant_at_reference: to_paper(c, fit.at(tref)),
                residual_rms: to_paper(c, fit.residual_rms),
            });
        }
        let n = points.len() as f64;
        Ok(Self {
            experiment,
            points,
            coefficients,
            calibrated_h,
            settling_h,
            total_h: calibrated_h + n * settling_h,
        })
    }
}
