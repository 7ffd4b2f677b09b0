//! `Replay::push_batch` compensates a batch four samples at a time before it navigates them;
//! `Replay::push` compensates one sample at a time. Both must give the same replay to the bit.
//! (A stationary run shows the last bits of the velocity increments in its velocities; those
//! of the angular increments vanish into the attitude, so `sins-imu`'s own test compares the
//! compensated increments themselves.)

use sins_imu::{Compensator, ImuErrorParams, ImuSample, ParamModel};
use sins_nav::*;
use sins_replay::{Replay, ReplayConfig, ReplayError, Start};
use sins_sim::Simulator;

/// A 42-state IMU at ten times the magnitudes of the paper's Table 1 presets and Table 3
/// coefficients (so that every term of the compensation moves every sample).
fn params() -> ImuErrorParams {
    let mut p = ImuErrorParams::ideal(ParamModel::States42);
    p.gyro.bias_radps = Vec3::new(0.03, -0.02, 0.01) * DEG_PER_H;
    p.gyro.scale = Vec3::new(200e-6, 400e-6, 600e-6);
    p.gyro.misalignment_rad = [-618.8, 412.5, -206.3].map(|a| a * ARCSEC);
    p.accel.bias_mps2 = Vec3::new(10.0, -20.0, 30.0) * UG;
    p.accel.scale = Vec3::new(100e-6, 300e-6, 500e-6);
    p.accel.misalignment_rad = [-412.5, 206.2, 618.8, -618.8, -206.2, 412.5].map(|a| a * ARCSEC);
    p.temperature.bias_mps2_per_degc = Vec3::new(-27.7, 26.3, -254.5) * UG;
    p.temperature.scale_per_degc = Vec3::new(193.3e-6, 139.6e-6, 355.8e-6);
    p.temperature.misalignment_rad_per_degc =
        [-1.2, -0.2, -1.3, 1.4, 3.7, -4.7].map(|a| a * ARCSEC);
    p
}

/// Three minutes of the simulated stationary IMU (36,000 samples at 200 Hz) with a navigation
/// grade's white noise and a noisy thermometer (so that no two samples are alike), and its
/// scenario.
fn samples() -> (sins_sim::Scenario, Vec<ImuSample>) {
    let mut sc = crate::pipeline::stationary(0.05, params());
    sc.noise.gyro_arw_rad_per_sqrt_s = 0.002 * DEG / 60.0;
    sc.noise.accel_vrw_mps_per_sqrt_s = 20.0 * UG;
    sc.thermal.thermometer_noise_degc = 0.01;
    let mut sim = Simulator::from_scenario(&sc).expect("scenario");
    let mut xs = Vec::new();
    sim.run(10_000, |b| {
        xs.extend_from_slice(&b.samples);
        Ok::<_, ()>(())
    })
    .expect("simulated");
    (sc, xs)
}

fn replay(sc: &sins_sim::Scenario, coning: ConingOrder, stamped: bool) -> Replay {
    let nav = StrapdownConfig {
        sample_interval_s: 0.005,
        coning,
        vertical: VerticalChannel::Hold {
            height_m: sc.site.height_m,
        },
    };
    let state = NavState::at_rest(0.0, sc.motion.initial_ned_from_body, sc.site);
    let config = ReplayConfig {
        nav,
        start: Start::Known(state),
        output_interval_s: 1.0,
    };
    let comp = Compensator::new(params()).expect("params");
    Replay::new(config, comp, sc.site, 0.0).with_stamped_intervals(stamped)
}

/// Every error point and the final state, as text that shows each `f64` to the bit.
fn track(r: &Replay) -> String {
    format!("{:?} {:?}", r.points(), r.nav_state())
}

/// The whole track and its summary after [`Replay::finish`], as in [`track`].
fn finished(r: Replay) -> String {
    format!("{:?}", r.finish().expect("navigated"))
}

#[test]
fn a_batch_and_its_samples_one_at_a_time_replay_to_the_same_bits() {
    let (sc, xs) = samples();
    let segments: Vec<u16> = (0..xs.len()).map(|i| (i / 7_000) as u16).collect();
    for coning in [ConingOrder::Reconstruct, ConingOrder::TwoSample] {
        for stamped in [false, true] {
            let mut one = replay(&sc, coning, stamped);
            for (x, &g) in xs.iter().zip(&segments) {
                one.push(x, g).expect("sample");
            }
            let mut batched = replay(&sc, coning, stamped);
            // Batches of uneven length, so that quads and scalar tails straddle them.
            for (part, seg) in xs.chunks(3_001).zip(segments.chunks(3_001)) {
                batched.push_batch(part, Some(seg)).expect("batch");
            }
            let (a, b) = (finished(one), finished(batched));
            assert!(a.len() > 3_000, "{coning:?}: {a}");
            assert_eq!(a, b, "{coning:?}, stamped {stamped}");
        }
    }
}

#[test]
fn a_batch_stops_at_its_first_sample_without_temperatures_as_single_samples_do() {
    let (sc, mut xs) = samples();
    let bad = 20_003;
    xs[bad].temp_degc[1] = f64::NAN;
    let mut one = replay(&sc, ConingOrder::TwoSample, false);
    let first_error = xs
        .iter()
        .position(|x| one.push(x, 0).is_err())
        .expect("an error");
    assert_eq!(first_error, bad);
    let mut batched = replay(&sc, ConingOrder::TwoSample, false);
    let err = batched
        .push_batch(&xs, None)
        .expect_err("missing temperature");
    assert!(
        matches!(err, ReplayError::MissingTemperature { t_s } if t_s == xs[bad].t_s),
        "{err}"
    );
    assert_eq!(track(&one), track(&batched));
    assert!(one.points().len() >= 99);
}
