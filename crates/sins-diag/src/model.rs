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
//! (the static model of `sins_nav::linear` with positions in metres). The IMU centre does not
//! translate, so `A` is constant; all time variation (body attitude under rotations and
//! vibration) sits in the forcing `ε^n = C_nb ε^b`, `∇^n = C_nb ∇^b`, which the diagnosis
//! integrates at the sample rate into bins with three moments (see [`Moments`]) so that a bin
//! update is exact to second order in `A·Δ` however fast the forcing oscillates inside the bin.

use nalgebra::{SMatrix, SVector};
use sins_nav::{EarthAt, Geodetic, Wgs84};

/// Number of navigation error states.
pub const NX: usize = 7;
/// Navigation error state vector.
pub type Vec7 = SVector<f64, NX>;
/// 7x7 matrix.
pub type Mat7 = SMatrix<f64, NX, NX>;
/// Forcing of one bin: `[ε_N, ε_E, ε_D (rad), ∇_N, ∇_E (m/s)]` as increments in NED.
pub type Forcing = SVector<f64, 5>;

/// Index of the north position error.
pub const R_N: usize = 5;
/// Index of the east position error.
pub const R_E: usize = 6;

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
}

/// The constant error dynamics at one site and its discretisations.
#[derive(Clone, Debug)]
pub struct ErrorModel {
    /// Continuous dynamics matrix `A`.
    pub a: Mat7,
    /// `A²`.
    pub a2: Mat7,
    /// Earth quantities at the site.
    pub earth: EarthAt,
}

impl ErrorModel {
    /// Model at a fixed `site`.
    pub fn new(site: &Geodetic) -> Self {
        let e = EarthAt::new(site.lat_rad, site.height_m);
        let om = Wgs84::OMEGA_IE_RADPS;
        let (sl, cl) = (e.sin_lat, e.cos_lat);
        let (rm, rn) = (e.meridian_plus_h_m, e.transverse_plus_h_m);
        let g = e.gravity_mps2;
        let mut a = Mat7::zeros();
        // -ω_ie × φ with ω_ie = [Ω cL, 0, -Ω sL].
        a[(0, 1)] = -om * sl;
        a[(1, 0)] = om * sl;
        a[(1, 2)] = om * cl;
        a[(2, 1)] = -om * cl;
        // δω_en = [δv_E/Rn, -δv_N/Rm, -δv_E tanL/Rn]; δω_ie = [-Ω sL δL, 0, -Ω cL δL], δL = δr_N/Rm.
        a[(0, 4)] = 1.0 / rn;
        a[(1, 3)] = -1.0 / rm;
        a[(2, 4)] = -sl / cl / rn;
        a[(0, R_N)] = -om * sl / rm;
        a[(2, R_N)] = -om * cl / rm;
        // f × φ with f = [0, 0, -g].
        a[(3, 1)] = g;
        a[(4, 0)] = -g;
        // -2 ω_ie × δv (horizontal).
        a[(3, 4)] = -2.0 * om * sl;
        a[(4, 3)] = 2.0 * om * sl;
        a[(R_N, 3)] = 1.0;
        a[(R_E, 4)] = 1.0;
        Self {
            a2: a * a,
            a,
            earth: e,
        }
    }

    /// State transition over `dt_s`.
    pub fn transition(&self, dt_s: f64) -> Mat7 {
        (self.a * dt_s).exp()
    }

    /// The bin input `B m1 + A B m2 + A² B m3` of a forcing's moments.
    #[inline]
    pub fn input(&self, m: &Moments) -> Vec7 {
        self.a * inject(&m.m2) + self.a2 * inject(&m.m3) + inject(&m.m1)
    }

    /// Discrete covariance over `dt_s` of isotropic white gyro noise (angle random walk
    /// `arw_rad_per_sqrt_s`) and accelerometer noise (velocity random walk `vrw_mps_per_sqrt_s`),
    /// by Van Loan's method. Isotropic body noise stays isotropic in NED whatever the attitude.
    pub fn white_noise(&self, dt_s: f64, arw_rad_per_sqrt_s: f64, vrw_mps_per_sqrt_s: f64) -> Mat7 {
        let mut qc = Mat7::zeros();
        for i in 0..3 {
            qc[(i, i)] = arw_rad_per_sqrt_s.powi(2);
        }
        for i in 3..5 {
            qc[(i, i)] = vrw_mps_per_sqrt_s.powi(2);
        }
        let mut m = SMatrix::<f64, 14, 14>::zeros();
        m.fixed_view_mut::<NX, NX>(0, 0)
            .copy_from(&(-self.a * dt_s));
        m.fixed_view_mut::<NX, NX>(0, NX).copy_from(&(qc * dt_s));
        m.fixed_view_mut::<NX, NX>(NX, NX)
            .copy_from(&(self.a.transpose() * dt_s));
        let e = m.exp();
        let phi = e.fixed_view::<NX, NX>(NX, NX).transpose();
        let q = phi * e.fixed_view::<NX, NX>(0, NX);
        (q + q.transpose()) * 0.5
    }
}

/// `B u`: gyro increments enter the attitude error with a minus sign, accelerometer increments
/// the velocity error.
#[inline]
pub fn inject(u: &Forcing) -> Vec7 {
    Vec7::from([-u[0], -u[1], -u[2], u[3], u[4], 0.0, 0.0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_nav::Vec3;
    use sins_nav::linear::propagate_static;

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
