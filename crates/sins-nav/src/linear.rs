//! Linear static error model of a stationary INS (vertical channel held), written independently
//! of the mechanization so that each can check the other. States
//! `[φ_N, φ_E, φ_D, δv_N, δv_E, δL, δλ]` obey, at rest at latitude L,
//!
//! ```text
//! φ̇  = -ω_ie × φ + δω_ie(δL) + δω_en(δv) - ε^n
//! δv̇ = f^n × φ - 2 ω_ie × δv + ∇^n            (horizontal rows, f^n = [0, 0, -g])
//! δL̇ = δv_N / (R_M + h),   δλ̇ = δv_E / ((R_N + h) cos L)
//! ```
//! with constant gyro drift ε^n and accelerometer bias ∇^n in NED. The system is propagated
//! exactly with the matrix exponential of the augmented (state, input) system.
//!
//! This module is the test oracle of [`crate::error_model`] (the model the filters use) and must
//! stay independent of it: do not rewrite it in terms of that module.

use crate::earth::EarthAt;
use crate::{Vec3, Wgs84};
use nalgebra::{SMatrix, SVector};

/// Error of the linear model at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearErrorPoint {
    /// Time since the start (s).
    pub t_s: f64,
    /// Attitude error φ in NED (rad).
    pub phi_ned_rad: Vec3,
    /// North and east velocity errors (m/s).
    pub vel_ne_mps: [f64; 2],
    /// North and east position errors (m).
    pub pos_ne_m: [f64; 2],
}

impl LinearErrorPoint {
    /// Horizontal position error magnitude (m).
    pub fn horizontal_m(&self) -> f64 {
        self.pos_ne_m[0].hypot(self.pos_ne_m[1])
    }
}

/// Propagate the static error model at `lat_rad`, `height_m` from initial attitude error
/// `phi0_ned_rad` under constant gyro drift `gyro_drift_ned_radps` (ε^n, positive = the
/// indicated rate exceeds the true) and accelerometer bias `accel_bias_ned_mps2` (∇^n) for
/// `duration_s`, returning points every `step_s`.
pub fn propagate_static(
    lat_rad: f64,
    height_m: f64,
    phi0_ned_rad: &Vec3,
    gyro_drift_ned_radps: &Vec3,
    accel_bias_ned_mps2: &Vec3,
    duration_s: f64,
    step_s: f64,
) -> Vec<LinearErrorPoint> {
    let e = EarthAt::new(lat_rad, height_m);
    let (rm, rn, cl) = (e.meridian_plus_h_m, e.transverse_plus_h_m, e.cos_lat);
    let a = static_augmented_dynamics(lat_rad, height_m);
    let phi_step = (a * step_s).exp();
    let mut x = SVector::<f64, 12>::zeros();
    x.fixed_rows_mut::<3>(0).copy_from(phi0_ned_rad);
    x.fixed_rows_mut::<3>(7).copy_from(gyro_drift_ned_radps);
    x[10] = accel_bias_ned_mps2.x;
    x[11] = accel_bias_ned_mps2.y;
    let n = (duration_s / step_s).round() as usize;
    let mut out = Vec::with_capacity(n + 1);
    for k in 0..=n {
        out.push(LinearErrorPoint {
            t_s: k as f64 * step_s,
            phi_ned_rad: Vec3::new(x[0], x[1], x[2]),
            vel_ne_mps: [x[3], x[4]],
            pos_ne_m: [x[5] * rm, x[6] * rn * cl],
        });
        x = phi_step * x;
    }
    out
}

/// Augmented 12x12 dynamics of the static model at `lat_rad`, `height_m`: the 7 states
/// `[φ_N, φ_E, φ_D (rad), δv_N, δv_E (m/s), δL, δλ (rad)]` followed by the 5 constant inputs
/// `[ε_N, ε_E, ε_D (rad/s), ∇_N, ∇_E (m/s²)]` (1/s; the input columns are the input matrix).
pub fn static_augmented_dynamics(lat_rad: f64, height_m: f64) -> SMatrix<f64, 12, 12> {
    let e = EarthAt::new(lat_rad, height_m);
    let om = Wgs84::OMEGA_IE_RADPS;
    let (sl, cl) = (e.sin_lat, e.cos_lat);
    let (rm, rn) = (e.meridian_plus_h_m, e.transverse_plus_h_m);
    let g = e.gravity_mps2;
    let mut a = SMatrix::<f64, 12, 12>::zeros();
    // -ω_ie × φ with ω_ie = [Ω cL, 0, -Ω sL].
    a[(0, 1)] = -om * sl;
    a[(1, 0)] = om * sl;
    a[(1, 2)] = om * cl;
    a[(2, 1)] = -om * cl;
    // δω_en = [δv_E/Rn, -δv_N/Rm, -δv_E tanL/Rn]; δω_ie = [-Ω sL δL, 0, -Ω cL δL].
    a[(0, 4)] = 1.0 / rn;
    a[(1, 3)] = -1.0 / rm;
    a[(2, 4)] = -sl / cl / rn;
    a[(0, 5)] = -om * sl;
    a[(2, 5)] = -om * cl;
    // f × φ with f = [0, 0, -g]: [g φ_E, -g φ_N].
    a[(3, 1)] = g;
    a[(4, 0)] = -g;
    // -2 ω_ie × δv (horizontal): [-2Ω sL δv_E, 2Ω sL δv_N].
    a[(3, 4)] = -2.0 * om * sl;
    a[(4, 3)] = 2.0 * om * sl;
    a[(5, 3)] = 1.0 / rm;
    a[(6, 4)] = 1.0 / (rn * cl);
    // Inputs.
    for i in 0..3 {
        a[(i, 7 + i)] = -1.0;
    }
    a[(3, 10)] = 1.0;
    a[(4, 11)] = 1.0;
    a
}
