//! Navigate a dataset: an IMU standing level on a turntable at 28.22 deg N, facing 30 deg east of
//! north, for 80 minutes at 100 Hz, simulated in memory with `sins-sim` (exact increments, no
//! noise) and replayed with `sins-replay` on the `sins-nav` mechanization: aligned for 20 minutes
//! and then navigated for an hour, or navigated for the whole 80 minutes from the true start.
//! Prints the maximum horizontal error of each replay, in metres, and checks it against what the
//! physics says:
//!
//! 1. an error-free IMU, self-aligned, stays within a centimetre: the floor of the replay itself;
//! 2. an IMU whose forward accelerometer reads b = 100 µg too much, navigated from the true
//!    start, drifts along the Schuler loop, `b (1 − cos ω_s t) / ω_s²`, whose largest value
//!    `2 b / ω_s²` (about 1.27 km) comes after half a Schuler period (42 minutes);
//! 3. the same IMU self-aligned: the levelling tilts the attitude until the tilt cancels the
//!    bias (`φ_N = ∇_E / g`, `φ_E = −∇_N / g`) and the gyrocompass turns the heading by
//!    `−tan L · ∇_E / g`. That cancels the bias's east component for good, but the Earth's rate
//!    turns the east tilt of its north component into a growing north tilt: about 90 m after an
//!    hour, as the independent linear error model (`sins_nav::linear::propagate_static`) says
//!    from those aligned errors.
//!
//! `cargo run --release -p sins-replay --example navigate_dataset` (under a second). A dataset
//! file read with `sins-data` is replayed the same way, batch by batch (`sinsbench navigate`).

use sins_imu::{Compensator, ForwardModel, ImuErrorParams, ImuSample, ParamModel};
use sins_nav::alignment::AlignmentConfig;
use sins_nav::linear::propagate_static;
use sins_nav::{
    ConingOrder, EarthAt, Euler, Geodetic, NavState, StrapdownConfig, UG, Vec3, VerticalChannel,
    ned_from_body_euler,
};
use sins_replay::{Replay, ReplayConfig, ReplaySummary, Start};
use sins_sim::{MotionProgram, MotionSegment, NoiseModel, Scenario, ThermalModel, simulate_to_vec};
use std::error::Error;
use std::time::Instant;

/// A dataset in memory: what a dataset file holds (rate, site, samples in time order).
struct Dataset {
    rate_hz: f64,
    site: Geodetic,
    samples: Vec<ImuSample>,
}

/// A level IMU at rest at `site`, facing `yaw_deg`, for `duration_s`, with the error
/// coefficients `truth` and no noise.
fn simulate(
    site: Geodetic,
    yaw_deg: f64,
    duration_s: f64,
    truth: ImuErrorParams,
) -> Result<Dataset, Box<dyn Error>> {
    let rate_hz = 100.0;
    let scenario = Scenario {
        name: "stationary".into(),
        description: "level, at rest, no noise".into(),
        site,
        rate_hz,
        quadrature_nodes: 2,
        motion: MotionProgram {
            initial_ned_from_body: ned_from_body_euler(&Euler::from_deg(0.0, 0.0, yaw_deg)),
            segments: vec![MotionSegment::Dwell {
                duration_s,
                label: "stationary".into(),
            }],
        },
        thermal: ThermalModel {
            chamber_start_degc: 20.0,
            chamber: Vec::new(),
            accel_time_constant_s: [600.0; 3],
            accel_offset_degc: [0.0; 3],
            accel_initial_degc: None,
            thermometer_noise_degc: 0.0,
        },
        noise: NoiseModel::default(),
        truth,
        effects: Vec::new(),
        seed: 1,
        with_reference: false,
    };
    let batch = simulate_to_vec(&scenario, ForwardModel::new(truth))?;
    Ok(Dataset {
        rate_hz,
        site,
        samples: batch.samples,
    })
}

/// Replays `data` compensated with `params` (the ideal set: no calibration), from `start`.
fn navigate(
    data: &Dataset,
    params: ImuErrorParams,
    start: Start,
) -> Result<ReplaySummary, Box<dyn Error>> {
    let config = ReplayConfig {
        nav: StrapdownConfig {
            sample_interval_s: 1.0 / data.rate_hz,
            coning: ConingOrder::TwoSample,
            vertical: VerticalChannel::Hold {
                height_m: data.site.height_m,
            },
        },
        start,
        output_interval_s: 1.0,
    };
    let compensator = Compensator::new(params).ok_or("singular parameter set")?;
    // The first sample's interval starts at t = 0.
    let mut replay = Replay::new(config, compensator, data.site, 0.0);
    for chunk in data.samples.chunks(65_536) {
        replay.push_batch(chunk, None)?;
    }
    Ok(replay.finish()?.1)
}

fn report(what: &str, s: &ReplaySummary, expected: &str) {
    println!("{what}:");
    let at = if s.max_horizontal_m > 0.0 {
        format!("at t = {:.1} min", s.t_max_s / 60.0)
    } else {
        "(every error point exactly 0)".into()
    };
    println!(
        "  max horizontal error {:.4} m ({:.5} nmi) {at}, {:.0} min navigated",
        s.max_horizontal_m,
        s.max_horizontal_nmi(),
        s.navigated_s / 60.0
    );
    println!("  {expected}");
}

fn main() -> Result<(), Box<dyn Error>> {
    let started = Instant::now();
    let site = Geodetic::from_deg(28.22, 112.99, 60.0);
    let yaw_deg = 30.0;
    let duration_s = 80.0 * 60.0;
    let ideal = ImuErrorParams::ideal(ParamModel::States30);
    let align = Start::SelfAlign(AlignmentConfig::default()); // 20 min, as the paper
    let ned_from_body = ned_from_body_euler(&Euler::from_deg(0.0, 0.0, yaw_deg));
    let truth_start = Start::Known(NavState::at_rest(0.0, ned_from_body, site));

    // 1. Error-free IMU, self-aligned.
    let clean = simulate(site, yaw_deg, duration_s, ideal)?;
    let floor = navigate(&clean, ideal, align)?;
    report(
        "error-free IMU, self-aligned",
        &floor,
        "expected below 0.01 m",
    );

    // 2. 100 ug on the forward accelerometer, from the true start.
    let bias_mps2 = 100.0 * UG;
    let mut biased_imu = ideal;
    biased_imu.accel.bias_mps2 = Vec3::new(0.0, bias_mps2, 0.0);
    let biased = simulate(site, yaw_deg, duration_s, biased_imu)?;
    let schuler = navigate(&biased, ideal, truth_start)?;
    let earth = EarthAt::new(site.lat_rad, site.height_m);
    let omega_s = (earth.gravity_mps2 / earth.meridian_plus_h_m).sqrt();
    let peak_m = 2.0 * bias_mps2 / (omega_s * omega_s);
    let half_period_min = std::f64::consts::PI / omega_s / 60.0;
    report(
        "100 ug forward accelerometer bias, true start",
        &schuler,
        &format!("expected 2 b / w_s^2 = {peak_m:.3} m at {half_period_min:.1} min"),
    );

    // 3. The same data, self-aligned, against the linear error model from the aligned errors.
    let levelled = navigate(&biased, ideal, align)?;
    let g = earth.gravity_mps2;
    let bias_ned = ned_from_body * Vec3::new(0.0, bias_mps2, 0.0);
    let aligned_phi_ned = Vec3::new(
        bias_ned.y / g,
        -bias_ned.x / g,
        -site.lat_rad.tan() * bias_ned.y / g,
    );
    let linear_m = propagate_static(
        site.lat_rad,
        site.height_m,
        &aligned_phi_ned,
        &Vec3::zeros(),
        &bias_ned,
        levelled.navigated_s,
        10.0,
    )
    .iter()
    .map(|p| p.horizontal_m())
    .fold(0.0, f64::max);
    report(
        "100 ug forward accelerometer bias, self-aligned",
        &levelled,
        &format!("expected {linear_m:.3} m (linear error model from the aligned tilt and heading)"),
    );

    let simulated = clean.samples.len() + biased.samples.len();
    let replayed = clean.samples.len() + 2 * biased.samples.len();
    println!(
        "{simulated} samples simulated and {replayed} replayed in {:.2} s",
        started.elapsed().as_secs_f64()
    );

    assert!(floor.max_horizontal_m < 0.01, "{floor:?}");
    assert!(
        (schuler.max_horizontal_m / peak_m - 1.0).abs() < 0.02,
        "{} m vs {peak_m} m",
        schuler.max_horizontal_m
    );
    assert!(
        (schuler.t_max_s / 60.0 - half_period_min).abs() < 2.0,
        "peak at {} min",
        schuler.t_max_s / 60.0
    );
    assert!(
        (levelled.max_horizontal_m / linear_m - 1.0).abs() < 0.05,
        "{} m vs {linear_m} m",
        levelled.max_horizontal_m
    );
    Ok(())
}
