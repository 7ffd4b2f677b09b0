//! Analytic checks of the mechanization against the independent linear static error model, at
//! rest at the paper's site, with exact (closed-form) stationary increments.

use sins_nav::alignment::{AlignmentConfig, SelfAlignment};
use sins_nav::earth::EarthAt;
use sins_nav::linear::propagate_static;
use sins_nav::*;

const H_S: f64 = 0.005;
const DURATION_S: f64 = 15.0 * 3600.0;

fn site() -> Geodetic {
    Geodetic::from_deg(28.22, 112.99, 60.0)
}

/// Exact increments of a stationary IMU at attitude `ned_from_body` plus constant body-frame
/// gyro drift and accelerometer bias.
fn stationary_increment(
    ned_from_body: &Quat,
    gyro_bias_radps: &Vec3,
    accel_bias_mps2: &Vec3,
) -> Increment {
    let e = EarthAt::new(site().lat_rad, site().height_m);
    let body_from_ned = ned_from_body.inverse();
    Increment {
        dtheta_rad: (body_from_ned * e.earth_rate_ned_radps + gyro_bias_radps) * H_S,
        dv_mps: (body_from_ned * Vec3::new(0.0, 0.0, -e.gravity_mps2) + accel_bias_mps2) * H_S,
    }
}

fn config() -> StrapdownConfig {
    StrapdownConfig {
        sample_interval_s: H_S,
        coning: ConingOrder::TwoSample,
        vertical: VerticalChannel::Hold {
            height_m: site().height_m,
        },
    }
}

/// Navigate from `state` for `duration_s` on constant increments; returns (t, north, east,
/// v_north, v_east) every `every_s` seconds.
fn navigate(state: NavState, inc: Increment, duration_s: f64, every_s: f64) -> Vec<[f64; 5]> {
    let mut nav = Strapdown::new(config(), state);
    let n = (duration_s / H_S).round() as usize;
    let every = (every_s / H_S).round() as usize;
    let mut out = Vec::new();
    for k in 1..=n {
        nav.push(&inc);
        if k % every == 0 {
            let s = nav.state();
            let d = s.position.ned_offset_from_m(&site());
            out.push([s.t_s, d.x, d.y, s.vel_ned_mps.x, s.vel_ned_mps.y]);
        }
    }
    out
}

fn max_horizontal(track: &[[f64; 5]]) -> f64 {
    track.iter().map(|p| p[1].hypot(p[2])).fold(0.0, f64::max)
}

fn compare_with_linear(gyro_bias_body: Vec3, accel_bias_body: Vec3) -> (f64, f64, Vec<[f64; 5]>) {
    // Level, forward axis north: body x = east, y = north, z = up.
    let q = ned_from_body_euler(&Euler::default());
    let inc = stationary_increment(&q, &gyro_bias_body, &accel_bias_body);
    let track = navigate(NavState::at_rest(0.0, q, site()), inc, DURATION_S, 10.0);
    let eps_ned = q * gyro_bias_body;
    let acc_ned = q * accel_bias_body;
    let lin = propagate_static(
        site().lat_rad,
        site().height_m,
        &Vec3::zeros(),
        &eps_ned,
        &acc_ned,
        DURATION_S,
        10.0,
    );
    let lin_max = lin.iter().map(|p| p.horizontal_m()).fold(0.0, f64::max);
    (max_horizontal(&track), lin_max, track)
}

#[test]
fn error_free_stationary_floor_is_below_a_metre() {
    let q = ned_from_body_euler(&Euler::from_deg(1.0, -91.0, -91.0));
    let inc = stationary_increment(&q, &Vec3::zeros(), &Vec3::zeros());
    let track = navigate(NavState::at_rest(0.0, q, site()), inc, DURATION_S, 60.0);
    let m = max_horizontal(&track);
    assert!(m < 0.1, "error-free stationary 15 h drifted {m} m");
}

#[test]
fn north_gyro_bias_matches_linear_model() {
    let b = 0.005 * DEG_PER_H;
    let (mech, lin, _) = compare_with_linear(Vec3::new(0.0, b, 0.0), Vec3::zeros());
    eprintln!("north gyro 0.005 deg/h: mechanization {mech:.1} m, linear {lin:.1} m");
    assert!(lin > 1000.0, "the bias must matter: {lin} m");
    assert!(
        (mech - lin).abs() <= 0.05 * lin,
        "mech {mech} vs linear {lin}"
    );
}

#[test]
fn vertical_gyro_bias_matches_linear_model() {
    let b = 0.005 * DEG_PER_H;
    let (mech, lin, _) = compare_with_linear(Vec3::new(0.0, 0.0, b), Vec3::zeros());
    eprintln!("vertical gyro 0.005 deg/h: mechanization {mech:.1} m, linear {lin:.1} m");
    assert!(lin > 100.0, "the bias must matter: {lin} m");
    assert!(
        (mech - lin).abs() <= 0.05 * lin,
        "mech {mech} vs linear {lin}"
    );
}

#[test]
fn east_accel_bias_matches_linear_model_and_schuler_period() {
    let (mech, lin, track) = compare_with_linear(Vec3::zeros(), Vec3::new(20.0 * UG, 0.0, 0.0));
    eprintln!("east accel 20 ug: mechanization {mech:.1} m, linear {lin:.1} m");
    assert!(lin > 100.0, "the bias must matter: {lin} m");
    assert!(
        (mech - lin).abs() <= 0.05 * lin,
        "mech {mech} vs linear {lin}"
    );
    // Schuler period from upward zero crossings of the east velocity error in the first 10 h
    // (before the Foucault envelope's node near 12.8 h), linearly interpolated.
    let ups: Vec<f64> = track
        .windows(2)
        .filter(|w| w[0][0] < 10.0 * 3600.0 && w[0][4] < 0.0 && w[1][4] >= 0.0)
        .map(|w| w[0][0] + (w[1][0] - w[0][0]) * (-w[0][4]) / (w[1][4] - w[0][4]))
        .collect();
    assert!(ups.len() >= 5, "too few Schuler cycles: {}", ups.len());
    let period_min = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64 / 60.0;
    eprintln!("Schuler period measured: {period_min:.3} min");
    assert!(
        (period_min - 84.4).abs() <= 0.01 * 84.4,
        "Schuler period {period_min} min"
    );
}

/// Navigate 15 h after a (noise-free) 20 min self-alignment with the given body-frame biases;
/// returns (max error after alignment, max error from the true attitude, aligned attitude error).
fn aligned_vs_unaligned(q_true: &Quat, gyro: Vec3, accel: Vec3) -> (f64, f64, Vec3) {
    let inc = stationary_increment(q_true, &gyro, &accel);
    let unaligned = max_horizontal(&navigate(
        NavState::at_rest(0.0, *q_true, site()),
        inc,
        DURATION_S,
        60.0,
    ));
    // The data are noise-free, so the filter is told so (its accuracy is otherwise noise-limited:
    // about ARW / (Ω cos L √T) in heading).
    let quiet = AlignmentConfig {
        gyro_arw_rad_per_sqrt_s: 1e-9,
        accel_vrw_mps_per_sqrt_s: 1e-8,
        velocity_sigma_mps: 1e-4,
        ..AlignmentConfig::default()
    };
    let mut align = SelfAlignment::new(quiet, config(), site(), 0.0);
    while !align.push(&inc).unwrap() {}
    let r = align.finish().unwrap();
    let aligned = max_horizontal(&navigate(r.state, inc, DURATION_S, 60.0));
    (
        aligned,
        unaligned,
        attitude::attitude_error_ned_rad(&r.state.ned_from_body, q_true),
    )
}

#[test]
fn alignment_absorbs_east_gyro_and_east_accel_biases() {
    let q_true = ned_from_body_euler(&Euler::from_deg(0.5, -0.3, 0.0));
    let east_axis = q_true.inverse() * Vec3::new(0.0, 1.0, 0.0);
    let (aligned, unaligned, phi) =
        aligned_vs_unaligned(&q_true, east_axis * (0.005 * DEG_PER_H), Vec3::zeros());
    let gyrocompass = 0.005 * DEG_PER_H / (Wgs84::OMEGA_IE_RADPS * site().lat_rad.cos());
    eprintln!(
        "east gyro 0.005 deg/h: {aligned:.2} m aligned vs {unaligned:.1} m; heading error {:.2} arcsec",
        phi.z / ARCSEC
    );
    assert!(
        unaligned > 1000.0 && aligned < 0.01 * unaligned,
        "{aligned} vs {unaligned}"
    );
    assert!(
        (phi.z.abs() - gyrocompass).abs() < 0.02 * gyrocompass,
        "heading error {} rad",
        phi.z
    );

    let (aligned, unaligned, phi) =
        aligned_vs_unaligned(&q_true, Vec3::zeros(), east_axis * (50.0 * UG));
    eprintln!(
        "east accel 50 ug: {aligned:.2} m aligned vs {unaligned:.1} m; north tilt {:.2} arcsec",
        phi.x / ARCSEC
    );
    assert!(
        unaligned > 300.0 && aligned < 0.01 * unaligned,
        "{aligned} vs {unaligned}"
    );
    assert!((phi.x.abs() - 50.0 * UG / 9.79).abs() < 0.02 * 50.0 * UG / 9.79);
}

/// A north accelerometer bias is *not* absorbed over 15 h: after alignment the IMU's data are
/// exactly those of a bias-free IMU at latitude L + ∇_N/g, so the solution oscillates (Schuler,
/// Foucault) about that latitude and peaks near 2 R ∇_N / g. The linear model agrees.
#[test]
fn north_accel_bias_after_alignment_is_a_latitude_offset() {
    let q_true = ned_from_body_euler(&Euler::from_deg(0.5, -0.3, 0.0));
    let north_axis = q_true.inverse() * Vec3::new(1.0, 0.0, 0.0);
    let bias = 50.0 * UG;
    let (aligned, _, phi) = aligned_vs_unaligned(&q_true, Vec3::zeros(), north_axis * bias);
    let e = EarthAt::new(site().lat_rad, site().height_m);
    let lin = propagate_static(
        site().lat_rad,
        site().height_m,
        &phi,
        &Vec3::zeros(),
        &Vec3::new(bias, 0.0, 0.0),
        DURATION_S,
        10.0,
    );
    let lin_max = lin.iter().map(|p| p.horizontal_m()).fold(0.0, f64::max);
    let two_r_alpha = 2.0 * e.meridian_plus_h_m * bias / e.gravity_mps2;
    eprintln!(
        "north accel 50 ug after alignment: {aligned:.1} m, linear {lin_max:.1} m, 2R∇/g {two_r_alpha:.1} m"
    );
    assert!(
        (aligned - lin_max).abs() < 0.05 * lin_max,
        "{aligned} vs {lin_max}"
    );
    assert!(
        (aligned - two_r_alpha).abs() < 0.05 * two_r_alpha,
        "{aligned} vs {two_r_alpha}"
    );
}

#[test]
fn alignment_recovers_attitude_of_an_error_free_imu() {
    let q_true = ned_from_body_euler(&Euler::from_deg(1.0, -91.0, -91.0));
    let inc = stationary_increment(&q_true, &Vec3::zeros(), &Vec3::zeros());
    let mut align = SelfAlignment::new(AlignmentConfig::default(), config(), site(), 0.0);
    while !align.push(&inc).unwrap() {}
    let r = align.finish().unwrap();
    let err = attitude::attitude_error_ned_rad(&r.state.ned_from_body, &q_true);
    let coarse = attitude::attitude_error_ned_rad(&r.coarse_ned_from_body, &q_true);
    eprintln!(
        "alignment error (arcsec): fine {:?}, coarse {:?}",
        err / ARCSEC,
        coarse / ARCSEC
    );
    assert!(err.norm() < 1.0 * ARCSEC, "fine alignment error {err:?}");
    assert!((r.state.t_s - 1200.0).abs() < 1e-9);
}

#[test]
fn vertical_channel_free_diverges_and_damped_holds() {
    let q = ned_from_body_euler(&Euler::default());
    let e = EarthAt::new(site().lat_rad, site().height_m);
    // 10 ug vertical accelerometer bias (body z = up).
    let inc = stationary_increment(&q, &Vec3::zeros(), &Vec3::new(0.0, 0.0, 10.0 * UG));
    let run = |vertical| {
        let mut nav = Strapdown::new(
            StrapdownConfig {
                vertical,
                ..config()
            },
            NavState::at_rest(0.0, q, site()),
        );
        for _ in 0..(3.0 * 3600.0 / H_S) as usize {
            nav.push(&inc);
        }
        (nav.state().position.height_m - site().height_m).abs()
    };
    let free = run(VerticalChannel::Free);
    let damped = run(VerticalChannel::Damped {
        height_m: site().height_m,
        tau_s: 100.0,
    });
    // Instability time constant sqrt(R/2g) ≈ 570 s: 3 h of 10 ug grows to kilometres.
    assert!(
        free > 1000.0,
        "free vertical channel should diverge, got {free} m"
    );
    // Damped: steady offset = bias · τ² = 1e-4 · 1e4 ≈ 1 m.
    assert!(
        damped < 1.5 * 10.0 * UG * 100.0 * 100.0 + 1e-3,
        "damped {damped} m"
    );
    let _ = e;
}
