//! Navigation core of sinsbench: WGS-84 Earth, frames and attitude, strapdown mechanization on
//! angular and velocity increments, vertical-channel damping, stationary self-alignment, the
//! linearised navigation error model that the filters and the diagnosis use
//! ([`error_model`]), and a linear static error model written independently of both, used as a
//! check of the mechanization and of [`error_model`].
//!
//! Frames follow Wang et al. 2021: `n` is north-east-down (NED), `b` is right-forward-up (RFU).
//! Everything is SI: radians, metres, seconds, m/s, m/s^2.
//!
#![doc = include_str!("../README.md")]

pub mod alignment;
pub mod attitude;
pub mod earth;
pub mod error_model;
pub mod linear;
pub mod mechanization;
pub mod reconstruct;
pub mod simd4;

pub use alignment::{AlignmentConfig, AlignmentError, AlignmentResult, SelfAlignment};
pub use attitude::{Euler, enu_from_body_euler, ned_from_body_euler};
pub use earth::{EarthAt, Geodetic, Wgs84};
pub use mechanization::{
    ConingOrder, Increment, NavState, Strapdown, StrapdownConfig, VerticalChannel,
    compensated_increments,
};

/// 3-vector of f64 (SI units, frame given by the variable name).
pub type Vec3 = nalgebra::Vector3<f64>;
/// 3x3 matrix of f64.
pub type Mat3 = nalgebra::Matrix3<f64>;
/// Unit quaternion used for attitude, e.g. `ned_from_body`.
pub type Quat = nalgebra::UnitQuaternion<f64>;

/// Degrees to radians.
pub const DEG: f64 = std::f64::consts::PI / 180.0;
/// Arc-seconds to radians.
pub const ARCSEC: f64 = DEG / 3600.0;
/// Degrees per hour to radians per second.
pub const DEG_PER_H: f64 = DEG / 3600.0;
/// Standard gravity used for the `ug` unit (m/s^2).
pub const G0_MPS2: f64 = 9.80665;
/// One micro-g in m/s^2.
pub const UG: f64 = 1e-6 * G0_MPS2;
/// One nautical mile in metres.
pub const NMI_M: f64 = 1852.0;
