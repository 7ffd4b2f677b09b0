//! The simulator on its own thread feeding filters and replays: the same results, to the bit,
//! as everything on one thread, and a failing consumer stops the run with its own error.

use sins_harness::HarnessError;
use sins_harness::feed::{Consumer, feed};
use sins_harness::pipeline::{NamedParams, simulate_and_calibrate, simulate_and_replay};
use sins_imu::{ImuErrorParams, ParamModel};
use sins_nav::{AlignmentConfig, DEG, Euler, Geodetic, Vec3, ned_from_body_euler};
use sins_replay::setup::{ReplayOptions, StartMode};
use sins_sim::{
    MotionProgram, MotionSegment, NoiseModel, Scenario, SimBatch, Simulator, ThermalModel,
};

fn dwell(duration_s: f64) -> MotionSegment {
    MotionSegment::Dwell {
        duration_s,
        label: "dwell".into(),
    }
}

fn rotate(axis: [f64; 3]) -> MotionSegment {
    MotionSegment::Rotate {
        axis_body: Vec3::from(axis),
        angle_rad: 90.0 * DEG,
        rate_radps: 10.0 * DEG,
        label: "rotate".into(),
    }
}

/// 36 min at 100 Hz: 21 min still (the filter's alignment takes 20), then turns about each axis between dwells; a noisy IMU in a
/// warming chamber with the truth's errors, so that every random stream and the thermal model
/// are in play.
fn scenario() -> Scenario {
    let mut segments = vec![dwell(1260.0)];
    for axis in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
        segments.push(rotate(axis));
        segments.push(dwell(291.0));
    }
    let mut truth = ImuErrorParams::ideal(ParamModel::States42);
    truth.gyro.bias_radps = Vec3::new(0.05, -0.03, 0.02) * DEG / 3600.0;
    Scenario {
        name: "feed".into(),
        description: "feed test".into(),
        site: Geodetic::from_deg(28.22, 112.99, 50.0),
        rate_hz: 100.0,
        quadrature_nodes: 4,
        motion: MotionProgram {
            initial_ned_from_body: ned_from_body_euler(&Euler::from_deg(1.0, -1.0, 30.0)),
            segments,
        },
        thermal: ThermalModel {
            chamber_start_degc: 20.0,
            chamber: Vec::new(),
            accel_time_constant_s: [600.0; 3],
            accel_offset_degc: [0.0; 3],
            accel_initial_degc: Some([15.0; 3]),
            thermometer_noise_degc: 0.01,
        },
        noise: NoiseModel {
            gyro_arw_rad_per_sqrt_s: 0.002 * DEG / 60.0,
            gyro_bias_instability_radps: 0.003 * DEG / 3600.0,
            gyro_bias_correlation_s: 600.0,
            gyro_quantum_rad: 0.0,
            accel_vrw_mps_per_sqrt_s: 20e-6 * 9.8 / 60.0,
            accel_bias_instability_mps2: 10e-6 * 9.8,
            accel_bias_correlation_s: 600.0,
        },
        truth,
        effects: Vec::new(),
        seed: 7,
        with_reference: false,
    }
}

#[test]
fn the_filters_on_their_own_threads_give_the_one_thread_results_to_the_bit() {
    let sc = scenario();
    let models = [ParamModel::States42, ParamModel::States30];
    let run = |threads| {
        let mut samples = 0u64;
        let r = simulate_and_calibrate(&sc, &models, 20.0, threads, &mut |n| samples += n)
            .expect("calibration");
        (format!("{r:?}"), samples)
    };
    let (one, n1) = run(1);
    assert_eq!(n1, 216_000);
    for threads in [2, 4] {
        let (many, n) = run(threads);
        assert_eq!(n, n1, "progress with {threads} threads");
        assert!(one == many, "{threads} threads changed a calibration");
    }
}

#[test]
fn the_replays_beside_the_simulator_give_the_one_thread_outcome_to_the_bit() {
    let sc = scenario();
    let options = ReplayOptions {
        start: StartMode::Align(AlignmentConfig {
            duration_s: 240.0,
            coarse_duration_s: 60.0,
            ..AlignmentConfig::default()
        }),
        ..ReplayOptions::default()
    };
    let mut truth = sc.truth;
    truth.gyro.bias_radps = Vec3::zeros();
    let sets = [
        NamedParams {
            key: "truth".into(),
            params: sc.truth,
        },
        NamedParams {
            key: "no gyro bias".into(),
            params: truth,
        },
    ];
    let run = |threads| {
        let out = simulate_and_replay(&sc, &sets, &options, threads, &mut |_| {}).expect("replay");
        // The set that omits the gyro bias drifts: the comparison below is of real tracks.
        assert!(out.tracks[1].summary.max_horizontal_m > out.tracks[0].summary.max_horizontal_m);
        format!("{out:?}")
    };
    let one = run(1);
    assert!(
        one == run(2),
        "the simulator on its own thread changed a track"
    );
}

/// Folds every sample a consumer sees, in order, into a fingerprint (FNV-1a over the bits).
fn fold(hash: &mut u64, b: &SimBatch) -> Result<(), HarnessError> {
    for s in &b.samples {
        for v in [s.t_s, s.dtheta_rad[0], s.dv_mps[2], s.temp_degc[1]] {
            *hash = (*hash ^ v.to_bits()).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    Ok(())
}

#[test]
fn every_consumer_sees_every_batch_in_order_and_the_first_failure_stops_the_run() {
    let sc = scenario();
    let hashes = |threads, fail_at: Option<usize>| {
        let mut sim = Simulator::from_scenario(&sc).expect("scenario");
        let mut h = [0xcbf2_9ce4_8422_2325u64; 3];
        let mut calls = 0usize;
        let result = {
            let [h0, h1, h2] = &mut h;
            let calls = &mut calls;
            let mut consumers: Vec<Consumer<'_>> = vec![
                Box::new(move |b: &SimBatch| fold(h0, b)),
                Box::new(move |b: &SimBatch| {
                    *calls += 1;
                    if Some(*calls) == fail_at {
                        return Err(HarnessError::Mismatch(format!("stop at batch {calls}")));
                    }
                    fold(h1, b)
                }),
                Box::new(move |b: &SimBatch| fold(h2, b)),
            ];
            feed(&mut sim, 1000, threads, &mut consumers, &mut |_| {})
        };
        (result.map_err(|e| e.to_string()), h, calls)
    };
    let (r1, h1, calls) = hashes(1, None);
    assert_eq!(r1, Ok(()));
    assert_eq!(calls, 216);
    assert!(h1[0] == h1[1] && h1[1] == h1[2]);
    let (r3, h3, _) = hashes(3, None);
    assert_eq!(r3, Ok(()));
    assert_eq!(h3, h1, "a consumer on its own thread saw other batches");
    for threads in [1, 3] {
        let (r, _, calls) = hashes(threads, Some(40));
        assert_eq!(r, Err("stop at batch 40".to_string()), "{threads} threads");
        assert_eq!(calls, 40, "{threads} threads");
    }
}
