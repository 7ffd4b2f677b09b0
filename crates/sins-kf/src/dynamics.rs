//! The navigation block of eq (6): the 9x9 error dynamics `F_nn` of `[φ, δV, δL, δλ, δh]`
//! (NED, φ defined by `C_est = (I − [φ×]) C_true`, errors = estimate − truth), its transition
//! matrix over one update interval and the discrete process noise of white gyro and
//! accelerometer noise are the workspace's one error model, [`sins_nav::error_model`]
//! (`f_matrix`, `transition`, `process_noise`, used as they are by [`crate::engine`]; the
//! augmented sensor-error blocks live in [`crate::moments`]). This module checks that block
//! against the independent static model of `sins-nav`.
//!
//! On a turntable the IMU centre rests: the specific force in n is `−g^n` and the velocity zero,
//! so `F_nn` is constant over an update interval; the time variation of eq (6) lives entirely in
//! the input matrix of the coefficients (`C_b^n` turning with the table), which
//! [`crate::moments`] integrates sample by sample.

#[cfg(test)]
mod tests {
    use crate::states::{POS, VEL};
    use nalgebra::SMatrix;
    use sins_nav::Vec3;
    use sins_nav::earth::EarthAt;
    use sins_nav::error_model::f_matrix;
    use sins_nav::linear::propagate_static;

    /// The navigation block, started from an attitude error at rest, reproduces the independent
    /// static error model of `sins-nav` (which holds the vertical channel).
    #[test]
    fn matches_the_static_linear_model() {
        let (lat, h) = (28.22f64.to_radians(), 60.0);
        let g = EarthAt::new(lat, h).gravity_mps2;
        let f = f_matrix(lat, h, &Vec3::zeros(), &Vec3::new(0.0, 0.0, -g));
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
