//! Table 3 with the truth column: the 42-state (proposed) and the least-squares temperature
//! coefficients of the same truth IMU against the truth, beside the paper's two columns, and the
//! calibration time of each method.

use crate::baseline::LsStudy;
use crate::reference::Table3;
use crate::run::CalibrationRun;
use crate::units::{PARAMS, to_paper};
use serde::Serialize;
use sins_imu::{ImuErrorParams, ParamModel};
use sins_kf::params_to_vec;

/// One temperature coefficient (paper units).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table3Entry {
    /// Name (eq 8).
    pub name: String,
    /// Paper unit.
    pub unit: String,
    /// Truth of the simulated IMU.
    pub truth: f64,
    /// Our 42-state estimate.
    pub proposed: f64,
    /// Its 1-sigma.
    pub proposed_sigma: f64,
    /// Our 42-state estimate − truth.
    pub proposed_error: f64,
    /// Our least-squares slope.
    pub ls: f64,
    /// Its 1-sigma (propagated from the four calibrations).
    pub ls_sigma: f64,
    /// Our least-squares slope − truth.
    pub ls_error: f64,
    /// The paper's proposed value (Table 3).
    pub paper_proposed: f64,
    /// The paper's least-squares value (Table 3).
    pub paper_ls: f64,
}

/// The Table 3 comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table3Study {
    /// Experiment of the proposed (42-state) calibration.
    pub proposed_experiment: String,
    /// Seed of that run.
    pub proposed_seed: u64,
    /// The 12 temperature coefficients in eq-8 order.
    pub entries: Vec<Table3Entry>,
    /// Calibration time of the proposed method (h): one run.
    pub proposed_time_h: f64,
    /// Calibration time of the least-squares method (h): four runs plus settling.
    pub ls_time_h: f64,
    /// Coefficients where |proposed error| < |LS error|.
    pub proposed_closer: usize,
    /// RMS over the 12 of (error / 1-sigma), proposed.
    pub proposed_rms_z: f64,
    /// RMS over the 12 of (error / 1-sigma), least squares.
    pub ls_rms_z: f64,
    /// The same errors relative to the truth's magnitude, RMS over the 12 (proposed).
    pub proposed_rms_relative: f64,
    /// The same, least squares.
    pub ls_rms_relative: f64,
    /// Median over the 12 of LS 1-sigma / proposed 1-sigma.
    pub median_sigma_ratio_ls_over_proposed: f64,
}

impl Table3Study {
    /// Build from the proposed run (42-state on the truth experiment), the LS baseline, the truth
    /// and the paper's Table 3.
    pub fn new(
        proposed_experiment: String,
        proposed_seed: u64,
        proposed: &CalibrationRun,
        proposed_time_h: f64,
        ls: &LsStudy,
        truth: &ImuErrorParams,
        table3: &Table3,
    ) -> Self {
        let t = params_to_vec(truth, ParamModel::States42);
        let e = params_to_vec(&proposed.result.params, ParamModel::States42);
        let s = params_to_vec(&proposed.result.sigma, ParamModel::States42);
        let entries: Vec<Table3Entry> = (21..33)
            .map(|k| {
                let lsc = ls.coefficients.iter().find(|c| c.name == PARAMS[k].name);
                let paper = table3.rows.iter().find(|r| r.state_index == k);
                let truth_k = to_paper(k, t[k]);
                let ls_v = lsc.map_or(f64::NAN, |c| c.slope);
                Table3Entry {
                    name: PARAMS[k].name.to_owned(),
                    unit: PARAMS[k].unit.to_owned(),
                    truth: truth_k,
                    proposed: to_paper(k, e[k]),
                    proposed_sigma: to_paper(k, s[k]),
                    proposed_error: to_paper(k, e[k] - t[k]),
                    ls: ls_v,
                    ls_sigma: lsc.map_or(f64::NAN, |c| c.slope_sigma),
                    ls_error: ls_v - truth_k,
                    paper_proposed: paper.map_or(f64::NAN, |r| r.proposed),
                    paper_ls: paper.map_or(f64::NAN, |r| r.least_squares),
                }
            })
            .collect();
        let rms = |f: &dyn Fn(&Table3Entry) -> f64| {
            (entries.iter().map(|e| f(e).powi(2)).sum::<f64>() / entries.len() as f64).sqrt()
        };
        Self {
            proposed_experiment,
            proposed_seed,
            proposed_time_h,
            ls_time_h: ls.total_h,
            proposed_closer: entries
                .iter()
                .filter(|e| e.proposed_error.abs() < e.ls_error.abs())
                .count(),
            proposed_rms_z: rms(&|e| e.proposed_error / e.proposed_sigma),
            ls_rms_z: rms(&|e| e.ls_error / e.ls_sigma),
            proposed_rms_relative: rms(&|e| e.proposed_error / e.truth),
            ls_rms_relative: rms(&|e| e.ls_error / e.truth),
            median_sigma_ratio_ls_over_proposed: crate::stats::median(
                &entries
                    .iter()
                    .map(|e| e.ls_sigma / e.proposed_sigma)
                    .collect::<Vec<_>>(),
            ),
            entries,
        }
    }
}
