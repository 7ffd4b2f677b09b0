//! Settings of the calibration filter (all SI).

use sins_imu::{ImuErrorParams, ParamModel};
use sins_nav::alignment::AlignmentConfig;
use sins_nav::{ARCSEC, DEG_PER_H, Geodetic, UG};

/// Sensor noise the filter assumes (its process noise).
///
/// Bias instability is modelled as in the simulator: a first-order Gauss-Markov wander of
/// stationary 1-sigma σ and correlation time τ on top of the constant bias. With a finite τ the
/// filter carries three extra nuisance states per sensor triad for it (beside the 30/42 states
/// of eq (8), which keep their meaning: the constant coefficients); the biases of eq (8) are
/// then the long-term means. A random walk instead would make a slow bias change look like a
/// temperature ramp and leave TB_a nearly unobservable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterNoise {
    /// Gyro angle random walk (rad/sqrt(s)); white rate noise into the attitude errors.
    pub gyro_arw_rad_per_sqrt_s: f64,
    /// Accelerometer velocity random walk (m/s/sqrt(s)); white noise into the velocity errors.
    pub accel_vrw_mps_per_sqrt_s: f64,
    /// Stationary 1-sigma of the gyro bias wander (rad/s); 0 = none.
    pub gyro_bias_wander_radps: f64,
    /// Correlation time of the gyro bias wander (s); infinite = part of the constant bias.
    pub gyro_bias_correlation_s: f64,
    /// Stationary 1-sigma of the accelerometer bias wander (m/s^2); 0 = none.
    pub accel_bias_wander_mps2: f64,
    /// Correlation time of the accelerometer bias wander (s); infinite = constant.
    pub accel_bias_correlation_s: f64,
}

impl FilterNoise {
    /// No sensor noise and constant coefficients (for noise-free data). The filter still adds
    /// its small numerical floor ([`crate::ARW_FLOOR_RAD_PER_SQRT_S`]).
    pub fn none() -> Self {
        Self {
            gyro_arw_rad_per_sqrt_s: 0.0,
            accel_vrw_mps_per_sqrt_s: 0.0,
            gyro_bias_wander_radps: 0.0,
            gyro_bias_correlation_s: f64::INFINITY,
            accel_bias_wander_mps2: 0.0,
            accel_bias_correlation_s: f64::INFINITY,
        }
    }

    /// Filter noise matching a sensor with white noise `gyro_arw` (rad/sqrt(s)) and
    /// `accel_vrw` (m/s/sqrt(s)) and Gauss-Markov biases of stationary 1-sigma
    /// `gyro_gm_sigma` (rad/s) / `accel_gm_sigma` (m/s^2) with correlation times (s).
    pub fn from_sensor(
        gyro_arw: f64,
        gyro_gm_sigma: f64,
        gyro_gm_tau_s: f64,
        accel_vrw: f64,
        accel_gm_sigma: f64,
        accel_gm_tau_s: f64,
    ) -> Self {
        Self {
            gyro_arw_rad_per_sqrt_s: gyro_arw,
            accel_vrw_mps_per_sqrt_s: accel_vrw,
            gyro_bias_wander_radps: gyro_gm_sigma,
            gyro_bias_correlation_s: gyro_gm_tau_s,
            accel_bias_wander_mps2: accel_gm_sigma,
            accel_bias_correlation_s: accel_gm_tau_s,
        }
    }

    /// The modelled wander triads: `(first coefficient index (0 gyro, 3 accel), σ, τ)` for each
    /// triad with σ > 0 and a finite τ.
    pub(crate) fn wander_triads(&self) -> Vec<(usize, f64, f64)> {
        [
            (0, self.gyro_bias_wander_radps, self.gyro_bias_correlation_s),
            (
                3,
                self.accel_bias_wander_mps2,
                self.accel_bias_correlation_s,
            ),
        ]
        .into_iter()
        .filter(|&(_, s, t)| s > 0.0 && t.is_finite())
        .collect()
    }
}

/// 1-sigma of the measurements (eqs 9-11): navigation velocity against zero and position
/// against the known site.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasurementNoise {
    /// Velocity measurement 1-sigma (m/s), each NED axis.
    pub velocity_mps: f64,
    /// Position measurement 1-sigma (m), north, east and down.
    pub position_m: f64,
}

impl Default for MeasurementNoise {
    /// 0.1 mm/s and 1 mm: the turntable centre does not move; these only keep the update regular.
    fn default() -> Self {
        Self {
            velocity_mps: 1e-4,
            position_m: 1e-3,
        }
    }
}

/// Initial 1-sigma of every state at the start of the filter (after the alignment).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialSigmas {
    /// Level attitude errors φ_N, φ_E (rad).
    pub level_rad: f64,
    /// Heading error φ_D (rad).
    pub heading_rad: f64,
    /// Velocity errors (m/s).
    pub velocity_mps: f64,
    /// Position errors (m, converted to δL, δλ at the site).
    pub position_m: f64,
    /// 1-sigma of each coefficient around the initial estimate (SI, same layout as the estimate).
    pub params: ImuErrorParams,
}

impl InitialSigmas {
    /// Generous priors for an uncalibrated navigation-grade IMU: level 100 arcsec, heading
    /// 10 arcmin, 1 mm/s, 0.1 m; gyro drift 0.02 deg/h, scale 100 ppm, installation 100 arcsec;
    /// accelerometer bias 100 ug, scale 100 ppm, installation 100 arcsec; TB 10 ug/degC,
    /// TK 20 ppm/degC, TM 1 arcsec/degC (temperature terms only for the 42-state model).
    pub fn generous(model: ParamModel) -> Self {
        let mut p = ImuErrorParams::ideal(model);
        p.gyro.bias_radps.fill(0.02 * DEG_PER_H);
        p.gyro.scale.fill(100e-6);
        p.gyro.misalignment_rad = [100.0 * ARCSEC; 3];
        p.accel.bias_mps2.fill(100.0 * UG);
        p.accel.scale.fill(100e-6);
        p.accel.misalignment_rad = [100.0 * ARCSEC; 6];
        if model == ParamModel::States42 {
            p.temperature.bias_mps2_per_degc.fill(10.0 * UG);
            p.temperature.scale_per_degc.fill(20e-6);
            p.temperature.misalignment_rad_per_degc = [ARCSEC; 6];
        }
        Self {
            level_rad: 100.0 * ARCSEC,
            heading_rad: 600.0 * ARCSEC,
            velocity_mps: 1e-3,
            position_m: 0.1,
            params: p,
        }
    }
}

/// When to refuse a dataset as not a turntable run. A horizontal velocity innovation above the
/// limit is far beyond what sensor noise and coefficient errors make in one update; such an
/// update is not used (the motion is not absorbed into attitude and coefficients), and when
/// it persists the data are refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionCheck {
    /// Limit of the horizontal velocity innovation (m/s per update).
    pub max_horizontal_innovation_mps: f64,
    /// How long (s) the limit may be exceeded in a row before the data are refused.
    pub max_duration_s: f64,
}

impl Default for MotionCheck {
    /// 0.05 m/s for 3 s. With 1 s updates, coefficient errors of 1000 ppm or 1000 arcsec during
    /// a 9 deg/s turn make about 0.015 m/s; on the paper's run the largest innovation is 5e-4 m/s
    /// (noisy, 42 states) and 0.02 m/s for the 30-state filter on 42-state data; a vehicle
    /// accelerating at 0.1 m/s² adds 0.1 m/s per update.
    fn default() -> Self {
        Self {
            max_horizontal_innovation_mps: 0.05,
            max_duration_s: 3.0,
        }
    }
}

/// Everything the calibration filter needs besides the data and the initial estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CalibrationConfig {
    /// 30- or 42-state filter.
    pub model: ParamModel,
    /// Sample interval of the data (s), e.g. 0.005.
    pub sample_interval_s: f64,
    /// The known turntable site.
    pub site: Geodetic,
    /// Kalman measurement-update interval (s); rounded to whole navigation updates.
    pub update_interval_s: f64,
    /// Interval of the convergence-history snapshots (s); rounded to whole updates.
    pub snapshot_interval_s: f64,
    /// The stationary self-alignment before the filter (the paper: 20 min).
    pub alignment: AlignmentConfig,
    /// Process noise.
    pub noise: FilterNoise,
    /// Measurement noise.
    pub measurement: MeasurementNoise,
    /// Initial state uncertainty.
    pub initial_sigma: InitialSigmas,
    /// Non-turntable detection.
    pub motion_check: MotionCheck,
    /// Ratio final/initial σ above which a state counts as not excited by the scheme.
    pub weak_ratio: f64,
}

impl CalibrationConfig {
    /// Defaults for `model` at `site` with samples every `sample_interval_s`: 1 s updates, 10 s
    /// snapshots, 20 min alignment, no process noise (set [`Self::noise`] for
    /// real data), [`MeasurementNoise::default`], [`InitialSigmas::generous`].
    pub fn new(model: ParamModel, sample_interval_s: f64, site: Geodetic) -> Self {
        Self {
            model,
            sample_interval_s,
            site,
            update_interval_s: 1.0,
            snapshot_interval_s: 10.0,
            alignment: AlignmentConfig::default(),
            noise: FilterNoise::none(),
            measurement: MeasurementNoise::default(),
            initial_sigma: InitialSigmas::generous(model),
            motion_check: MotionCheck::default(),
            weak_ratio: 0.5,
        }
    }
}

fn bad(field: &'static str, reason: String) -> crate::CalibrationError {
    crate::CalibrationError::Config { field, reason }
}

fn positive(field: &'static str, v: f64) -> Result<(), crate::CalibrationError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(bad(field, format!("must be finite and positive, got {v}")))
    }
}

fn non_negative(field: &'static str, v: f64) -> Result<(), crate::CalibrationError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(bad(field, format!("must be finite and >= 0, got {v}")))
    }
}

impl CalibrationConfig {
    /// Samples per measurement update: `update_interval_s` rounded to whole two-sample
    /// navigation updates (at least one).
    pub fn samples_per_update(&self) -> usize {
        ((self.update_interval_s / self.sample_interval_s).round() as usize / 2).max(1) * 2
    }

    /// Check every setting; the filter calls this before it starts.
    pub fn validate(&self) -> Result<(), crate::CalibrationError> {
        positive("sample_interval_s", self.sample_interval_s)?;
        positive("update_interval_s", self.update_interval_s)?;
        positive("snapshot_interval_s", self.snapshot_interval_s)?;
        let lat = self.site.lat_rad;
        if !(lat.is_finite() && lat.abs() <= 89f64.to_radians()) {
            return Err(bad(
                "site.lat_rad",
                format!("must be within ±89 deg, got {lat} rad"),
            ));
        }
        non_negative("site.lon_rad", self.site.lon_rad.abs())?;
        non_negative("site.height_m", self.site.height_m.abs())?;
        positive("alignment.duration_s", self.alignment.duration_s)?;
        positive(
            "alignment.coarse_duration_s",
            self.alignment.coarse_duration_s,
        )?;
        if self.alignment.coarse_duration_s >= self.alignment.duration_s {
            return Err(bad(
                "alignment.coarse_duration_s",
                "must be shorter than alignment.duration_s".into(),
            ));
        }
        let n = &self.noise;
        non_negative("noise.gyro_arw_rad_per_sqrt_s", n.gyro_arw_rad_per_sqrt_s)?;
        non_negative("noise.accel_vrw_mps_per_sqrt_s", n.accel_vrw_mps_per_sqrt_s)?;
        non_negative("noise.gyro_bias_wander_radps", n.gyro_bias_wander_radps)?;
        non_negative("noise.accel_bias_wander_mps2", n.accel_bias_wander_mps2)?;
        for (field, tau) in [
            ("noise.gyro_bias_correlation_s", n.gyro_bias_correlation_s),
            ("noise.accel_bias_correlation_s", n.accel_bias_correlation_s),
        ] {
            if tau.is_nan() || tau <= 0.0 {
                return Err(bad(
                    field,
                    format!("must be positive or infinite, got {tau}"),
                ));
            }
        }
        positive("measurement.velocity_mps", self.measurement.velocity_mps)?;
        positive("measurement.position_m", self.measurement.position_m)?;
        let s = &self.initial_sigma;
        positive("initial_sigma.level_rad", s.level_rad)?;
        positive("initial_sigma.heading_rad", s.heading_rad)?;
        positive("initial_sigma.velocity_mps", s.velocity_mps)?;
        positive("initial_sigma.position_m", s.position_m)?;
        for (k, v) in crate::states::params_to_vec(&s.params, self.model)
            .into_iter()
            .enumerate()
        {
            if !(v.is_finite() && v > 0.0) {
                let name = crate::states::STATE_NAMES[crate::states::NAV_STATES + k];
                return Err(bad(
                    "initial_sigma.params",
                    format!("{name} must be > 0, got {v}"),
                ));
            }
        }
        positive(
            "motion_check.max_horizontal_innovation_mps",
            self.motion_check.max_horizontal_innovation_mps,
        )?;
        non_negative(
            "motion_check.max_duration_s",
            self.motion_check.max_duration_s,
        )?;
        positive("weak_ratio", self.weak_ratio)
    }
}
