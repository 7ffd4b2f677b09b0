//! Linear navigation error model of an INS at rest on a turntable (vertical channel held), in the
//! form the diagnosis propagates: seven states
//! `x = [φ_N, φ_E, φ_D, δv_N, δv_E, δr_N, δr_E]` (rad, m/s, m) obeying
//!
//! ```text
//! φ̇  = -ω_ie × φ + δω_ie(δr_N) + δω_en(δv) - ε^n
//! δv̇ = f^n × φ - 2 ω_ie × δv + ∇^n                  (north and east rows, f^n = [0, 0, -g])
//! δṙ = δv
//! ```
//!
//! (the static model of `sins_nav::linear` with positions in metres). `A` is the `F` of
//! [`sins_nav::error_model::StaticModel`], the projection of the workspace's one error model at
//! rest; this module adds the diagnosis' input machinery. The IMU centre does not
//! translate, so `A` is constant; all time variation (body attitude under rotations and
//! vibration) sits in the forcing `ε^n = C_nb ε^b`, `∇^n = C_nb ∇^b`, which the diagnosis
//! integrates at the sample rate into bins with three moments (see [`Moments`]) so that a bin
//! update is exact to second order in `A·Δ` however fast the forcing oscillates inside the bin.

use nalgebra::SVector;
use sins_nav::error_model::{self, ACCEL_INPUT_SIGN, GYRO_INPUT_SIGN, StaticModel};
use sins_nav::{EarthAt, Geodetic};

/// Number of navigation error states.
pub const NX: usize = error_model::STATIC_STATES;
/// Navigation error state vector (rad, m/s, m).
pub type Vec7 = error_model::Vec7;
/// 7x7 matrix.
pub type Mat7 = error_model::Mat7;
/// Forcing of one bin: `[ε_N, ε_E, ε_D (rad), ∇_N, ∇_E (m/s)]` as increments in NED.
pub type Forcing = SVector<f64, 5>;

/// Index of the north position error (m).
pub const R_N: usize = error_model::STATIC_R_N;
/// Index of the east position error (m).
pub const R_E: usize = error_model::STATIC_R_E;

/// Three moments of the forcing increments `u_j` applied at times `s_j` inside a bin of length
/// `Δ`: `m1 = Σ u_j`, `m2 = Σ (Δ - s_j) u_j`, `m3 = Σ (Δ - s_j)² / 2 · u_j`. The state at the bin
/// end is `Φ x + B m1 + A B m2 + A² B m3`, the expansion of `Σ e^{A(Δ - s_j)} B u_j`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    /// Σ u.
    pub m1: Forcing,
    /// Σ (Δ - s) u.
    pub m2: Forcing,
    /// Σ (Δ - s)²/2 u.
    pub m3: Forcing,
}

impl Moments {
    /// Add the forcing increment `u` applied `w_s` seconds before the bin end.
    #[inline]
    pub fn add(&mut self, u: &Forcing, w_s: f64) {
        self.m1 += u;
        self.m2 += u * w_s;
        self.m3 += u * (0.5 * w_s * w_s);
    }

    /// [`Moments::add`] of a forcing that is zero outside components `first..first + N`, which
    /// are `u`; `half_w2_s2` is `0.5 * w_s * w_s`. The zero components are skipped: adding an
    /// exact zero to a sum that started at +0 leaves it unchanged, so the moments are
    /// [`Moments::add`]'s to the bit.
    #[inline]
    pub fn add_part<const N: usize>(
        &mut self,
        first: usize,
        u: [f64; N],
        w_s: f64,
        half_w2_s2: f64,
    ) {
        for (k, uk) in u.into_iter().enumerate() {
            self.m1[first + k] += uk;
            self.m2[first + k] += uk * w_s;
            self.m3[first + k] += uk * half_w2_s2;
        }
    }
}

/// The constant error dynamics at one site and its discretisations: a thin wrapper of
/// [`StaticModel`] that caches `A²` for the bin inputs.
#[derive(Clone, Debug)]
pub struct ErrorModel {
    /// Continuous dynamics matrix `A` (the static model's `F`, 1/s).
    pub a: Mat7,
    /// `A²`.
    pub a2: Mat7,
    /// Earth quantities at the site.
    pub earth: EarthAt,
    /// The error model this wraps.
    model: StaticModel,
}

impl ErrorModel {
    /// Model at a fixed `site`.
    pub fn new(site: &Geodetic) -> Self {
        let model = StaticModel::new(site.lat_rad, site.height_m);
        Self {
            a: model.f,
            a2: model.f * model.f,
            earth: model.earth,
            model,
        }
    }

    /// State transition over `dt_s`.
    pub fn transition(&self, dt_s: f64) -> Mat7 {
        self.model.transition(dt_s)
    }

    /// The bin input `B m1 + A B m2 + A² B m3` of a forcing's moments.
    #[inline]
    pub fn input(&self, m: &Moments) -> Vec7 {
        self.a * inject(&m.m2) + self.a2 * inject(&m.m3) + inject(&m.m1)
    }

    /// Discrete covariance over `dt_s` of isotropic white gyro noise (angle random walk
    /// `arw_rad_per_sqrt_s`) and accelerometer noise (velocity random walk `vrw_mps_per_sqrt_s`),
    /// by Van Loan's method ([`StaticModel::process_noise`]). Isotropic body noise stays
    /// isotropic in NED whatever the attitude.
    pub fn white_noise(&self, dt_s: f64, arw_rad_per_sqrt_s: f64, vrw_mps_per_sqrt_s: f64) -> Mat7 {
        self.model
            .process_noise(dt_s, arw_rad_per_sqrt_s.powi(2), vrw_mps_per_sqrt_s.powi(2))
    }
}

/// `B u`: gyro increments enter the attitude error with a minus sign, accelerometer increments
/// the velocity error (signs of [`sins_nav::error_model::input_matrix`]).
#[inline]
pub fn inject(u: &Forcing) -> Vec7 {
    let (g, a) = (GYRO_INPUT_SIGN, ACCEL_INPUT_SIGN);
    Vec7::from([g * u[0], g * u[1], g * u[2], a * u[3], a * u[4], 0.0, 0.0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_nav::Vec3;
    use sins_nav::linear::propagate_static;

    /// Adding only a forcing's non-zero part leaves the moments [`Moments::add`] leaves, to the
    /// bit, for gyro-only (three components) and accelerometer-only (two) forcings of both
    /// signs over a bin.
    #[test]
    fn adding_the_non_zero_part_equals_adding_the_whole_forcing() {
        let (mut whole, mut part) = (Moments::default(), Moments::default());
        for k in 0..400 {
            let x = f64::from(k);
            let w_s = 1.0 - (x + 0.5) * 0.0025;
            let g = [(x * 0.7).sin() * 1e-5, -(x * 1.3).cos() * 3e-6, 2e-7 * x];
            let a = [(x * 0.9).cos() * 1e-3, -(x * 0.2).sin() * 4e-4];
            if k % 3 == 0 {
                whole.add(&Forcing::from([g[0], g[1], g[2], 0.0, 0.0]), w_s);
                part.add_part(0, g, w_s, 0.5 * w_s * w_s);
            } else {
                whole.add(&Forcing::from([0.0, 0.0, 0.0, a[0], a[1]]), w_s);
                part.add_part(3, a, w_s, 0.5 * w_s * w_s);
            }
        }
        let bits = |m: &Moments| {
            [m.m1, m.m2, m.m3]
                .iter()
                .flat_map(|f| f.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&whole), bits(&part));
        assert!(whole.m3.iter().all(|v| *v != 0.0));
    }

    /// Constant NED drift and bias: stepping with one-second bins of moments reproduces the
    /// exact matrix-exponential solution of `sins_nav::linear` to 1e-5 (third-order terms).
    #[test]
    fn binned_forcing_matches_the_static_model() {
        let site = Geodetic::from_deg(28.22, 112.99, 60.0);
        let m = ErrorModel::new(&site);
        let eps = Vec3::new(2e-8, -1e-8, 3e-8);
        let nab = Vec3::new(1e-4, -2e-4, 0.0);
        let phi0 = Vec3::new(1e-5, -2e-5, 3e-4);
        let reference = propagate_static(
            site.lat_rad,
            site.height_m,
            &phi0,
            &eps,
            &nab,
            6.0 * 3600.0,
            3600.0,
        );
        let phi = m.transition(1.0);
        let h = 0.01;
        let mut mom = Moments::default();
        for j in 0..100 {
            let u = Forcing::from([eps.x * h, eps.y * h, eps.z * h, nab.x * h, nab.y * h]);
            mom.add(&u, 1.0 - (j as f64 + 0.5) * h);
        }
        let inp = m.input(&mom);
        let mut x = Vec7::zeros();
        x.fixed_rows_mut::<3>(0).copy_from(&phi0);
        for k in 1..=6 * 3600 {
            x = phi * x + inp;
            if k % 3600 == 0 {
                let r = &reference[k / 3600];
                let scale = r.horizontal_m().max(1.0);
                let d = (x[R_N] - r.pos_ne_m[0]).hypot(x[R_E] - r.pos_ne_m[1]);
                assert!(d < 1e-5 * scale, "t = {} h: {d} m of {scale} m", k / 3600);
            }
        }
    }
}
