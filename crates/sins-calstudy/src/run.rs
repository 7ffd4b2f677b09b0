//! One calibration: the simulator streamed straight into the calibration filter (no files),
//! with the mean accelerometer temperatures over the filter span and the time spent.

use crate::error::StudyError;
use sins_imu::{ImuErrorParams, ParamModel};
use sins_kf::{CalibrationConfig, CalibrationFilter, CalibrationResult};
use sins_sim::{Scenario, Simulator};
use std::time::{Duration, Instant};

/// Samples per simulator batch (bounded memory: about 6 MB).
const BATCH_LEN: usize = 65_536;

/// A finished calibration of one simulated scenario.
#[derive(Clone, Debug)]
pub struct CalibrationRun {
    /// The filter's result (estimate, 1-sigma, covariance, history, observability).
    pub result: CalibrationResult,
    /// Mean thermometer reading of each accelerometer (degC) over the samples the Kalman filter
    /// used (after the alignment).
    pub mean_filter_temp_degc: [f64; 3],
    /// Number of samples simulated and filtered.
    pub samples: usize,
    /// Wall time of simulation and filter together.
    pub wall: Duration,
    /// Wall time spent inside the filter (`push` and `finish`) only.
    pub filter: Duration,
}

/// The default filter configuration for a scenario: `model`, the scenario's sample interval and
/// site, and the filter noise of its `[imu.noise]` ([`crate::filter_noise_from_experiment`]).
pub fn config_for_scenario(scenario: &Scenario, model: ParamModel) -> CalibrationConfig {
    let mut c = CalibrationConfig::new(model, 1.0 / scenario.rate_hz, scenario.site);
    c.noise = crate::filter_noise_from_experiment(&scenario.noise);
    c
}

/// Simulate `scenario` and calibrate it with `config`, starting from the ideal (all-zero)
/// estimate at the truth's reference temperature.
pub fn calibrate_scenario(
    scenario: &Scenario,
    config: CalibrationConfig,
) -> Result<CalibrationRun, StudyError> {
    let started = Instant::now();
    let states = config.model.n_states();
    let fail = |source| StudyError::Calibration {
        scenario: format!("{} (seed {})", scenario.name, scenario.seed),
        states,
        source,
    };
    let mut initial = ImuErrorParams::ideal(config.model);
    initial.reference_temperature_degc = scenario.truth.reference_temperature_degc;
    let filter_from_s = config.alignment.duration_s;
    let mut filter = CalibrationFilter::new(config, initial).map_err(fail)?;
    let mut sim = Simulator::from_scenario(scenario).map_err(|source| StudyError::Simulation {
        scenario: scenario.name.clone(),
        source,
    })?;
    let mut in_filter = Duration::ZERO;
    let (mut temp_sum, mut temp_n, mut samples) = ([0.0f64; 3], 0usize, 0usize);
    let fed = sim.run(BATCH_LEN, |b| {
        for s in b.samples.iter().filter(|s| s.t_s > filter_from_s) {
            for (acc, t) in temp_sum.iter_mut().zip(s.temp_degc) {
                *acc += t;
            }
            temp_n += 1;
        }
        samples += b.samples.len();
        let t0 = Instant::now();
        let r = filter.push_batch(&b.samples, None);
        in_filter += t0.elapsed();
        r
    });
    fed.map_err(fail)?;
    let t0 = Instant::now();
    let result = filter.finish().map_err(fail)?;
    in_filter += t0.elapsed();
    let n = temp_n.max(1) as f64;
    Ok(CalibrationRun {
        result,
        mean_filter_temp_degc: temp_sum.map(|s| s / n),
        samples,
        wall: started.elapsed(),
        filter: in_filter,
    })
}

/// Keep only the motion of the first `duration_s` seconds of a scenario: whole segments up to
/// that time (at least the first). For shortened studies and tests, e.g. the alignment and one
/// pass of the 18-step scheme instead of four.
pub fn truncate_motion(scenario: &mut Scenario, duration_s: f64) {
    use sins_sim::MotionSegment as M;
    let mut t = 0.0;
    let mut keep = 0;
    for seg in &scenario.motion.segments {
        let len = match seg {
            M::Dwell { duration_s, .. } | M::Vibrate { duration_s, .. } => *duration_s,
            M::Rotate {
                angle_rad,
                rate_radps,
                ..
            } => angle_rad.abs() / rate_radps,
        };
        if keep > 0 && t + len > duration_s + 1e-9 {
            break;
        }
        t += len;
        keep += 1;
    }
    scenario.motion.segments.truncate(keep);
}
