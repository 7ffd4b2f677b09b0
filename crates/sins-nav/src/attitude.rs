//! Attitude conventions of the paper: navigation frame n = north-east-down, body frame
//! b = right-forward-up. Euler angles use the right-forward-up convention common in Chinese SINS
//! literature: `C_enu_from_body = Rz(yaw) · Rx(pitch) · Ry(roll)`, so that zero angles mean level
//! with the forward axis pointing north, yaw is positive counter-clockwise seen from above
//! (heading = -yaw), pitch is positive nose-up and roll positive right-wing-down.

use crate::{Mat3, Quat, Vec3};
use nalgebra::{Rotation3, Unit};

/// Euler angles in radians in the right-forward-up convention described in the module docs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Euler {
    /// Pitch about the body right axis (rad).
    pub pitch_rad: f64,
    /// Roll about the body forward axis (rad).
    pub roll_rad: f64,
    /// Yaw about the up axis (rad), counter-clockwise positive.
    pub yaw_rad: f64,
}

impl Euler {
    /// Angles from degrees.
    pub fn from_deg(pitch_deg: f64, roll_deg: f64, yaw_deg: f64) -> Self {
        Self {
            pitch_rad: pitch_deg.to_radians(),
            roll_rad: roll_deg.to_radians(),
            yaw_rad: yaw_deg.to_radians(),
        }
    }
}

/// Rotation taking ENU coordinates to NED coordinates (a constant permutation with a sign).
pub fn ned_from_enu() -> Mat3 {
    Mat3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0)
}

/// `C_enu_from_body` for the given Euler angles.
pub fn enu_from_body_euler(e: &Euler) -> Mat3 {
    let rz = Rotation3::from_axis_angle(&Vec3::z_axis(), e.yaw_rad);
    let rx = Rotation3::from_axis_angle(&Vec3::x_axis(), e.pitch_rad);
    let ry = Rotation3::from_axis_angle(&Vec3::y_axis(), e.roll_rad);
    (rz * rx * ry).into_inner()
}

/// Attitude quaternion `ned_from_body` for the given Euler angles.
pub fn ned_from_body_euler(e: &Euler) -> Quat {
    let m = ned_from_enu() * enu_from_body_euler(e);
    Quat::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

/// Euler angles (rad) of an attitude quaternion `ned_from_body` (inverse of
/// [`ned_from_body_euler`], pitch in [-90, 90] deg).
pub fn euler_from_ned_from_body(ned_from_body: &Quat) -> Euler {
    let c = ned_from_enu().transpose() * ned_from_body.to_rotation_matrix().into_inner();
    // c = Rz(y) Rx(p) Ry(r): c[2,1] = sin p, c[2,0] = -cos p sin r, c[2,2] = cos p cos r,
    // c[0,1] = -sin y cos p, c[1,1] = cos y cos p.
    let pitch = c[(2, 1)].clamp(-1.0, 1.0).asin();
    let roll = (-c[(2, 0)]).atan2(c[(2, 2)]);
    let yaw = (-c[(0, 1)]).atan2(c[(1, 1)]);
    Euler {
        pitch_rad: pitch,
        roll_rad: roll,
        yaw_rad: yaw,
    }
}

/// Skew-symmetric cross-product matrix `[v×]`.
pub fn skew(v: &Vec3) -> Mat3 {
    Mat3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Exact unit quaternion of a rotation vector (rad), using a series near zero.
pub fn quat_from_rotation_vector(phi_rad: &Vec3) -> Quat {
    let a2 = phi_rad.norm_squared();
    let (s, c) = if a2 < 1e-8 {
        // sin(a/2)/a and cos(a/2) to O(a^6): relative error below 1e-20 for a < 1e-4.
        (
            0.5 - a2 / 48.0 + a2 * a2 / 3840.0,
            1.0 - a2 / 8.0 + a2 * a2 / 384.0,
        )
    } else {
        let a = a2.sqrt();
        ((0.5 * a).sin() / a, (0.5 * a).cos())
    };
    Quat::new_unchecked(nalgebra::Quaternion::new(
        c,
        s * phi_rad.x,
        s * phi_rad.y,
        s * phi_rad.z,
    ))
}

/// Small-angle attitude error φ (rad, in the navigation frame) between an estimated
/// `ned_from_body` and the true one, defined by `C_est = (I - [φ×]) C_true`.
pub fn attitude_error_ned_rad(est_ned_from_body: &Quat, true_ned_from_body: &Quat) -> Vec3 {
    // C_true C_est^T = I + [φ×] to first order: its rotation vector is φ.
    let d = true_ned_from_body * est_ned_from_body.inverse();
    d.scaled_axis()
}

/// Rotation about a unit axis by an angle (rad), as a quaternion.
pub fn quat_about_axis(axis: &Vec3, angle_rad: f64) -> Quat {
    Quat::from_axis_angle(&Unit::new_normalize(*axis), angle_rad)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_attitude_is_right_east_forward_north_up_up() {
        let q = ned_from_body_euler(&Euler::default());
        let c = q.to_rotation_matrix();
        assert!((c * Vec3::x() - Vec3::new(0.0, 1.0, 0.0)).norm() < 1e-15); // right = east
        assert!((c * Vec3::y() - Vec3::new(1.0, 0.0, 0.0)).norm() < 1e-15); // forward = north
        assert!((c * Vec3::z() - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-15); // up = -down
    }

    #[test]
    fn euler_round_trip_and_sense() {
        let e = Euler::from_deg(1.0, -91.0, -91.0);
        let back = euler_from_ned_from_body(&ned_from_body_euler(&e));
        assert!((back.pitch_rad - e.pitch_rad).abs() < 1e-12);
        assert!((back.roll_rad - e.roll_rad).abs() < 1e-12);
        assert!((back.yaw_rad - e.yaw_rad).abs() < 1e-12);
        // Positive pitch raises the forward axis: its down component becomes negative.
        let c = ned_from_body_euler(&Euler::from_deg(10.0, 0.0, 0.0)).to_rotation_matrix();
        assert!((c * Vec3::y()).z < -0.17);
        // Positive yaw turns the forward axis from north towards west.
        let c = ned_from_body_euler(&Euler::from_deg(0.0, 0.0, 10.0)).to_rotation_matrix();
        assert!((c * Vec3::y()).y < -0.17);
    }

    #[test]
    fn rotation_vector_quaternion_is_exact() {
        for phi in [
            Vec3::new(1e-9, -2e-9, 3e-9),
            Vec3::new(1e-5, 2e-5, -1e-5),
            Vec3::new(0.3, -0.2, 0.9),
        ] {
            let q = quat_from_rotation_vector(&phi);
            let r = Quat::from_scaled_axis(phi);
            assert!(q.angle_to(&r) < 1e-15, "{phi:?}");
            assert!((q.scaled_axis() - phi).norm() <= 1e-15 * (1.0 + phi.norm()));
        }
    }
}
