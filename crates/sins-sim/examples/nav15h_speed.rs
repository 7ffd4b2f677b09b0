//! Times the generation of the paper's 15 h navigation motion (5 h stationary, vibration patterns
//! 1-3 of Table 4 with 1 h stationary between them) at 200 Hz with all noise sources on.
//!
//! Run: `cargo run --release -p sins-sim --example nav15h_speed [-- --reference]`

use sins_imu::{ImuErrorParams, ParamModel};
use sins_nav::{ARCSEC, DEG, DEG_PER_H, Euler, Geodetic, UG, Vec3, ned_from_body_euler};
use sins_sim::{
    ChamberSegment, MotionProgram, MotionSegment, NoiseModel, Scenario, Simulator, ThermalModel,
};
use std::time::Instant;

fn vibrate(label: &str, amp_deg: [f64; 3], period_s: [f64; 3]) -> MotionSegment {
    MotionSegment::Vibrate {
        duration_s: 8.0 * 3600.0 / 3.0,
        amplitude_rad: Vec3::from(amp_deg) * DEG,
        period_s: Vec3::from(period_s),
        phase_rad: Vec3::zeros(),
        label: label.into(),
    }
}

fn dwell(label: &str, hours: f64) -> MotionSegment {
    MotionSegment::Dwell {
        duration_s: hours * 3600.0,
        label: label.into(),
    }
}

fn main() {
    let with_reference = std::env::args().any(|a| a == "--reference");
    let scenario = Scenario {
        name: "nav15h".into(),
        description: "15 h navigation motion, timing run".into(),
        site: Geodetic::from_deg(28.22, 112.99, 50.0),
        rate_hz: 200.0,
        quadrature_nodes: 6,
        motion: MotionProgram {
            initial_ned_from_body: ned_from_body_euler(&Euler::from_deg(0.5, -0.3, 30.0)),
            segments: vec![
                dwell("stationary", 5.0),
                vibrate("pattern1", [2.0, 4.0, 2.0], [0.1, 0.2, 0.3]),
                dwell("stationary", 1.0),
                vibrate("pattern2", [6.0, 5.0, 6.0], [0.1, 0.2, 0.15]),
                dwell("stationary", 1.0),
                vibrate("pattern3", [8.0, 9.0, 15.0], [0.2, 0.1, 0.15]),
            ],
        },
        thermal: ThermalModel {
            chamber_start_degc: 30.0,
            chamber: vec![ChamberSegment::Fluctuating {
                duration_s: 15.0 * 3600.0,
                rate_degc_per_s: -1.0 / 3600.0,
                fluctuation_amplitude_degc: 0.5,
                fluctuation_period_s: 1800.0,
            }],
            accel_time_constant_s: [600.0, 700.0, 800.0],
            accel_offset_degc: [1.0, 1.5, 2.0],
            accel_initial_degc: None,
            thermometer_noise_degc: 0.01,
        },
        noise: NoiseModel {
            gyro_arw_rad_per_sqrt_s: 0.0005 * DEG / 60.0,
            gyro_bias_instability_radps: 0.005 * DEG_PER_H,
            gyro_bias_correlation_s: 3600.0,
            gyro_quantum_rad: 1.0 * ARCSEC,
            accel_vrw_mps_per_sqrt_s: 5.0 * UG,
            accel_bias_instability_mps2: 20.0 * UG,
            accel_bias_correlation_s: 3600.0,
        },
        truth: ImuErrorParams::ideal(ParamModel::States42),
        effects: Vec::new(),
        seed: 7,
        with_reference,
    };
    let mut sim = match Simulator::from_scenario(&scenario) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("invalid scenario: {e}");
            std::process::exit(1);
        }
    };
    let n = sim.n_samples();
    let start = Instant::now();
    let mut count = 0usize;
    let mut checksum = 0.0;
    let result: Result<(), std::convert::Infallible> = sim.run(65_536, |batch| {
        count += batch.len();
        checksum += batch.samples.iter().map(|s| s.dtheta_rad.x).sum::<f64>();
        Ok(())
    });
    let elapsed = start.elapsed().as_secs_f64();
    if let Err(e) = result {
        match e {}
    }
    println!(
        "{count} of {n} samples (reference: {with_reference}) in {elapsed:.3} s: {:.2} M samples/s \
         (checksum {checksum:.6e})",
        count as f64 / elapsed / 1e6
    );
}
