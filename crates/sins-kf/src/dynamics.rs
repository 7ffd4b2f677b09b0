//! The navigation block of eq (6): the 9x9 error dynamics `F_nn` of `[φ, δV, δL, δλ, δh]`
//! (NED, φ defined by `C_est = (I − [φ×]) C_true`, errors = estimate − truth), its transition
//! matrix over one update interval and the discrete process noise of white gyro and
//! accelerometer noise.
//!
//! On a turntable the IMU centre rests: the specific force in n is `−g^n` and the velocity zero,
//! so `F_nn` is constant over an update interval; the time variation of eq (6) lives entirely in
//! the input matrix of the coefficients (`C_b^n` turning with the table), which
//! [`crate::moments`] integrates sample by sample.

use crate::states::{PHI, POS, VEL};
use nalgebra::SMatrix;
use sins_nav::attitude::skew;
use sins_nav::earth::{EarthAt, normal_gravity_mps2};
use sins_nav::{Mat3, Vec3, Wgs84};

/// 9x9 matrix of the navigation block.
pub(crate) type Mat9 = SMatrix<f64, 9, 9>;

/// `F_nn` of eq (6) at latitude `lat_rad`, height `height_m`, NED velocity `vel` (m/s) and NED
/// specific force `f_ned` (m/s^2), with a free vertical channel (gravity gradient included).
pub(crate) fn nav_error_matrix(lat_rad: f64, height_m: f64, vel: &Vec3, f_ned: &Vec3) -> Mat9 {
    let e = EarthAt::new(lat_rad, height_m);
    let (sl, cl) = (e.sin_lat, e.cos_lat);
    let tl = sl / cl;
    let (rm, rn) = (e.meridian_plus_h_m, e.transverse_plus_h_m);
    let om = Wgs84::OMEGA_IE_RADPS;
    let w_ie = e.earth_rate_ned_radps;
    let w_en = e.transport_rate_ned_radps(vel);
    let (vn, ve) = (vel.x, vel.y);

    // δω_ie and δω_en as linear maps of [δV (3), δL, δh]: columns 0..3 velocity, 3 δL, 4 δh.
    let mut d_ie = SMatrix::<f64, 3, 5>::zeros();
    d_ie[(0, 3)] = -om * sl;
    d_ie[(2, 3)] = -om * cl;
    let mut d_en = SMatrix::<f64, 3, 5>::zeros();
    d_en[(0, 1)] = 1.0 / rn;
    d_en[(0, 4)] = -ve / (rn * rn);
    d_en[(1, 0)] = -1.0 / rm;
    d_en[(1, 4)] = vn / (rm * rm);
    d_en[(2, 1)] = -tl / rn;
    d_en[(2, 3)] = -ve / (cl * cl * rn);
    d_en[(2, 4)] = ve * tl / (rn * rn);

    let mut f = Mat9::zeros();
    let put3 = |f: &mut Mat9, r: usize, c: usize, m: &Mat3| {
        f.fixed_view_mut::<3, 3>(r, c).copy_from(m);
    };
    // Attitude: φ̇ = −ω_in × φ + δω_in (− C δω^b in the coefficient block).
    put3(&mut f, PHI, PHI, &(-skew(&(w_ie + w_en))));
    let d_in = d_ie + d_en;
    // Velocity: δV̇ = f^n × φ − (2ω_ie + ω_en) × δV + V × (2δω_ie + δω_en) + δg.
    put3(&mut f, VEL, PHI, &skew(f_ned));
    put3(&mut f, VEL, VEL, &(-skew(&(2.0 * w_ie + w_en))));
    let v_cross = skew(vel) * (2.0 * d_ie + d_en);
    let dg_dh = 0.5
        * (normal_gravity_mps2(lat_rad, height_m + 1.0)
            - normal_gravity_mps2(lat_rad, height_m - 1.0));
    for r in 0..3 {
        for (k, col) in [(0, VEL), (1, VEL + 1), (2, VEL + 2), (3, POS), (4, POS + 2)] {
            f[(PHI + r, col)] += d_in[(r, k)];
            f[(VEL + r, col)] += v_cross[(r, k)];
        }
    }
    f[(VEL + 2, POS + 2)] += dg_dh;
    // Position: δL̇, δλ̇, δḣ.
    f[(POS, VEL)] = 1.0 / rm;
    f[(POS, POS + 2)] = -vn / (rm * rm);
    f[(POS + 1, VEL + 1)] = 1.0 / (rn * cl);
    f[(POS + 1, POS)] = ve * tl / (rn * cl);
    f[(POS + 1, POS + 2)] = -ve / (rn * rn * cl);
    f[(POS + 2, VEL + 2)] = -1.0;
    f
}

/// Discrete noise `∫_0^T e^{Fτ} Q_c e^{Fᵀτ} dτ` of white gyro noise (variance density `qg`,
/// rad²/s) into φ and accelerometer noise (`qa`, m²/s³) into δV, to third order in `T`
/// (exact for the nilpotent attitude-velocity-position chain that dominates).
pub(crate) fn nav_process_noise(f: &Mat9, t: f64, qg: f64, qa: f64) -> Mat9 {
    let mut qc = Mat9::zeros();
    for i in 0..3 {
        qc[(PHI + i, PHI + i)] = qg;
        qc[(VEL + i, VEL + i)] = qa;
    }
    let fq = f * qc;
    let q1 = qc * t;
    let q2 = (fq + fq.transpose()) * (t * t / 2.0);
    let ffq = f * fq;
    let q3 = (ffq + ffq.transpose() + 2.0 * fq * f.transpose()) * (t * t * t / 6.0);
    let q = q1 + q2 + q3;
    (q + q.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_nav::linear::propagate_static;

    /// The navigation block, started from an attitude error at rest, reproduces the independent
    /// static error model of `sins-nav` (which holds the vertical channel).
    #[test]
    fn matches_the_static_linear_model() {
        let (lat, h) = (28.22f64.to_radians(), 60.0);
        let g = EarthAt::new(lat, h).gravity_mps2;
        let f = nav_error_matrix(lat, h, &Vec3::zeros(), &Vec3::new(0.0, 0.0, -g));
        let step = 10.0;
        let phi = (f * step).exp();
        let phi0 = Vec3::new(1e-4, -2e-4, 3e-4);
        let lin = propagate_static(lat, h, &phi0, &Vec3::zeros(), &Vec3::zeros(), 3600.0, step);
        let mut x = SMatrix::<f64, 9, 1>::zeros();
        x.fixed_rows_mut::<3>(0).copy_from(&phi0);
        let e = EarthAt::new(lat, h);
        for p in &lin {
            let north = x[POS] * e.meridian_plus_h_m;
            let east = x[POS + 1] * e.transverse_plus_h_m * e.cos_lat;
            assert!((p.phi_ned_rad - x.fixed_rows::<3>(0)).norm() < 1e-3 * phi0.norm());
            assert!((p.pos_ne_m[0] - north).abs() < 1e-3 * (1.0 + p.horizontal_m()));
            assert!((p.pos_ne_m[1] - east).abs() < 1e-3 * (1.0 + p.horizontal_m()));
            x = phi * x;
            // The linear model holds the vertical channel: keep it at zero here too.
            x[VEL + 2] = 0.0;
            x[POS + 2] = 0.0;
        }
    }
}
