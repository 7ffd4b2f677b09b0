//! Scenario builders shared by the integration tests.
#![allow(dead_code)]

use sins_imu::{ImuErrorParams, ParamModel};
use sins_nav::{DEG, Euler, Geodetic, Quat, Vec3, ned_from_body_euler};
use sins_sim::{MotionProgram, MotionSegment, NoiseModel, Scenario, ThermalModel};

/// The literature's calibration start attitude: pitch 1, roll -91, yaw -91 deg.
pub fn start_attitude() -> Quat {
    ned_from_body_euler(&Euler::from_deg(1.0, -91.0, -91.0))
}

/// Changsha (the paper's site).
pub fn site() -> Geodetic {
    Geodetic::from_deg(28.22, 112.99, 50.0)
}

pub fn dwell(duration_s: f64, label: &str) -> MotionSegment {
    MotionSegment::Dwell {
        duration_s,
        label: label.into(),
    }
}

pub fn rotate(axis: [f64; 3], angle_deg: f64, rate_deg_s: f64, label: &str) -> MotionSegment {
    MotionSegment::Rotate {
        axis_body: Vec3::from(axis),
        angle_rad: angle_deg * DEG,
        rate_radps: rate_deg_s * DEG,
        label: label.into(),
    }
}

/// Vibration pattern 3 of the paper's Table 4 (8/9/15 deg at 0.2/0.1/0.15 s) with given phases.
pub fn pattern3(duration_s: f64, phase_rad: [f64; 3]) -> MotionSegment {
    MotionSegment::Vibrate {
        duration_s,
        amplitude_rad: Vec3::new(8.0, 9.0, 15.0) * DEG,
        period_s: Vec3::new(0.2, 0.1, 0.15),
        phase_rad: Vec3::from(phase_rad),
        label: "pattern3".into(),
    }
}

/// Chamber constant at 20 degC, accelerometers in equilibrium, no thermometer noise.
pub fn quiet_thermal() -> ThermalModel {
    ThermalModel {
        chamber_start_degc: 20.0,
        chamber: Vec::new(),
        accel_time_constant_s: [600.0, 600.0, 600.0],
        accel_offset_degc: [0.0; 3],
        accel_initial_degc: None,
        thermometer_noise_degc: 0.0,
    }
}

/// An ideal, noise-free IMU at 200 Hz with 6 nodes running `segments`.
pub fn scenario(segments: Vec<MotionSegment>) -> Scenario {
    Scenario {
        name: "test".into(),
        description: "integration test".into(),
        site: site(),
        rate_hz: 200.0,
        quadrature_nodes: 6,
        motion: MotionProgram {
            initial_ned_from_body: start_attitude(),
            segments,
        },
        thermal: quiet_thermal(),
        noise: NoiseModel::default(),
        truth: ImuErrorParams::ideal(ParamModel::States42),
        effects: Vec::new(),
        seed: 1,
        with_reference: false,
    }
}

/// Relative difference |a - b| / |b|.
pub fn rel(a: &Vec3, b: &Vec3) -> f64 {
    (a - b).norm() / b.norm()
}
