//! A simulation scenario in SI units: site, sampling, turntable motion program, thermal chamber,
//! sensor noise and the truth IMU. Files (TOML in human units) are parsed into this by
//! `sins-config`; this crate never reads files.

use sins_imu::{EffectSpec, ImuErrorParams};
use sins_nav::{Geodetic, Quat, Vec3};

/// One segment of the turntable motion program. Attitude is continuous across segments: each
/// segment starts from the attitude the previous one ended at.
#[derive(Clone, Debug, PartialEq)]
pub enum MotionSegment {
    /// Hold the current attitude for `duration_s`.
    Dwell {
        /// Length (s).
        duration_s: f64,
        /// Segment label written to the dataset (e.g. "alignment", "stationary").
        label: String,
    },
    /// Rotate about a body-fixed axis at a constant rate. Rate steps are instantaneous (the
    /// simulator integrates across the step exactly).
    Rotate {
        /// Rotation axis in body coordinates (unit vector, x right, y forward, z up).
        axis_body: Vec3,
        /// Rotation angle (rad), sign gives the sense about `axis_body`.
        angle_rad: f64,
        /// Magnitude of the rotation rate (rad/s).
        rate_radps: f64,
        /// Segment label.
        label: String,
    },
    /// Simultaneous sinusoidal angular vibration about the three body axes around the current
    /// attitude: `C_ned_from_body(t) = C_start · Rz(θz(t)) · Ry(θy(t)) · Rx(θx(t))` with
    /// `θi(t) = A_i sin(2π (t - t0)/P_i + φ_i) - A_i sin(φ_i)` (so the attitude is continuous).
    Vibrate {
        /// Length (s).
        duration_s: f64,
        /// Amplitude A about x, y, z (rad).
        amplitude_rad: Vec3,
        /// Period P about x, y, z (s); must be positive.
        period_s: Vec3,
        /// Phase φ about x, y, z (rad).
        phase_rad: Vec3,
        /// Segment label.
        label: String,
    },
}

/// The turntable motion program: initial attitude and segments in order.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionProgram {
    /// Attitude at t = 0.
    pub initial_ned_from_body: Quat,
    /// Segments in time order.
    pub segments: Vec<MotionSegment>,
}

/// One segment of the chamber temperature profile; each starts at the temperature the previous
/// one ended at (the first at [`ThermalModel::chamber_start_degc`]).
#[derive(Clone, Debug, PartialEq)]
pub enum ChamberSegment {
    /// Step to `temp_degc` and hold it for `duration_s` (a set-point step).
    Hold {
        /// Length (s).
        duration_s: f64,
        /// Set point (degC).
        temp_degc: f64,
    },
    /// Linear ramp at `rate_degc_per_s` for `duration_s`.
    Ramp {
        /// Length (s).
        duration_s: f64,
        /// Rate (degC/s), negative for cooling.
        rate_degc_per_s: f64,
    },
    /// Sustained drop (or rise) with deterministic fluctuations: linear trend plus a sinusoid of
    /// `fluctuation_amplitude_degc` and `fluctuation_period_s`, starting at zero phase.
    Fluctuating {
        /// Length (s).
        duration_s: f64,
        /// Trend (degC/s).
        rate_degc_per_s: f64,
        /// Fluctuation amplitude (degC).
        fluctuation_amplitude_degc: f64,
        /// Fluctuation period (s).
        fluctuation_period_s: f64,
    },
}

impl ChamberSegment {
    /// Change of the chamber temperature over the segment from its trend (degC): rate times
    /// duration for a ramp or a fluctuating segment (the sinusoid's end value aside), 0 for a
    /// hold (its step is not a trend).
    pub fn trend_change_degc(&self) -> f64 {
        match self {
            ChamberSegment::Hold { .. } => 0.0,
            ChamberSegment::Ramp {
                duration_s,
                rate_degc_per_s,
            }
            | ChamberSegment::Fluctuating {
                duration_s,
                rate_degc_per_s,
                ..
            } => duration_s * rate_degc_per_s,
        }
    }
}

/// Chamber profile, accelerometer thermal lags and thermometers.
#[derive(Clone, Debug, PartialEq)]
pub struct ThermalModel {
    /// Chamber temperature at t = 0 (degC).
    pub chamber_start_degc: f64,
    /// Chamber profile; after the last segment the chamber holds its final temperature.
    pub chamber: Vec<ChamberSegment>,
    /// First-order lag time constant of each accelerometer behind the chamber (s).
    pub accel_time_constant_s: [f64; 3],
    /// Steady offset of each accelerometer from the chamber (uneven heat distribution, degC).
    pub accel_offset_degc: [f64; 3],
    /// Initial accelerometer temperatures (degC); `None` starts them in equilibrium.
    pub accel_initial_degc: Option<[f64; 3]>,
    /// White noise of each thermometer reading (degC, 1 sigma).
    pub thermometer_noise_degc: f64,
}

/// Sensor noise (all zero for an ideal IMU).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct NoiseModel {
    /// Gyro angle random walk (rad/sqrt(s)).
    pub gyro_arw_rad_per_sqrt_s: f64,
    /// Gyro bias instability: stationary std of a first-order Gauss-Markov bias (rad/s).
    pub gyro_bias_instability_radps: f64,
    /// Correlation time of the gyro Gauss-Markov bias (s); infinite means random constant.
    pub gyro_bias_correlation_s: f64,
    /// Laser-gyro output quantum (rad per pulse); 0 disables quantization.
    pub gyro_quantum_rad: f64,
    /// Accelerometer velocity random walk (m/s/sqrt(s)).
    pub accel_vrw_mps_per_sqrt_s: f64,
    /// Accelerometer bias instability: stationary std of a Gauss-Markov bias (m/s^2).
    pub accel_bias_instability_mps2: f64,
    /// Correlation time of the accelerometer Gauss-Markov bias (s).
    pub accel_bias_correlation_s: f64,
}

/// Everything needed to simulate one dataset.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Short name (used for file names).
    pub name: String,
    /// Free description written to the dataset metadata.
    pub description: String,
    /// Fixed turntable site (the IMU centre does not translate).
    pub site: Geodetic,
    /// Output sample rate (Hz).
    pub rate_hz: f64,
    /// Gauss-Legendre nodes per sample interval for the increment integrals (1..=8).
    pub quadrature_nodes: usize,
    /// Motion program.
    pub motion: MotionProgram,
    /// Thermal model.
    pub thermal: ThermalModel,
    /// Sensor noise.
    pub noise: NoiseModel,
    /// Truth IMU error coefficients.
    pub truth: ImuErrorParams,
    /// Effects outside the paper's model, applied after eqs (1)-(2) in this order.
    pub effects: Vec<EffectSpec>,
    /// Random seed (noise, thermometers).
    pub seed: u64,
    /// Write reference (truth) attitude, velocity and position columns.
    pub with_reference: bool,
}

#[cfg(test)]
mod chamber_tests {
    use super::ChamberSegment;

    #[test]
    fn trend_change_is_rate_times_duration_and_zero_for_a_hold() {
        let ramp = ChamberSegment::Ramp {
            duration_s: 3600.0,
            rate_degc_per_s: -2.0 / 3600.0,
        };
        let fluct = ChamberSegment::Fluctuating {
            duration_s: 1800.0,
            rate_degc_per_s: 1.0 / 3600.0,
            fluctuation_amplitude_degc: 0.7,
            fluctuation_period_s: 600.0,
        };
        let hold = ChamberSegment::Hold {
            duration_s: 100.0,
            temp_degc: 40.0,
        };
        assert!((ramp.trend_change_degc() + 2.0).abs() < 1e-12);
        assert!((fluct.trend_change_degc() - 0.5).abs() < 1e-12);
        assert_eq!(hold.trend_change_degc(), 0.0);
    }
}
