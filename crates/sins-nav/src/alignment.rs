//! Stationary self-alignment: coarse analytic alignment (TRIAD on gravity and Earth rate from
//! averaged increments) followed by fine alignment with a zero-velocity Kalman filter whose
//! attitude and velocity estimates are fed back into the running strapdown solution.
//!
//! The filter has five states `[φ_N, φ_E, φ_D, δv_N, δv_E]` and no sensor-bias states, so the
//! unobservable combinations settle where classical gyrocompassing puts them: horizontal
//! accelerometer biases are absorbed by level errors and the east gyro bias by a heading error,
//! which is what makes them harmless afterwards. Its matrices ([`FineFilterModel`]) come from
//! the reduced model [`crate::error_model::AlignmentModel`]; `sins-diag`'s linear replica of the
//! alignment uses the same [`FineFilterModel`], so the two cannot drift apart.

use crate::earth::Geodetic;
use crate::error_model::AlignmentModel;
use crate::mechanization::{Increment, NavState, Strapdown, StrapdownConfig, VerticalChannel};
use crate::{Mat3, Quat, Vec3};
use nalgebra::{Matrix2, Matrix2x5, Matrix5, Matrix5x2, Rotation3, Vector2, Vector5};

/// Self-alignment settings (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlignmentConfig {
    /// Total alignment time (s), coarse plus fine; the paper uses 20 min.
    pub duration_s: f64,
    /// Part of it used for coarse alignment (s).
    pub coarse_duration_s: f64,
    /// Kalman update interval (s).
    pub update_interval_s: f64,
    /// Gyro angle random walk assumed by the filter (rad/sqrt(s)).
    pub gyro_arw_rad_per_sqrt_s: f64,
    /// Accelerometer velocity random walk assumed by the filter (m/s/sqrt(s)).
    pub accel_vrw_mps_per_sqrt_s: f64,
    /// 1-sigma of the zero-velocity measurement (m/s).
    pub velocity_sigma_mps: f64,
    /// Initial 1-sigma of the level errors after coarse alignment (rad).
    pub initial_level_sigma_rad: f64,
    /// Initial 1-sigma of the heading error after coarse alignment (rad).
    pub initial_heading_sigma_rad: f64,
}

impl Default for AlignmentConfig {
    /// 20 min in all (1 min coarse), 0.1 s updates, noise of a navigation-grade laser-gyro IMU.
    fn default() -> Self {
        Self {
            duration_s: 1200.0,
            coarse_duration_s: 60.0,
            update_interval_s: 0.1,
            gyro_arw_rad_per_sqrt_s: 0.0005 * crate::DEG / 60.0,
            accel_vrw_mps_per_sqrt_s: 10.0 * crate::UG,
            velocity_sigma_mps: 1e-3,
            initial_level_sigma_rad: 0.1 * crate::DEG,
            initial_heading_sigma_rad: 3.0 * crate::DEG,
        }
    }
}

/// Outcome of an alignment.
#[derive(Clone, Copy, Debug)]
pub struct AlignmentResult {
    /// State at the end of alignment: aligned attitude, zero velocity, the known site.
    pub state: NavState,
    /// Attitude from the coarse (analytic) stage alone.
    pub coarse_ned_from_body: Quat,
    /// Final filter 1-sigma of `[φ_N, φ_E, φ_D]` (rad).
    pub attitude_sigma_rad: Vec3,
}

/// Errors of the alignment stage.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum AlignmentError {
    /// The data ended before the configured alignment time was complete (times rounded to a
    /// microsecond, so that one missing sample shows).
    #[error("alignment needs {needed_s} s of data but the data end after {got_s} s")]
    TooShort {
        /// Required (s).
        needed_s: f64,
        /// Received (s).
        got_s: f64,
    },
    /// The alignment time is shorter than its coarse (analytic) stage, so the alignment could
    /// never complete: the total time must cover the coarse stage.
    #[error(
        "an alignment time of {duration_s} s is shorter than the {coarse_s} s of coarse alignment \
         it starts with; use an alignment time of at least {coarse_s} s"
    )]
    ShorterThanCoarse {
        /// Configured total alignment time (s).
        duration_s: f64,
        /// Coarse stage (s), rounded to whole samples and coning updates.
        coarse_s: f64,
    },
    /// The averaged specific force or Earth rate cannot define an attitude.
    #[error("coarse alignment failed: {0}")]
    Degenerate(&'static str),
}

/// `x` rounded to a millionth (for messages: 12000 samples of 0.005 s are 60 s, not
/// 60.00000000000001 s).
fn micro_round(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

/// Analytic (TRIAD) attitude from mean specific force `f_body_mps2` and mean angular rate
/// `w_body_radps` of a stationary IMU at latitude `lat_rad`.
pub fn coarse_align(f_body_mps2: &Vec3, w_body_radps: &Vec3) -> Result<Quat, AlignmentError> {
    if f_body_mps2.norm() < 1.0 {
        return Err(AlignmentError::Degenerate(
            "mean specific force is far from 1 g",
        ));
    }
    let down = -f_body_mps2.normalize();
    let east = down.cross(w_body_radps);
    if east.norm() < 1e-3 * w_body_radps.norm().max(1e-12) || w_body_radps.norm() < 1e-6 {
        return Err(AlignmentError::Degenerate(
            "Earth rate not measurable (at a pole or no rate)",
        ));
    }
    let east = east.normalize();
    let north = east.cross(&down);
    let body_from_ned = Mat3::from_columns(&[north, east, down]);
    let ned_from_body = body_from_ned.transpose();
    Ok(Quat::from_rotation_matrix(
        &Rotation3::from_matrix_unchecked(ned_from_body),
    ))
}

/// Streaming self-alignment: feed samples with [`SelfAlignment::push`] until it returns true,
/// then take the result with [`SelfAlignment::finish`].
pub struct SelfAlignment {
    config: AlignmentConfig,
    nav_config: StrapdownConfig,
    site: Geodetic,
    t0_s: f64,
    n_coarse: usize,
    n_total: usize,
    n_seen: usize,
    sum_dtheta: Vec3,
    sum_dv: Vec3,
    coarse: Option<Quat>,
    fine: Option<FineFilter>,
}

struct FineFilter {
    nav: Strapdown,
    x: Vector5<f64>,
    p: Matrix5<f64>,
    model: FineFilterModel,
    samples_per_update: usize,
    since_update: usize,
}

/// Floor of the gyro angle random walk the fine filter assumes (rad/sqrt(s)), so that `Q` stays
/// positive definite for an ideal IMU.
const MIN_GYRO_ARW_RAD_PER_SQRT_S: f64 = 1e-12;
/// Floor of the accelerometer velocity random walk the fine filter assumes (m/s/sqrt(s)).
const MIN_ACCEL_VRW_MPS_PER_SQRT_S: f64 = 1e-10;

/// The fine alignment filter's matrices over one update interval, built from
/// [`AlignmentModel`] (states `[φ_N, φ_E, φ_D, δv_N, δv_E]`, rad and m/s) and the settings of an
/// [`AlignmentConfig`]. The filter and any replica of it take them from here.
#[derive(Clone, Debug, PartialEq)]
pub struct FineFilterModel {
    /// Transition `Φ` over one update interval.
    pub phi: Matrix5<f64>,
    /// Process noise `Q` over one update interval (rad², m²/s²).
    pub q: Matrix5<f64>,
    /// Zero-velocity measurement matrix `H` (picks `δv_N`, `δv_E`).
    pub h: Matrix2x5<f64>,
    /// Measurement noise `R` of the zero-velocity update (m²/s²).
    pub r: Matrix2<f64>,
    /// Covariance `P0` at the start of the fine stage (rad², m²/s²).
    pub p0: Matrix5<f64>,
}

impl FineFilterModel {
    /// The fine filter of `config` at `site` (update interval `config.update_interval_s`).
    pub fn new(config: &AlignmentConfig, site: &Geodetic) -> Self {
        let model = AlignmentModel::new(site.lat_rad, site.height_m);
        let dt_s = config.update_interval_s;
        let arw = config
            .gyro_arw_rad_per_sqrt_s
            .max(MIN_GYRO_ARW_RAD_PER_SQRT_S);
        let vrw = config
            .accel_vrw_mps_per_sqrt_s
            .max(MIN_ACCEL_VRW_MPS_PER_SQRT_S);
        Self {
            phi: model.transition(dt_s),
            q: AlignmentModel::process_noise(dt_s, arw.powi(2), vrw.powi(2)),
            h: AlignmentModel::h(),
            r: AlignmentModel::r(config.velocity_sigma_mps),
            p0: AlignmentModel::initial_covariance(
                config.initial_level_sigma_rad,
                config.initial_heading_sigma_rad,
            ),
        }
    }

    /// One covariance step of the filter on `p`: predict `P ← Φ P Φᵀ + Q`, then the
    /// zero-velocity update in Joseph form. Returns the gain `K` (5x2, rad per m/s and
    /// dimensionless), or `None` with `p` left predicted when the innovation covariance is
    /// singular. The covariance recursion does not depend on the measurements.
    pub fn covariance_step(&self, p: &mut Matrix5<f64>) -> Option<Matrix5x2<f64>> {
        *p = self.phi * *p * self.phi.transpose() + self.q;
        let s = self.h * *p * self.h.transpose() + self.r;
        let s_inv = s.try_inverse()?;
        let k: Matrix5x2<f64> = *p * self.h.transpose() * s_inv;
        let ikh = Matrix5::identity() - k * self.h;
        *p = ikh * *p * ikh.transpose() + k * self.r * k.transpose();
        Some(k)
    }
}

impl SelfAlignment {
    /// Alignment at the known `site` starting at time `t0_s`. `nav_config` gives the sample
    /// interval and coning algorithm; the vertical channel is held at the site height.
    pub fn new(
        config: AlignmentConfig,
        nav_config: StrapdownConfig,
        site: Geodetic,
        t0_s: f64,
    ) -> Self {
        let h = nav_config.sample_interval_s;
        let per = nav_config.coning.samples_per_update();
        let round_to = |d: f64| (((d / h).round() as usize) / per) * per;
        Self {
            config,
            nav_config: StrapdownConfig {
                vertical: VerticalChannel::Hold {
                    height_m: site.height_m,
                },
                ..nav_config
            },
            site,
            t0_s,
            n_coarse: round_to(config.coarse_duration_s).max(per),
            n_total: round_to(config.duration_s),
            n_seen: 0,
            sum_dtheta: Vec3::zeros(),
            sum_dv: Vec3::zeros(),
            coarse: None,
            fine: None,
        }
    }

    /// Samples the alignment consumes in all.
    pub fn total_samples(&self) -> usize {
        self.n_total
    }

    /// Add one compensated sample; returns true once the alignment time is complete. Fails with
    /// [`AlignmentError::ShorterThanCoarse`] at the first sample when the alignment time does
    /// not cover the coarse stage (it could never complete).
    pub fn push(&mut self, inc: &Increment) -> Result<bool, AlignmentError> {
        if self.n_total < self.n_coarse {
            let h = self.nav_config.sample_interval_s;
            return Err(AlignmentError::ShorterThanCoarse {
                duration_s: self.config.duration_s,
                coarse_s: micro_round(self.n_coarse as f64 * h),
            });
        }
        if self.n_seen >= self.n_total {
            return Ok(true);
        }
        self.n_seen += 1;
        if self.n_seen <= self.n_coarse {
            self.sum_dtheta += inc.dtheta_rad;
            self.sum_dv += inc.dv_mps;
            if self.n_seen == self.n_coarse {
                self.start_fine()?;
            }
        } else if let Some(f) = self.fine.as_mut() {
            f.step(inc, &self.site);
        }
        Ok(self.n_seen >= self.n_total)
    }

    fn start_fine(&mut self) -> Result<(), AlignmentError> {
        let dur = self.n_coarse as f64 * self.nav_config.sample_interval_s;
        let q = coarse_align(&(self.sum_dv / dur), &(self.sum_dtheta / dur))?;
        self.coarse = Some(q);
        let model = FineFilterModel::new(&self.config, &self.site);
        let dt = self.config.update_interval_s;
        let per = self.nav_config.coning.samples_per_update();
        let spu = ((dt / self.nav_config.sample_interval_s).round() as usize).max(per) / per * per;
        let state = NavState::at_rest(self.t0_s + dur, q, self.site);
        self.fine = Some(FineFilter {
            nav: Strapdown::new(self.nav_config, state),
            x: Vector5::zeros(),
            p: model.p0,
            model,
            samples_per_update: spu,
            since_update: 0,
        });
        Ok(())
    }

    /// Result of a completed alignment.
    pub fn finish(&self) -> Result<AlignmentResult, AlignmentError> {
        let h = self.nav_config.sample_interval_s;
        let (Some(coarse), Some(fine), true) =
            (self.coarse, self.fine.as_ref(), self.n_seen >= self.n_total)
        else {
            if self.n_total < self.n_coarse {
                return Err(AlignmentError::ShorterThanCoarse {
                    duration_s: self.config.duration_s,
                    coarse_s: micro_round(self.n_coarse as f64 * h),
                });
            }
            return Err(AlignmentError::TooShort {
                needed_s: micro_round(self.n_total as f64 * h),
                got_s: micro_round(self.n_seen as f64 * h),
            });
        };
        let mut state = *fine.nav.state();
        state.vel_ned_mps = Vec3::zeros();
        state.position = self.site;
        state.t_s = self.t0_s + self.n_total as f64 * h;
        let sig = Vec3::new(
            fine.p[(0, 0)].sqrt(),
            fine.p[(1, 1)].sqrt(),
            fine.p[(2, 2)].sqrt(),
        );
        Ok(AlignmentResult {
            state,
            coarse_ned_from_body: coarse,
            attitude_sigma_rad: sig,
        })
    }
}

impl FineFilter {
    fn step(&mut self, inc: &Increment, site: &Geodetic) {
        if !self.nav.push(inc) {
            return;
        }
        self.since_update += self.nav.config().coning.samples_per_update();
        if self.since_update < self.samples_per_update {
            return;
        }
        self.since_update = 0;
        // Predict, then update on the zero horizontal velocity.
        self.x = self.model.phi * self.x;
        let Some(k) = self.model.covariance_step(&mut self.p) else {
            return;
        };
        let v = self.nav.state().vel_ned_mps;
        let z = Vector2::new(v.x, v.y);
        self.x += k * (z - self.model.h * self.x);
        // Feed back and reset the error states.
        let phi = Vec3::new(self.x[0], self.x[1], self.x[2]);
        let dv = Vec3::new(self.x[3], self.x[4], 0.0);
        self.nav.correct(&phi, &dv, None);
        self.nav.state_mut().position = *site;
        self.x = Vector5::zeros();
    }
}
