//! One IMU output sample: the record every dataset, simulator and filter exchanges.

use sins_nav::Vec3;

/// One sample of an IMU with per-accelerometer thermometers. Increments are integrals over the
/// interval `(t_s - dt, t_s]` where `dt` is the sample interval of the dataset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuSample {
    /// Time at the end of the sample interval (s).
    pub t_s: f64,
    /// Angular increment about body x (right), y (forward), z (up) (rad).
    pub dtheta_rad: Vec3,
    /// Velocity (specific-force) increment along body x, y, z (m/s).
    pub dv_mps: Vec3,
    /// Thermometer readings of the x, y and z accelerometers (degC).
    pub temp_degc: [f64; 3],
}

impl ImuSample {
    /// A sample with zero increments and temperatures.
    pub fn zero(t_s: f64) -> Self {
        Self {
            t_s,
            dtheta_rad: Vec3::zeros(),
            dv_mps: Vec3::zeros(),
            temp_degc: [0.0; 3],
        }
    }
}
