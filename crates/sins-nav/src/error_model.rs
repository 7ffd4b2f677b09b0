//! The linearised navigation error model of sinsbench: attitude, velocity and position errors of
//! a strapdown INS at a site, written once. The calibration filter (`sins-kf`), the gap
//! diagnosis (`sins-diag`) and the fine alignment ([`crate::alignment`]) all take their
//! matrices from here; [`crate::linear`] is deliberately kept separate, as the independent
//! oracle this module is tested against.
//!
//! # States and conventions
//!
//! The full model has nine states, in this order ([`PHI`], [`VEL`], [`POS`]):
//! `x = [φ_N, φ_E, φ_D, δv_N, δv_E, δv_D, δL, δλ, δh]` (rad, m/s, rad, m). Frames are NED;
//! the attitude error φ is defined by `C_est = (I − [φ×]) C_true` (so `C_est = ned_from_body`
//! as computed), and every error is estimate − truth. At latitude `L`, height `h`, NED velocity
//! `v` and NED specific force `f^n`:
//!
//! ```text
//! φ̇  = −ω_in × φ + δω_in − C_b^n δω^b                         ω_in = ω_ie + ω_en
//! δv̇ = f^n × φ − (2ω_ie + ω_en) × δv + v × (2δω_ie + δω_en) + δg + C_b^n δf^b
//! δL̇ = δv_N/(R_M+h) − v_N δh/(R_M+h)²
//! δλ̇ = δv_E/((R_N+h) cos L) + v_E tan L δL/((R_N+h) cos L) − v_E δh/((R_N+h)² cos L)
//! δḣ = −δv_D
//! ```
//!
//! with `δω_ie = [−Ω sin L δL, 0, −Ω cos L δL]`, `δω_en` the derivative of the transport rate
//! `[v_E/(R_N+h), −v_N/(R_M+h), −v_E tan L/(R_N+h)]` with respect to `δv`, `δL`, `δh`, and
//! `δg = (∂g/∂h) δh` down (free vertical channel). The sensor errors `δω^b` (gyro, rad/s) and
//! `δf^b` (accelerometer, m/s²), positive when the indicated value exceeds the true one, enter
//! through the input matrix `G` ([`input_matrix`]).
//!
//! # Matrices
//!
//! Named as in Kalman filter texts (and `adskalman`): `F` the continuous dynamics
//! ([`f_matrix`]), `Φ = e^{F Δt}` the transition over `Δt` ([`transition`]), `Q` the discrete
//! process noise of white gyro and accelerometer noise ([`process_noise`]), `H` and `R` the
//! zero-velocity measurement of the alignment ([`AlignmentModel::h`], [`AlignmentModel::r`]).
//!
//! # Projections
//!
//! Two reduced models are projections of `F` at rest (`v = 0`, `f^n = [0, 0, −g]`):
//!
//! - [`StaticModel`], seven states `[φ_N, φ_E, φ_D, δv_N, δv_E, δr_N, δr_E]` with the vertical
//!   channel held (`δv_D`, `δh` dropped: the replays hold the height at the site) and the
//!   horizontal position errors in metres, `δr_N = (R_M+h) δL`, `δr_E = (R_N+h) cos L δλ`. It is
//!   the model the gap diagnosis propagates.
//! - [`AlignmentModel`], five states `[φ_N, φ_E, φ_D, δv_N, δv_E]`: the stationary fine
//!   alignment's zero-velocity Kalman filter. Position errors are dropped because the
//!   alignment resets the position to the known site after every update, `δv_D` because it
//!   holds the vertical channel; the transport-rate coupling of velocity into attitude
//!   (`∂δω_en/∂δv`, 1/R ≈ 1.6e-7 rad/s per m/s) is left out as in classical gyrocompassing,
//!   since the zero-velocity updates keep `δv` at the mm/s level.

use crate::attitude::skew;
use crate::earth::{EarthAt, normal_gravity_mps2};
use crate::{Mat3, Vec3, Wgs84};
use nalgebra::{Matrix2, Matrix2x5, Matrix5, SMatrix, SVector, Vector5};

/// Number of states of the full model: `φ_N, φ_E, φ_D, δv_N, δv_E, δv_D, δL, δλ, δh`.
pub const NAV_STATES: usize = 9;
/// Index of `φ_N` (attitude errors, rad, occupy 0..3).
pub const PHI: usize = 0;
/// Index of `δv_N` (velocity errors, m/s, occupy 3..6).
pub const VEL: usize = 3;
/// Index of `δL` (position errors `δL` (rad), `δλ` (rad), `δh` (m) occupy 6..9).
pub const POS: usize = 6;

/// Sign with which a gyro error `δω^b` (rad/s, or an angle increment in rad) enters `φ̇`.
pub const GYRO_INPUT_SIGN: f64 = -1.0;
/// Sign with which an accelerometer error `δf^b` (m/s², or a velocity increment in m/s) enters
/// `δv̇`.
pub const ACCEL_INPUT_SIGN: f64 = 1.0;

/// 9x9 matrix of the full model (`F`, `Φ`, `Q`; units of row state over column state).
pub type Mat9 = SMatrix<f64, NAV_STATES, NAV_STATES>;
/// Input matrix `G` of the full model: 9 states by `[δω^b (3, rad/s), δf^b (3, m/s²)]`.
pub type InputMatrix = SMatrix<f64, NAV_STATES, 6>;

/// Columns of the rate-error Jacobians: `δv_N, δv_E, δv_D, δL, δh`.
type RateJacobian = SMatrix<f64, 3, 5>;

/// Continuous dynamics `F` of the full model at latitude `lat_rad`, height `height_m`, NED
/// velocity `vel_ned_mps` (m/s) and NED specific force `f_ned_mps2` (m/s²), free vertical
/// channel (gravity gradient included). Units: row state per second over column state.
pub fn f_matrix(lat_rad: f64, height_m: f64, vel_ned_mps: &Vec3, f_ned_mps2: &Vec3) -> Mat9 {
    let e = EarthAt::new(lat_rad, height_m);
    let w_ie = e.earth_rate_ned_radps;
    let w_en = e.transport_rate_ned_radps(vel_ned_mps);
    let (d_ie, d_en) = rate_error_jacobians(&e, vel_ned_mps);
    let mut f = Mat9::zeros();
    // Attitude: φ̇ = −ω_in × φ + δω_in.
    put3(&mut f, PHI, PHI, &(-skew(&(w_ie + w_en))));
    // Velocity: δV̇ = f^n × φ − (2ω_ie + ω_en) × δV + V × (2δω_ie + δω_en) + δg.
    put3(&mut f, VEL, PHI, &skew(f_ned_mps2));
    put3(&mut f, VEL, VEL, &(-skew(&(2.0 * w_ie + w_en))));
    let d_in = d_ie + d_en;
    let v_cross = skew(vel_ned_mps) * (2.0 * d_ie + d_en);
    for r in 0..3 {
        for (k, col) in [(0, VEL), (1, VEL + 1), (2, VEL + 2), (3, POS), (4, POS + 2)] {
            f[(PHI + r, col)] += d_in[(r, k)];
            f[(VEL + r, col)] += v_cross[(r, k)];
        }
    }
    f[(VEL + 2, POS + 2)] += gravity_gradient_per_s2(lat_rad, height_m);
    position_rows(&mut f, &e, vel_ned_mps);
    f
}

/// `F` at rest at latitude `lat_rad`, height `height_m`: zero velocity and the specific force
/// of a resting IMU, `f^n = [0, 0, −g]` (normal gravity, m/s²).
pub fn f_at_rest(lat_rad: f64, height_m: f64) -> Mat9 {
    let g = EarthAt::new(lat_rad, height_m).gravity_mps2;
    f_matrix(lat_rad, height_m, &Vec3::zeros(), &Vec3::new(0.0, 0.0, -g))
}

/// Transition `Φ = e^{F dt_s}` of the full model over `dt_s` seconds.
pub fn transition(f: &Mat9, dt_s: f64) -> Mat9 {
    (f * dt_s).exp()
}

/// Input matrix `G` for the attitude `ned_from_body`: `φ̇ += −C_b^n δω^b`, `δv̇ += C_b^n δf^b`
/// (signs [`GYRO_INPUT_SIGN`], [`ACCEL_INPUT_SIGN`]); the position rows are zero.
pub fn input_matrix(ned_from_body: &Mat3) -> InputMatrix {
    let mut g = InputMatrix::zeros();
    g.fixed_view_mut::<3, 3>(PHI, 0)
        .copy_from(&(ned_from_body * GYRO_INPUT_SIGN));
    g.fixed_view_mut::<3, 3>(VEL, 3)
        .copy_from(&(ned_from_body * ACCEL_INPUT_SIGN));
    g
}

/// Continuous noise density `Q_c` of white gyro noise (`gyro_psd_rad2_per_s`, rad²/s, the
/// angle random walk squared) into φ and white accelerometer noise (`accel_psd_m2_per_s3`,
/// m²/s³, the velocity random walk squared) into δv. Isotropic body noise stays isotropic in
/// NED whatever the attitude.
pub fn noise_density(gyro_psd_rad2_per_s: f64, accel_psd_m2_per_s3: f64) -> Mat9 {
    let mut qc = Mat9::zeros();
    for i in 0..3 {
        qc[(PHI + i, PHI + i)] = gyro_psd_rad2_per_s;
        qc[(VEL + i, VEL + i)] = accel_psd_m2_per_s3;
    }
    qc
}

/// Discrete process noise `Q = ∫_0^T e^{Fτ} Q_c e^{Fᵀτ} dτ` over `dt_s` of the noise densities
/// of [`noise_density`], to third order in `T` (exact for the nilpotent
/// attitude-velocity-position chain that dominates). Units: row state times column state.
pub fn process_noise(
    f: &Mat9,
    dt_s: f64,
    gyro_psd_rad2_per_s: f64,
    accel_psd_m2_per_s3: f64,
) -> Mat9 {
    let qc = noise_density(gyro_psd_rad2_per_s, accel_psd_m2_per_s3);
    let t = dt_s;
    let fq = f * qc;
    let q1 = qc * t;
    let q2 = (fq + fq.transpose()) * (t * t / 2.0);
    let ffq = f * fq;
    let q3 = (ffq + ffq.transpose() + 2.0 * fq * f.transpose()) * (t * t * t / 6.0);
    let q = q1 + q2 + q3;
    (q + q.transpose()) * 0.5
}

/// Copy the 3x3 block `m` into `f` at row `r`, column `c`.
fn put3(f: &mut Mat9, r: usize, c: usize, m: &Mat3) {
    f.fixed_view_mut::<3, 3>(r, c).copy_from(m);
}

/// `δω_ie` and `δω_en` (rad/s) as linear maps of `[δv_N, δv_E, δv_D, δL, δh]`.
fn rate_error_jacobians(e: &EarthAt, vel_ned_mps: &Vec3) -> (RateJacobian, RateJacobian) {
    let (sl, cl) = (e.sin_lat, e.cos_lat);
    let tl = sl / cl;
    let (rm, rn) = (e.meridian_plus_h_m, e.transverse_plus_h_m);
    let om = Wgs84::OMEGA_IE_RADPS;
    let (vn, ve) = (vel_ned_mps.x, vel_ned_mps.y);
    let mut d_ie = RateJacobian::zeros();
    d_ie[(0, 3)] = -om * sl;
    d_ie[(2, 3)] = -om * cl;
    let mut d_en = RateJacobian::zeros();
    d_en[(0, 1)] = 1.0 / rn;
    d_en[(0, 4)] = -ve / (rn * rn);
    d_en[(1, 0)] = -1.0 / rm;
    d_en[(1, 4)] = vn / (rm * rm);
    d_en[(2, 1)] = -tl / rn;
    d_en[(2, 3)] = -ve / (cl * cl * rn);
    d_en[(2, 4)] = ve * tl / (rn * rn);
    (d_ie, d_en)
}

/// `∂g/∂h` of normal gravity (1/s², negative: gravity weakens upwards), central difference
/// over ±1 m.
fn gravity_gradient_per_s2(lat_rad: f64, height_m: f64) -> f64 {
    0.5 * (normal_gravity_mps2(lat_rad, height_m + 1.0)
        - normal_gravity_mps2(lat_rad, height_m - 1.0))
}

/// The position rows `δL̇`, `δλ̇`, `δḣ` of `F`.
fn position_rows(f: &mut Mat9, e: &EarthAt, vel_ned_mps: &Vec3) {
    let (sl, cl) = (e.sin_lat, e.cos_lat);
    let tl = sl / cl;
    let (rm, rn) = (e.meridian_plus_h_m, e.transverse_plus_h_m);
    let (vn, ve) = (vel_ned_mps.x, vel_ned_mps.y);
    f[(POS, VEL)] = 1.0 / rm;
    f[(POS, POS + 2)] = -vn / (rm * rm);
    f[(POS + 1, VEL + 1)] = 1.0 / (rn * cl);
    f[(POS + 1, POS)] = ve * tl / (rn * cl);
    f[(POS + 1, POS + 2)] = -ve / (rn * rn * cl);
    f[(POS + 2, VEL + 2)] = -1.0;
}

/// Number of states of [`StaticModel`]: `φ_N, φ_E, φ_D, δv_N, δv_E, δr_N, δr_E`.
pub const STATIC_STATES: usize = 7;
/// Index of the north position error `δr_N` (m) in [`StaticModel`].
pub const STATIC_R_N: usize = 5;
/// Index of the east position error `δr_E` (m) in [`StaticModel`].
pub const STATIC_R_E: usize = 6;
/// State vector of [`StaticModel`] (rad, m/s, m).
pub type Vec7 = SVector<f64, STATIC_STATES>;
/// 7x7 matrix of [`StaticModel`].
pub type Mat7 = SMatrix<f64, STATIC_STATES, STATIC_STATES>;

/// The full model at rest with the vertical channel held and horizontal positions in metres:
/// states `[φ_N, φ_E, φ_D, δv_N, δv_E, δr_N, δr_E]` (rad, m/s, m). States 0..5 are the full
/// model's 0..5; `δv_D` and `δh` are dropped (held vertical channel). Its `F` is constant.
#[derive(Clone, Debug)]
pub struct StaticModel {
    /// Continuous dynamics `F` (1/s, with the position columns per metre).
    pub f: Mat7,
    /// Earth quantities at the site.
    pub earth: EarthAt,
}

impl StaticModel {
    /// Model at rest at latitude `lat_rad`, height `height_m`. The position columns are the full
    /// model's `δL`, `δλ` columns divided by `R_M+h` and `(R_N+h) cos L`; the position rows are
    /// the kinematic identity `δṙ_N = δv_N`, `δṙ_E = δv_E` (what `(R_M+h) δL̇` and
    /// `(R_N+h) cos L δλ̇` reduce to at rest), written exactly.
    pub fn new(lat_rad: f64, height_m: f64) -> Self {
        let full = f_at_rest(lat_rad, height_m);
        let earth = EarthAt::new(lat_rad, height_m);
        let east_m_per_rad = earth.transverse_plus_h_m * earth.cos_lat;
        let mut f = Mat7::zeros();
        for r in 0..STATIC_R_N {
            for c in 0..STATIC_R_N {
                f[(r, c)] = full[(r, c)];
            }
            f[(r, STATIC_R_N)] = full[(r, POS)] / earth.meridian_plus_h_m;
            f[(r, STATIC_R_E)] = full[(r, POS + 1)] / east_m_per_rad;
        }
        f[(STATIC_R_N, VEL)] = 1.0;
        f[(STATIC_R_E, VEL + 1)] = 1.0;
        Self { f, earth }
    }

    /// Transition `Φ = e^{F dt_s}` over `dt_s` seconds.
    pub fn transition(&self, dt_s: f64) -> Mat7 {
        (self.f * dt_s).exp()
    }

    /// Noise density `Q_c` of [`noise_density`] on the seven states (rad²/s into φ, m²/s³ into
    /// `δv_N`, `δv_E`).
    pub fn noise_density(gyro_psd_rad2_per_s: f64, accel_psd_m2_per_s3: f64) -> Mat7 {
        let full = noise_density(gyro_psd_rad2_per_s, accel_psd_m2_per_s3);
        Mat7::from_fn(|r, c| {
            if r < STATIC_R_N && c < STATIC_R_N {
                full[(r, c)]
            } else {
                0.0
            }
        })
    }

    /// Discrete process noise `Q` over `dt_s` of white gyro noise (`gyro_psd_rad2_per_s`,
    /// rad²/s) and accelerometer noise (`accel_psd_m2_per_s3`, m²/s³), exact by Van Loan's
    /// method.
    pub fn process_noise(
        &self,
        dt_s: f64,
        gyro_psd_rad2_per_s: f64,
        accel_psd_m2_per_s3: f64,
    ) -> Mat7 {
        const N: usize = STATIC_STATES;
        let qc = Self::noise_density(gyro_psd_rad2_per_s, accel_psd_m2_per_s3);
        let mut m = SMatrix::<f64, { 2 * N }, { 2 * N }>::zeros();
        m.fixed_view_mut::<N, N>(0, 0).copy_from(&(-self.f * dt_s));
        m.fixed_view_mut::<N, N>(0, N).copy_from(&(qc * dt_s));
        m.fixed_view_mut::<N, N>(N, N)
            .copy_from(&(self.f.transpose() * dt_s));
        let e = m.exp();
        let phi = e.fixed_view::<N, N>(N, N).transpose();
        let q = phi * e.fixed_view::<N, N>(0, N);
        (q + q.transpose()) * 0.5
    }
}

/// Number of states of [`AlignmentModel`]: `φ_N, φ_E, φ_D, δv_N, δv_E`.
pub const ALIGNMENT_STATES: usize = 5;
/// Initial variance of the horizontal velocity errors of the alignment filter (m²/s², i.e.
/// 1 cm/s 1-sigma).
pub const ALIGNMENT_INITIAL_VELOCITY_VAR_M2PS2: f64 = 1e-4;

/// The reduced model of the stationary fine alignment's zero-velocity Kalman filter: states
/// `[φ_N, φ_E, φ_D, δv_N, δv_E]` (rad, m/s), the full model's 0..5 at rest, with position
/// errors, `δv_D` and the transport-rate coupling `∂δω_en/∂δv` left out (see the module
/// documentation for why).
#[derive(Clone, Debug)]
pub struct AlignmentModel {
    /// Continuous dynamics `F` (1/s).
    pub f: Matrix5<f64>,
}

impl AlignmentModel {
    /// Model at rest at latitude `lat_rad`, height `height_m`.
    pub fn new(lat_rad: f64, height_m: f64) -> Self {
        let full = f_at_rest(lat_rad, height_m);
        let mut f = Matrix5::from_fn(|r, c| full[(r, c)]);
        f.fixed_view_mut::<3, 2>(PHI, VEL).fill(0.0);
        Self { f }
    }

    /// Transition over `dt_s` seconds as the filter uses it: `Φ = I + F dt + (F dt)²/2`, the
    /// exponential to second order in `F dt`.
    pub fn transition(&self, dt_s: f64) -> Matrix5<f64> {
        let fdt = self.f * dt_s;
        Matrix5::identity() + fdt + fdt * fdt * 0.5
    }

    /// Discrete process noise over `dt_s`, `Q = Q_c dt` (first order) for white gyro noise
    /// `gyro_psd_rad2_per_s` (rad²/s) and accelerometer noise `accel_psd_m2_per_s3` (m²/s³).
    pub fn process_noise(
        dt_s: f64,
        gyro_psd_rad2_per_s: f64,
        accel_psd_m2_per_s3: f64,
    ) -> Matrix5<f64> {
        let (qa, qv) = (gyro_psd_rad2_per_s * dt_s, accel_psd_m2_per_s3 * dt_s);
        Matrix5::from_diagonal(&Vector5::new(qa, qa, qa, qv, qv))
    }

    /// Zero-velocity measurement matrix `H`: the measured horizontal velocity (m/s) is
    /// `[δv_N, δv_E]`.
    pub fn h() -> Matrix2x5<f64> {
        let mut h = Matrix2x5::zeros();
        h[(0, VEL)] = 1.0;
        h[(1, VEL + 1)] = 1.0;
        h
    }

    /// Measurement noise `R` (m²/s²) of a zero-velocity update with 1-sigma
    /// `velocity_sigma_mps` per axis.
    pub fn r(velocity_sigma_mps: f64) -> Matrix2<f64> {
        Matrix2::from_diagonal_element(velocity_sigma_mps.powi(2))
    }

    /// Initial covariance `P0` after coarse alignment: level errors with 1-sigma
    /// `level_sigma_rad`, heading error with `heading_sigma_rad`, velocity variance
    /// [`ALIGNMENT_INITIAL_VELOCITY_VAR_M2PS2`].
    pub fn initial_covariance(level_sigma_rad: f64, heading_sigma_rad: f64) -> Matrix5<f64> {
        let (l, hd) = (level_sigma_rad.powi(2), heading_sigma_rad.powi(2));
        let v = ALIGNMENT_INITIAL_VELOCITY_VAR_M2PS2;
        Matrix5::from_diagonal(&Vector5::new(l, l, hd, v, v))
    }
}

#[cfg(test)]
mod tests;
