//! Checks of the error model against the independent static model of [`crate::linear`] and
//! against closed-form Schuler, Foucault and Earth-rate frequencies.

use super::*;
use crate::earth::Geodetic;
use crate::linear::{propagate_static, static_augmented_dynamics};

fn site() -> Geodetic {
    Geodetic::from_deg(28.22, 112.99, 60.0)
}

/// `a` and `b` agree to a few ulp of the larger.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-14 * a.abs().max(b.abs())
}

/// `F` at rest on the oracle's states `[φ, δv_N, δv_E, δL, δλ]`, and `G` for a level,
/// north-pointing body (`C_b^n = I`), equal the oracle's augmented matrix entry by entry.
#[test]
fn f_and_g_at_rest_match_the_static_oracle() {
    let states = [PHI, PHI + 1, PHI + 2, VEL, VEL + 1, POS, POS + 1];
    for lat_deg in [-60.0, 0.0, 28.22, 75.0] {
        let (lat, h) = (f64::to_radians(lat_deg), 60.0);
        let oracle = static_augmented_dynamics(lat, h);
        let f = f_at_rest(lat, h);
        let g = input_matrix(&Mat3::identity());
        for (r, &fr) in states.iter().enumerate() {
            for (c, &fc) in states.iter().enumerate() {
                let (ours, theirs) = (f[(fr, fc)], oracle[(r, c)]);
                assert!(
                    close(ours, theirs),
                    "F[{fr},{fc}] at {lat_deg}: {ours} vs {theirs}"
                );
            }
            for c in 0..3 {
                assert!(close(g[(fr, c)], oracle[(r, 7 + c)]), "G gyro[{fr},{c}]");
            }
            for c in 0..2 {
                assert!(
                    close(g[(fr, 3 + c)], oracle[(r, 10 + c)]),
                    "G accel[{fr},{c}]"
                );
            }
        }
    }
}

/// The static projection, driven by constant NED gyro drift and accelerometer bias through
/// `G`, reproduces the oracle's propagation over 6 h (positions in metres).
#[test]
fn static_model_propagation_matches_the_oracle() {
    let s = site();
    let m = StaticModel::new(s.lat_rad, s.height_m);
    let eps = Vec3::new(2e-8, -1e-8, 3e-8);
    let nab = Vec3::new(1e-4, -2e-4, 0.0);
    let phi0 = Vec3::new(1e-5, -2e-5, 3e-4);
    let g = input_matrix(&Mat3::identity());
    let mut a = SMatrix::<f64, 12, 12>::zeros();
    a.fixed_view_mut::<STATIC_STATES, STATIC_STATES>(0, 0)
        .copy_from(&m.f);
    for r in 0..STATIC_R_N {
        for c in 0..3 {
            a[(r, 7 + c)] = g[(r, c)];
        }
        for c in 0..2 {
            a[(r, 10 + c)] = g[(r, 3 + c)];
        }
    }
    let step_s = 600.0;
    let phi = (a * step_s).exp();
    let mut x = SVector::<f64, 12>::zeros();
    x.fixed_rows_mut::<3>(0).copy_from(&phi0);
    x.fixed_rows_mut::<3>(7).copy_from(&eps);
    (x[10], x[11]) = (nab.x, nab.y);
    let oracle = propagate_static(
        s.lat_rad,
        s.height_m,
        &phi0,
        &eps,
        &nab,
        6.0 * 3600.0,
        step_s,
    );
    for p in &oracle {
        let scale = p.horizontal_m().max(1.0);
        let d = (x[STATIC_R_N] - p.pos_ne_m[0]).hypot(x[STATIC_R_E] - p.pos_ne_m[1]);
        assert!(d < 1e-9 * scale, "t = {} s: {d} m of {scale} m", p.t_s);
        let dphi = (p.phi_ned_rad - x.fixed_rows::<3>(0)).norm();
        assert!(
            dphi < 1e-9 * p.phi_ned_rad.norm(),
            "t = {} s: φ off by {dphi}",
            p.t_s
        );
        x = phi * x;
    }
}

/// At rest the static model oscillates at the closed-form frequencies: Earth rate `Ω`, and the
/// Schuler frequency `ω_s = sqrt(g/R)` split by the Foucault rate `Ω sin L` into
/// `sqrt(ω_s² + (Ω sin L)²) ± Ω sin L`, plus the free east position (0), all undamped. The
/// closed form assumes a spherical Earth; with `R = sqrt(R_M R_N)` the ellipsoid moves the
/// Schuler pair by about 1e-4 of itself away from the pole, well inside the 1e-3 tolerance and
/// well below the Foucault split (1-3 % here) that a wrong Coriolis term would remove.
#[test]
fn static_model_has_the_schuler_foucault_and_earth_rate_frequencies() {
    for lat_deg in [-45.0, 10.0, 28.22, 60.0] {
        let (lat, h) = (f64::to_radians(lat_deg), 60.0);
        let m = StaticModel::new(lat, h);
        let e = &m.earth;
        let om = Wgs84::OMEGA_IE_RADPS;
        let ws2 = e.gravity_mps2 / (e.meridian_plus_h_m * e.transverse_plus_h_m).sqrt();
        let oz = om * e.sin_lat.abs();
        let split = (ws2 + oz * oz).sqrt();
        let expected = [0.0, om, split - oz, split + oz];
        let mut got: Vec<f64> =
            m.f.complex_eigenvalues()
                .iter()
                .map(|z| z.im.abs())
                .collect();
        got.sort_by(f64::total_cmp);
        got.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        assert_eq!(got.len(), expected.len(), "{lat_deg} deg: {got:?}");
        for (g, x) in got.iter().zip(expected) {
            assert!(
                (g - x).abs() <= 1e-3 * x + 1e-12,
                "{lat_deg} deg: {g} vs {x}"
            );
        }
        let max_re =
            m.f.complex_eigenvalues()
                .iter()
                .map(|z| z.re.abs())
                .fold(0.0, f64::max);
        assert!(
            max_re < 1e-9,
            "{lat_deg} deg: damped or unstable ({max_re})"
        );
    }
}

/// The third-order `Q` of the full model and the exact (Van Loan) `Q` of the static projection
/// agree on the attitude and horizontal-velocity block.
#[test]
fn process_noise_of_the_full_and_static_models_agree() {
    let s = site();
    let (qg, qa) = (1e-13, 1e-8);
    let dt_s = 1.0;
    let full = process_noise(&f_at_rest(s.lat_rad, s.height_m), dt_s, qg, qa);
    let stat = StaticModel::new(s.lat_rad, s.height_m).process_noise(dt_s, qg, qa);
    for r in 0..STATIC_R_N {
        for c in 0..STATIC_R_N {
            let scale = (full[(r, r)] * full[(c, c)]).sqrt();
            let d = (full[(r, c)] - stat[(r, c)]).abs();
            assert!(
                d < 1e-6 * scale,
                "Q[{r},{c}]: {} vs {}",
                full[(r, c)],
                stat[(r, c)]
            );
        }
    }
}

/// The alignment model is the full model at rest on `[φ, δv_N, δv_E]` without the
/// transport-rate coupling; `H` measures the horizontal velocity errors.
#[test]
fn alignment_model_is_the_projection_of_the_full_model() {
    let s = site();
    let full = f_at_rest(s.lat_rad, s.height_m);
    let m = AlignmentModel::new(s.lat_rad, s.height_m);
    for r in 0..ALIGNMENT_STATES {
        for c in 0..ALIGNMENT_STATES {
            let dropped = r < VEL && c >= VEL;
            let want = if dropped { 0.0 } else { full[(r, c)] };
            assert_eq!(m.f[(r, c)], want, "F[{r},{c}]");
        }
    }
    let x = Vector5::new(1.0, 2.0, 3.0, 4.0, 5.0);
    assert_eq!(AlignmentModel::h() * x, nalgebra::Vector2::new(4.0, 5.0));
    assert_eq!(AlignmentModel::r(2e-3)[(1, 1)], 4e-6);
}
