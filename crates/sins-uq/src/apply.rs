//! A draw turned into the concrete scenarios of one sample: the calibration run (42-state, and
//! the 30-state one when it ran separately at a stable temperature) and the navigation runs.

use crate::assumptions::{AssumptionSet, Knob};
use crate::draw::{Draw, Stream, element_distribution};
use sins_imu::{ImuErrorParams, ParamModel};
use sins_kf::{params_from_vec, params_to_vec};
use sins_nav::Vec3;
use sins_nav::attitude::quat_about_axis;
use sins_replay::setup::ReplayOptions;
use sins_sim::scenario::{ChamberSegment, MotionSegment, Scenario, ThermalModel};

/// The replica as the experiment files define it (the point replica of `sinsbench report`).
#[derive(Clone, Debug)]
pub struct ReplicaBase {
    /// The truth IMU's calibration run (the 42-state filter's data).
    pub calibration: Scenario,
    /// The navigation runs (Table 5's experiments), in order.
    pub navigation: Vec<Scenario>,
    /// Reference temperature of the calibrated temperature terms (degC).
    pub reference_temperature_degc: f64,
    /// Replay settings of the navigation runs.
    pub replay: ReplayOptions,
}

/// The scenarios of one sample.
#[derive(Clone, Debug)]
pub struct SampleScenarios {
    /// The truth IMU of this sample.
    pub truth: ImuErrorParams,
    /// The calibration run the 42-state filter sees (and the 30-state filter when it is `None`
    /// in [`Self::cal30`]).
    pub cal42: Scenario,
    /// A separate stable-temperature run for the 30-state filter, if the draw says so.
    pub cal30: Option<Scenario>,
    /// The navigation runs.
    pub navigation: Vec<Scenario>,
}

/// The scenarios of `draw` (`None` values of unset knobs keep the base files' values).
pub fn build(base: &ReplicaBase, set: &AssumptionSet, draw: &Draw) -> SampleScenarios {
    let value = |knob: Knob| crate::draw::knob_value(set, draw, knob);
    let truth = truth_of(&base.calibration.truth, set, draw);
    let mut cal42 = base.calibration.clone();
    prepare(&mut cal42, set, draw, &truth, draw.cal_seed);
    let cal30 = (value(Knob::Cal30Chamber) == Some(1.0)).then(|| {
        let mut sc = cal42.clone();
        sc.name = format!("{}_stable", sc.name);
        sc.seed = draw.cal30_seed;
        let temp =
            value(Knob::Cal30StableTemperatureDegc).unwrap_or(base.reference_temperature_degc);
        let duration_s = sins_sim::MotionTimeline::new(&sc.motion)
            .map(|t| t.total_duration_s())
            .unwrap_or(0.0);
        sc.thermal.chamber_start_degc = temp;
        sc.thermal.chamber = vec![ChamberSegment::Hold {
            duration_s,
            temp_degc: temp,
        }];
        sc.thermal.accel_initial_degc = None;
        sc
    });
    let mut phases = Stream::new(draw.element_seed, 0);
    let phase_dist = element_distribution(set, draw.slot, Knob::VibrationPhaseRad).cloned();
    let navigation = base
        .navigation
        .iter()
        .enumerate()
        .map(|(i, nav)| {
            let mut sc = nav.clone();
            let seed = draw.nav_seeds.get(i).copied().unwrap_or(nav.seed);
            prepare(&mut sc, set, draw, &truth, seed);
            navigation_thermal(&mut sc.thermal, &value);
            mount(
                &mut sc,
                value(Knob::NavMounting),
                value(Knob::NavYawOffsetRad),
            );
            if let Some(d) = &phase_dist {
                for seg in &mut sc.motion.segments {
                    if let MotionSegment::Vibrate { phase_rad, .. } = seg {
                        for k in 0..3 {
                            phase_rad[k] = d.value_at(phases.uniform(), phases.normal());
                        }
                    }
                }
            }
            sc
        })
        .collect();
    SampleScenarios {
        truth,
        cal42,
        cal30,
        navigation,
    }
}

/// The base scenarios unchanged (the point replica): the files' truth, seeds and conditions.
pub fn point(base: &ReplicaBase) -> SampleScenarios {
    SampleScenarios {
        truth: base.calibration.truth,
        cal42: base.calibration.clone(),
        cal30: None,
        navigation: base.navigation.clone(),
    }
}

fn truth_of(base: &ImuErrorParams, set: &AssumptionSet, draw: &Draw) -> ImuErrorParams {
    let mut v = params_to_vec(base, ParamModel::States42);
    for (a, x) in set.assumptions.iter().zip(&draw.values) {
        if let Knob::TruthCoefficient(i) = a.knob
            && let Some(slot) = v.get_mut(i)
        {
            *slot = *x;
        }
    }
    params_from_vec(&v, ParamModel::States42, base.reference_temperature_degc)
}

/// Truth, noise, thermal lags and offsets, effects and seed: what the calibration and the
/// navigation runs share.
fn prepare(sc: &mut Scenario, set: &AssumptionSet, draw: &Draw, truth: &ImuErrorParams, seed: u64) {
    sc.truth = *truth;
    sc.seed = seed;
    sc.effects.extend(draw.effects.iter().cloned());
    for (a, &x) in set.assumptions.iter().zip(&draw.values) {
        let n = &mut sc.noise;
        match a.knob {
            Knob::GyroArw => n.gyro_arw_rad_per_sqrt_s = x,
            Knob::GyroBiasInstability => n.gyro_bias_instability_radps = x,
            Knob::GyroQuantum => n.gyro_quantum_rad = x,
            Knob::AccelVrw => n.accel_vrw_mps_per_sqrt_s = x,
            Knob::AccelBiasInstability => n.accel_bias_instability_mps2 = x,
            Knob::BiasCorrelationS => {
                n.gyro_bias_correlation_s = x;
                n.accel_bias_correlation_s = x;
            }
            Knob::ThermometerNoiseDegc => sc.thermal.thermometer_noise_degc = x,
            Knob::AccelTimeConstantScale => {
                sc.thermal.accel_time_constant_s = sc.thermal.accel_time_constant_s.map(|t| t * x)
            }
            Knob::AccelOffsetScale => {
                sc.thermal.accel_offset_degc = sc.thermal.accel_offset_degc.map(|o| o * x)
            }
            _ => {}
        }
    }
}

/// The chamber's sustained drop, fluctuations and level in a navigation run.
fn navigation_thermal(th: &mut ThermalModel, value: &dyn Fn(Knob) -> Option<f64>) {
    let base_drop: f64 = -th
        .chamber
        .iter()
        .map(ChamberSegment::trend_change_degc)
        .sum::<f64>();
    let rate_factor = match value(Knob::NavTemperatureDropDegc) {
        Some(drop) if base_drop.abs() > 1e-9 => drop / base_drop,
        _ => 1.0,
    };
    let amp = value(Knob::NavFluctuationAmplitudeScale).unwrap_or(1.0);
    let per = value(Knob::NavFluctuationPeriodScale).unwrap_or(1.0);
    let shift = value(Knob::NavTemperatureShiftDegc).unwrap_or(0.0);
    th.chamber_start_degc += shift;
    for s in &mut th.chamber {
        match s {
            ChamberSegment::Hold { temp_degc, .. } => *temp_degc += shift,
            ChamberSegment::Ramp {
                rate_degc_per_s, ..
            } => *rate_degc_per_s *= rate_factor,
            ChamberSegment::Fluctuating {
                rate_degc_per_s,
                fluctuation_amplitude_degc,
                fluctuation_period_s,
                ..
            } => {
                *rate_degc_per_s *= rate_factor;
                *fluctuation_amplitude_degc *= amp;
                *fluctuation_period_s *= per;
            }
        }
    }
    if let Some(init) = &mut th.accel_initial_degc {
        *init = init.map(|t| t + shift);
    }
}

/// Mounting (which body axis is up) and the start heading of a navigation run.
fn mount(sc: &mut Scenario, mounting: Option<f64>, yaw_offset_rad: Option<f64>) {
    let q = &mut sc.motion.initial_ned_from_body;
    match mounting.map(|m| m as usize) {
        // Rx(+90 deg) takes body y to where body z was (up); Ry(-90 deg) takes body x there.
        Some(1) => *q *= quat_about_axis(&Vec3::x(), std::f64::consts::FRAC_PI_2),
        Some(2) => *q *= quat_about_axis(&Vec3::y(), -std::f64::consts::FRAC_PI_2),
        _ => {}
    }
    if let Some(psi) = yaw_offset_rad {
        // Heading about the down axis of n (NED): a rotation of the whole table.
        *q = quat_about_axis(&Vec3::z(), psi) * *q;
    }
}
