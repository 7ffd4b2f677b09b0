//! Cross-checks through the whole pipeline: simulator (exact increments, forward model eqs 1-2)
//! → compensation (eqs 3-5) → strapdown replay, against the independent linear error model.

use sins_imu::{Compensator, ImuErrorParams, ParamModel};
use sins_nav::linear::propagate_static;
use sins_nav::*;
use sins_replay::{Replay, ReplayConfig, ReplaySummary, Start};
use sins_sim::{ChamberSegment, MotionSegment, Scenario, Simulator};
use std::path::PathBuf;

fn base_scenario() -> Scenario {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../experiments/error_free_navigation.toml");
    sins_config::load_experiment(p)
        .expect("experiment")
        .scenarios
        .remove(0)
}

/// A stationary scenario of `hours`, level with the forward axis north.
pub(crate) fn stationary(hours: f64, truth: ImuErrorParams) -> Scenario {
    let mut sc = base_scenario();
    sc.motion.initial_ned_from_body = ned_from_body_euler(&Euler::default());
    sc.motion.segments = vec![MotionSegment::Dwell {
        duration_s: hours * 3600.0,
        label: "stationary".into(),
    }];
    sc.truth = truth;
    sc
}

fn replay(sc: &Scenario, params: ImuErrorParams) -> ReplaySummary {
    let mut sim = Simulator::from_scenario(sc).expect("scenario");
    let nav = StrapdownConfig {
        sample_interval_s: sim.sample_interval_s(),
        coning: ConingOrder::TwoSample,
        vertical: VerticalChannel::Hold {
            height_m: sc.site.height_m,
        },
    };
    let start = Start::Known(NavState::at_rest(
        0.0,
        sc.motion.initial_ned_from_body,
        sc.site,
    ));
    let comp = Compensator::new(params).expect("params");
    let mut r = Replay::new(
        ReplayConfig {
            nav,
            start,
            output_interval_s: 10.0,
        },
        comp,
        sc.site,
        0.0,
    );
    sim.run(65_536, |b| r.push_batch(&b.samples, None))
        .expect("replay");
    r.finish().expect("navigated").1
}

fn linear_max(sc: &Scenario, gyro_body: Vec3, accel_body: Vec3, hours: f64) -> f64 {
    let q = sc.motion.initial_ned_from_body;
    propagate_static(
        sc.site.lat_rad,
        sc.site.height_m,
        &Vec3::zeros(),
        &(q * gyro_body),
        &(q * accel_body),
        hours * 3600.0,
        10.0,
    )
    .iter()
    .map(|p| p.horizontal_m())
    .fold(0.0, f64::max)
}

#[test]
fn simulated_north_gyro_bias_matches_the_linear_model() {
    let mut truth = ImuErrorParams::ideal(ParamModel::States30);
    truth.gyro.bias_radps = Vec3::new(0.0, 0.005 * DEG_PER_H, 0.0); // body y = north
    let sc = stationary(15.0, truth);
    let mech = replay(&sc, ImuErrorParams::ideal(ParamModel::States30)).max_horizontal_m;
    let lin = linear_max(&sc, truth.gyro.bias_radps, Vec3::zeros(), 15.0);
    eprintln!("simulated north gyro 0.005 deg/h: replay {mech:.1} m, linear {lin:.1} m");
    assert!(
        lin > 1000.0 && (mech - lin).abs() < 0.05 * lin,
        "{mech} vs {lin}"
    );
}

#[test]
fn simulated_east_accel_bias_matches_the_linear_model() {
    let mut truth = ImuErrorParams::ideal(ParamModel::States30);
    truth.accel.bias_mps2 = Vec3::new(20.0 * UG, 0.0, 0.0); // body x = east
    let sc = stationary(15.0, truth);
    let mech = replay(&sc, ImuErrorParams::ideal(ParamModel::States30)).max_horizontal_m;
    let lin = linear_max(&sc, Vec3::zeros(), truth.accel.bias_mps2, 15.0);
    eprintln!("simulated east accel 20 ug: replay {mech:.1} m, linear {lin:.1} m");
    assert!(
        lin > 100.0 && (mech - lin).abs() < 0.05 * lin,
        "{mech} vs {lin}"
    );
}

/// The paper's full truth IMU (Table 1 constants + Table 3 temperature coefficients) on a
/// thermal ramp, compensated with its own 42-state set, navigates like an ideal IMU; dropping
/// the temperature terms (a 30-state set at the reference temperature) does not.
#[test]
fn exact_42_state_compensation_removes_every_modelled_error_under_a_thermal_ramp() {
    let p =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/imu/paper_truth.toml");
    let truth = sins_config::load_params(p).expect("truth").params;
    let mut sc = stationary(4.0, truth);
    sc.thermal.chamber_start_degc = 0.0;
    sc.thermal.chamber = vec![ChamberSegment::Ramp {
        duration_s: 4.0 * 3600.0,
        rate_degc_per_s: 10.0 / 3600.0,
    }];
    sc.thermal.thermometer_noise_degc = 0.0;
    sc.motion.initial_ned_from_body = ned_from_body_euler(&Euler::from_deg(1.0, -91.0, -91.0));
    let with = replay(&sc, truth).max_horizontal_m;
    let mut thirty = truth;
    thirty.model = ParamModel::States30;
    thirty.temperature = Default::default();
    let without = replay(&sc, thirty).max_horizontal_m;
    let none = replay(&sc, ImuErrorParams::ideal(ParamModel::States30)).max_horizontal_m;
    eprintln!(
        "4 h ramp 0->40 degC: 42-state {with:.3} m, 30-state {without:.1} m, uncompensated {none:.1} m"
    );
    assert!(
        with < 0.5,
        "exact compensation should leave the floor, got {with} m"
    );
    assert!(
        without > 100.0 * with.max(0.01),
        "temperature terms must matter: {without} m"
    );
    assert!(
        none > without,
        "uncompensated {none} m vs 30-state {without} m"
    );
}
