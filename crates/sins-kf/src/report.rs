//! What a calibration returns: the estimated coefficients with their 1-sigma, the convergence
//! history and the observability report.

use crate::states::{STATE_NAMES, STATE_UNITS};
use sins_imu::ImuErrorParams;
use sins_nav::alignment::AlignmentResult;

/// One point of the convergence history.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// Time (s) of the filter update.
    pub t_s: f64,
    /// Estimate of every coefficient in state order (SI): 21 or 33 values.
    pub estimate: Vec<f64>,
    /// 1-sigma of every state in state order (SI, [`STATE_NAMES`] / [`STATE_UNITS`]): 30 or 42
    /// values, the 9 navigation errors first.
    pub sigma: Vec<f64>,
}

/// How much the calibration scheme reduced the uncertainty of one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateObservability {
    /// State name as in eq (8), e.g. `"TM_ayx"`.
    pub name: &'static str,
    /// SI unit of the sigmas.
    pub unit: &'static str,
    /// 1-sigma when the filter started (SI).
    pub initial_sigma: f64,
    /// 1-sigma at the end (SI).
    pub final_sigma: f64,
    /// `final_sigma / initial_sigma`.
    pub ratio: f64,
    /// True when the ratio exceeds the configured threshold: the scheme does not excite this
    /// state (enough).
    pub weak: bool,
}

/// Final over initial 1-sigma of every state.
#[derive(Clone, Debug, PartialEq)]
pub struct ObservabilityReport {
    /// One entry per state in state order (30 or 42).
    pub states: Vec<StateObservability>,
    /// The ratio above which a state is flagged as weak.
    pub threshold: f64,
}

impl ObservabilityReport {
    /// Build from initial and final sigmas (state order) with flag threshold `threshold`.
    pub fn new(initial: &[f64], last: &[f64], threshold: f64) -> Self {
        let states = initial
            .iter()
            .zip(last)
            .enumerate()
            .map(|(i, (&s0, &s1))| {
                let ratio = if s0 > 0.0 { s1 / s0 } else { f64::NAN };
                StateObservability {
                    name: STATE_NAMES[i],
                    unit: STATE_UNITS[i],
                    initial_sigma: s0,
                    final_sigma: s1,
                    ratio,
                    weak: ratio.is_nan() || ratio > threshold,
                }
            })
            .collect();
        Self { states, threshold }
    }

    /// Names of the states flagged as weak.
    pub fn weak_states(&self) -> Vec<&'static str> {
        self.states
            .iter()
            .filter(|s| s.weak)
            .map(|s| s.name)
            .collect()
    }

    /// The coefficient entries only (without the 9 navigation states).
    pub fn coefficients(&self) -> &[StateObservability] {
        &self.states[crate::states::NAV_STATES.min(self.states.len())..]
    }
}

/// One measurement update's horizontal velocity innovation, each component divided by the
/// square root of its predicted variance (`z_N/√S_NN`, `z_E/√S_EE`): standard normal when the
/// filter's model holds (any mistuning of its noise scales them by a constant).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StandardizedInnovation {
    /// Time (s) of the update.
    pub t_s: f64,
    /// North component (dimensionless).
    pub north: f64,
    /// East component (dimensionless).
    pub east: f64,
}

/// Result of a calibration run.
#[derive(Clone, Debug)]
pub struct CalibrationResult {
    /// Estimated coefficients (SI), the running totals at the end of the data.
    pub params: ImuErrorParams,
    /// 1-sigma of each coefficient (SI, same layout as `params`).
    pub sigma: ImuErrorParams,
    /// Final covariance of the coefficient block (SI, state order of eq 8), row-major
    /// `n × n` with n = 21 or 33; its diagonal is the square of `sigma`. For consistency
    /// checks (NEES) that need the correlations.
    pub param_covariance: Vec<f64>,
    /// The estimate the calibration started from.
    pub initial_params: ImuErrorParams,
    /// The prior 1-sigma of each coefficient.
    pub initial_sigma: ImuErrorParams,
    /// Convergence history, one snapshot per snapshot interval (the last update included).
    pub history: Vec<Snapshot>,
    /// Final/initial sigma of every state.
    pub observability: ObservabilityReport,
    /// The stationary alignment that preceded the filter.
    pub alignment: AlignmentResult,
    /// Time (s) at which the filter started (end of alignment).
    pub filter_start_s: f64,
    /// Time (s) of the last filter update.
    pub filter_end_s: f64,
    /// Number of measurement updates.
    pub updates: usize,
    /// Largest horizontal velocity innovation of any update (m/s).
    pub max_innovation_mps: f64,
    /// Largest normalized horizontal velocity innovation `z_N²/S_NN + z_E²/S_EE` of any update
    /// (χ² with 2 degrees of freedom when the filter is consistent).
    pub max_normalized_innovation: f64,
    /// Every update's standardized innovation, rejected ones included, when asked for
    /// ([`crate::CalibrationFilter::keep_innovations`]); empty otherwise.
    pub innovations: Vec<StandardizedInnovation>,
}
