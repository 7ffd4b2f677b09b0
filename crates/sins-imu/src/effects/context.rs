//! What an extra effect may depend on, for one sample interval, and the tracker that fills the
//! previous-sample fields in a stream of samples.

use sins_nav::Vec3;

/// What an extra effect may depend on, for one sample interval `(t_s - dt_s, t_s]`. Everything is
/// the truth (the simulator's, or a diagnosis's best reconstruction of it), never a raw output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EffectContext {
    /// Time at the end of the interval (s).
    pub t_s: f64,
    /// Sample interval (s).
    pub dt_s: f64,
    /// True angular increment (rad) over the interval, body axes.
    pub true_dtheta_rad: Vec3,
    /// True velocity (specific-force) increment (m/s) over the interval, body axes.
    pub true_dv_mps: Vec3,
    /// True angular increment (rad) of the previous interval; equal to [`Self::true_dtheta_rad`]
    /// for the first sample of a stream (no history: differences vanish).
    pub prev_true_dtheta_rad: Vec3,
    /// True velocity increment (m/s) of the previous interval; equal to [`Self::true_dv_mps`] for
    /// the first sample of a stream.
    pub prev_true_dv_mps: Vec3,
    /// True accelerometer temperatures (degC) at the interval midpoint.
    pub accel_temp_degc: [f64; 3],
    /// Rate of change of the true accelerometer temperatures (degC/s).
    pub accel_temp_rate_degc_per_s: [f64; 3],
}

impl EffectContext {
    /// A context with zero motion at constant temperature (handy for tests).
    pub fn at_rest(t_s: f64, dt_s: f64, accel_temp_degc: [f64; 3]) -> Self {
        Self {
            t_s,
            dt_s,
            true_dtheta_rad: Vec3::zeros(),
            true_dv_mps: Vec3::zeros(),
            prev_true_dtheta_rad: Vec3::zeros(),
            prev_true_dv_mps: Vec3::zeros(),
            accel_temp_degc,
            accel_temp_rate_degc_per_s: [0.0; 3],
        }
    }

    /// Mean angular rate over the interval, `dθ/dt` (rad/s, body axes).
    pub fn mean_rate_radps(&self) -> Vec3 {
        self.true_dtheta_rad / self.dt_s
    }

    /// Mean specific force over the interval, `dv/dt` (m/s^2, body axes).
    pub fn mean_specific_force_mps2(&self) -> Vec3 {
        self.true_dv_mps / self.dt_s
    }

    /// Angular acceleration from the two last increments, `(dθ_k - dθ_{k-1})/dt^2` (rad/s^2):
    /// exact for a constant angular acceleration, located at the start of the interval.
    pub fn angular_accel_radps2(&self) -> Vec3 {
        (self.true_dtheta_rad - self.prev_true_dtheta_rad) / (self.dt_s * self.dt_s)
    }

    /// Rate of change of the specific force from the two last increments,
    /// `(dv_k - dv_{k-1})/dt^2` (m/s^3): exact for a specific force linear in time.
    pub fn specific_force_rate_mps3(&self) -> Vec3 {
        (self.true_dv_mps - self.prev_true_dv_mps) / (self.dt_s * self.dt_s)
    }

    /// Mean of the three accelerometer temperatures (degC), which drives the gyro temperature
    /// terms (the IMU has no gyro thermometer).
    pub fn mean_temp_degc(&self) -> f64 {
        self.accel_temp_degc.iter().sum::<f64>() / 3.0
    }

    /// Mean of the three accelerometer temperature rates (degC/s).
    pub fn mean_temp_rate_degc_per_s(&self) -> f64 {
        self.accel_temp_rate_degc_per_s.iter().sum::<f64>() / 3.0
    }
}

/// Builds the [`EffectContext`] of consecutive samples, carrying the previous true increments.
/// Use one tracker per stream of samples (a run); [`ContextTracker::reset`] starts a new stream.
#[derive(Clone, Debug, Default)]
pub struct ContextTracker {
    prev: Option<(Vec3, Vec3)>,
}

impl ContextTracker {
    /// A tracker at the start of a stream.
    pub fn new() -> Self {
        Self::default()
    }

    /// Forget the previous sample (the next context is the first of a stream).
    pub fn reset(&mut self) {
        self.prev = None;
    }

    /// The context of the next sample: interval end `t_s` (s), length `dt_s` (s), true increments
    /// (rad, m/s), true accelerometer temperatures (degC) and their rates (degC/s).
    pub fn next(
        &mut self,
        t_s: f64,
        dt_s: f64,
        true_dtheta_rad: Vec3,
        true_dv_mps: Vec3,
        accel_temp_degc: [f64; 3],
        accel_temp_rate_degc_per_s: [f64; 3],
    ) -> EffectContext {
        let (prev_true_dtheta_rad, prev_true_dv_mps) =
            self.prev.unwrap_or((true_dtheta_rad, true_dv_mps));
        self.prev = Some((true_dtheta_rad, true_dv_mps));
        EffectContext {
            t_s,
            dt_s,
            true_dtheta_rad,
            true_dv_mps,
            prev_true_dtheta_rad,
            prev_true_dv_mps,
            accel_temp_degc,
            accel_temp_rate_degc_per_s,
        }
    }
}
