//! Kinematics of the turntable's angular vibration: Euler-angle channels
//! `θ_i(τ) = A_i sin(ω_i τ + φ_i) − A_i sin φ_i`, the attitude `Rz(θz) Ry(θy) Rx(θx)` relative
//! to the segment start, and the body rate from the Euler-angle rates.

use crate::trig::{reduced_phase, sin_cos};
use sins_nav::{Quat, Vec3};

/// One Euler-angle channel of a vibration: `θ(τ) = A sin(ω τ + φ) − A sin φ`, τ = t − t_start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct VibrationAxis {
    /// Amplitude A (rad).
    pub amp_rad: f64,
    /// Angular frequency ω = 2π/P (rad/s).
    pub omega_radps: f64,
    /// Phase φ (rad).
    pub phase_rad: f64,
    /// A sin φ (rad), subtracted so that θ(0) = 0.
    pub offset_rad: f64,
}

impl VibrationAxis {
    /// Angle θ (rad) and rate dθ/dt (rad/s) at τ seconds into the segment.
    #[inline]
    pub fn angle_and_rate(&self, tau_s: f64) -> (f64, f64) {
        let (s, c) = sin_cos(reduced_phase(self.omega_radps, tau_s, self.phase_rad));
        (
            self.amp_rad * s - self.offset_rad,
            self.amp_rad * self.omega_radps * c,
        )
    }
}

/// Rotation about body x, y or z by `angle_rad` as a quaternion (fast half-angle sin/cos).
#[inline]
pub(crate) fn quat_about_body_axis(axis: usize, angle_rad: f64) -> nalgebra::Quaternion<f64> {
    let (s, c) = sin_cos(0.5 * angle_rad);
    match axis {
        0 => nalgebra::Quaternion::new(c, s, 0.0, 0.0),
        1 => nalgebra::Quaternion::new(c, 0.0, s, 0.0),
        _ => nalgebra::Quaternion::new(c, 0.0, 0.0, s),
    }
}

/// `Rz(θz) · Ry(θy) · Rx(θx)` as a unit quaternion for angles `[θx, θy, θz]` (rad).
pub(crate) fn vibration_rotation(theta_rad: [f64; 3]) -> Quat {
    let q = quat_about_body_axis(2, theta_rad[2])
        * quat_about_body_axis(1, theta_rad[1])
        * quat_about_body_axis(0, theta_rad[0]);
    Quat::new_normalize(q)
}

/// Body rate ω_nb^b of `Rz(θz) Ry(θy) Rx(θx)` from the Euler-angle rates:
/// `ω = [θ̇x − sin θy θ̇z, cos θx θ̇y + sin θx cos θy θ̇z, −sin θx θ̇y + cos θx cos θy θ̇z]`, given
/// `(sin, cos)` of θx and θy.
#[inline]
pub(crate) fn vibration_body_rate(sc_x: (f64, f64), sc_y: (f64, f64), rate: [f64; 3]) -> Vec3 {
    let (sx, cx) = sc_x;
    let (sy, cy) = sc_y;
    Vec3::new(
        rate[0] - sy * rate[2],
        cx * rate[1] + sx * cy * rate[2],
        -sx * rate[1] + cx * cy * rate[2],
    )
}
