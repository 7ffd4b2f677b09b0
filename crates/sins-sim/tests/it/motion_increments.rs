//! Physics of the motion timeline and of the exact increments.

use crate::common;

use common::*;
use nalgebra::{Rotation3, Unit};
use sins_imu::ForwardModel;
use sins_nav::earth::EarthAt;
use sins_nav::{DEG, Mat3, Vec3};
use sins_sim::{IncrementIntegrator, MotionTimeline, simulate_to_vec};

/// `C_n^b ω_ie^n` and `C_n^b (−g^n)` for the attitude `c` (= C_b^n) at the test site.
fn earth_and_force_body(c: &Mat3) -> (Vec3, Vec3) {
    let e = EarthAt::new(site().lat_rad, site().height_m);
    (
        c.transpose() * e.earth_rate_ned_radps,
        c.transpose() * Vec3::new(0.0, 0.0, -e.gravity_mps2),
    )
}

/// `∫_0^T exp(−[u×] ω τ) v dτ` in closed form (ω signed).
fn rotating_integral(u: &Vec3, omega: f64, t: f64, v: &Vec3) -> Vec3 {
    let par = u * u.dot(v);
    let perp = v - par;
    let cross = u.cross(v);
    let wt = omega * t;
    par * t + perp * (wt.sin() / omega) - cross * ((1.0 - wt.cos()) / omega)
}

#[test]
fn dwell_sums_equal_earth_rate_and_gravity_times_duration() {
    let duration_s = 100.0;
    let sc = scenario(vec![dwell(duration_s, "stationary")]);
    let out = simulate_to_vec(&sc, ForwardModel::new(sc.truth)).unwrap();
    assert_eq!(out.len(), 20_000);
    let c = start_attitude().to_rotation_matrix().into_inner();
    let (e, f) = earth_and_force_body(&c);
    let sum_th: Vec3 = out.samples.iter().map(|s| s.dtheta_rad).sum();
    let sum_dv: Vec3 = out.samples.iter().map(|s| s.dv_mps).sum();
    assert!(
        rel(&sum_th, &(e * duration_s)) < 1e-12,
        "{:e}",
        rel(&sum_th, &(e * duration_s))
    );
    assert!(
        rel(&sum_dv, &(f * duration_s)) < 1e-12,
        "{:e}",
        rel(&sum_dv, &(f * duration_s))
    );
    // At rest the specific force is exactly "up" with magnitude g.
    assert!((f.norm() - EarthAt::new(site().lat_rad, site().height_m).gravity_mps2).abs() < 1e-14);
}

/// Dwell, rotation, dwell: the sums of the increments against the closed-form integrals.
fn check_rotation(axis: [f64; 3], angle_deg: f64, rate_deg_s: f64) {
    let (pre_s, post_s) = (2.0, 3.0);
    let sc = scenario(vec![
        dwell(pre_s, "before"),
        rotate(axis, angle_deg, rate_deg_s, "rotation"),
        dwell(post_s, "after"),
    ]);
    let out = simulate_to_vec(&sc, ForwardModel::new(sc.truth)).unwrap();
    let timeline = MotionTimeline::new(&sc.motion).unwrap();
    let u = Vec3::from(axis);
    let angle = angle_deg * DEG;
    let omega = (rate_deg_s * DEG).copysign(angle);
    let t_rot = angle.abs() / (rate_deg_s * DEG);
    let c0 = start_attitude().to_rotation_matrix().into_inner();
    let c_end = c0 * Rotation3::from_axis_angle(&Unit::new_normalize(u), angle).into_inner();
    // End attitude: start · exp(axis · angle), independently of the simulator.
    let q_end = timeline.segment_start_ned_from_body(2).unwrap();
    let err = (q_end.to_rotation_matrix().into_inner() - c_end)
        .abs()
        .max();
    assert!(err < 1e-15, "end attitude error {err:e}");
    let near_end = timeline
        .eval(timeline.segment_end_s(1).unwrap() - 1e-6)
        .ned_from_body;
    assert!((near_end.angle_to(&q_end) - rate_deg_s * DEG * 1e-6).abs() < 1e-12);
    // Sums over the whole run.
    let total_s = out.len() as f64 / sc.rate_hz;
    let (e0, f0) = earth_and_force_body(&c0);
    let (e1, f1) = earth_and_force_body(&c_end);
    let tail_s = total_s - pre_s - t_rot;
    let want_th = e0 * pre_s + u * angle + rotating_integral(&u, omega, t_rot, &e0) + e1 * tail_s;
    let want_dv = f0 * pre_s + rotating_integral(&u, omega, t_rot, &f0) + f1 * tail_s;
    let sum_th: Vec3 = out.samples.iter().map(|s| s.dtheta_rad).sum();
    let sum_dv: Vec3 = out.samples.iter().map(|s| s.dv_mps).sum();
    assert!(
        rel(&sum_th, &want_th) < 1e-12,
        "dtheta {:e}",
        rel(&sum_th, &want_th)
    );
    assert!(
        rel(&sum_dv, &want_dv) < 1e-12,
        "dv {:e}",
        rel(&sum_dv, &want_dv)
    );
    // The Earth-rate part is resolved (it is ~1e-4 of the total): compare it alone.
    let earth_part = sum_th - u * angle;
    let want_earth = want_th - u * angle;
    assert!(
        rel(&earth_part, &want_earth) < 1e-9,
        "earth {:e}",
        rel(&earth_part, &want_earth)
    );
}

#[test]
fn rotation_90_deg_at_9_deg_s_about_body_y_matches_closed_form() {
    check_rotation([0.0, 1.0, 0.0], 90.0, 9.0);
}

#[test]
fn rotation_off_the_sample_grid_matches_closed_form() {
    // 90/7 s: both rate steps fall inside sample intervals.
    check_rotation([0.0, 0.0, -1.0], -90.0, 7.0);
    let s = 1.0 / 3f64.sqrt();
    check_rotation([s, -s, s], 123.4, 11.3);
}

/// Increments of pattern 3 over `n` samples starting at `t_start` with `nodes` nodes.
fn pattern3_increments(nodes: usize, n: usize) -> Vec<(Vec3, Vec3)> {
    let sc = scenario(vec![
        dwell(3600.0, "stationary"),
        pattern3(20.0, [0.3, -1.1, 2.0]),
    ]);
    let timeline = MotionTimeline::new(&sc.motion).unwrap();
    let integ = IncrementIntegrator::new(&timeline, &sc.site, nodes, 1.0 / sc.rate_hz).unwrap();
    let k0 = 3600 * 200 - 3; // start just before the vibration (the first interval is split)
    (k0..k0 + n)
        .map(|k| integ.increments(k as f64 / 200.0, (k + 1) as f64 / 200.0))
        .collect()
}

#[test]
fn quadrature_converges_on_pattern3_and_midpoint_rule_does_not() {
    let n = 4000;
    let six = pattern3_increments(6, n);
    let eight = pattern3_increments(8, n);
    let one = pattern3_increments(1, n);
    let worst = |a: &[(Vec3, Vec3)]| {
        a.iter()
            .zip(&eight)
            .fold((0.0f64, 0.0f64), |(wt, wv), (x, y)| {
                (wt.max(rel(&x.0, &y.0)), wv.max(rel(&x.1, &y.1)))
            })
    };
    let (th6, v6) = worst(&six);
    assert!(
        th6 < 2e-15 && v6 < 2e-15,
        "6 vs 8 nodes: dtheta {th6:e}, dv {v6:e}"
    );
    let (th1, v1) = worst(&one);
    eprintln!("6 vs 8 nodes: {th6:e} {v6:e}; 1 vs 8 nodes: {th1:e} {v1:e}");
    assert!(
        th1 > 1e-5 && v1 > 1e-7,
        "1 vs 8 nodes: dtheta {th1:e}, dv {v1:e}"
    );
    // The increments are large: rates up to ~630 deg/s.
    let max_rate = eight.iter().map(|x| x.0.norm() * 200.0).fold(0.0, f64::max);
    assert!(
        max_rate > 500.0 * DEG,
        "max mean rate {:.1} deg/s",
        max_rate / DEG
    );
}

#[test]
fn vibration_increments_match_fine_quadrature_of_the_closed_form_attitude() {
    let sc = scenario(vec![pattern3(5.0, [0.3, -1.1, 2.0])]);
    let timeline = MotionTimeline::new(&sc.motion).unwrap();
    let integ = IncrementIntegrator::new(&timeline, &sc.site, 6, 0.005).unwrap();
    let earth = EarthAt::new(site().lat_rad, site().height_m);
    let rule = sins_sim::gauss_legendre_unit(8).unwrap();
    for k in [0usize, 1, 17, 60, 111, 199] {
        let (t0, t1) = (k as f64 * 0.005, (k + 1) as f64 * 0.005);
        let (th, dv) = integ.increments(t0, t1);
        // Independent: composite 8-node rule on 64 pieces, attitude from the quaternion path.
        let (mut want_th, mut want_dv) = (Vec3::zeros(), Vec3::zeros());
        let m = 64;
        let hs = (t1 - t0) / m as f64;
        for p in 0..m {
            for &(u, w) in rule {
                let st = timeline.eval(t0 + (p as f64 + u) * hs);
                let c = st.ned_from_body.to_rotation_matrix().into_inner();
                want_th += (st.omega_nb_body_radps + c.transpose() * earth.earth_rate_ned_radps)
                    * (w * hs);
                want_dv += c.transpose() * Vec3::new(0.0, 0.0, -earth.gravity_mps2) * (w * hs);
            }
        }
        assert!(
            rel(&th, &want_th) < 1e-13,
            "k={k}: {:e}",
            rel(&th, &want_th)
        );
        assert!(
            rel(&dv, &want_dv) < 1e-13,
            "k={k}: {:e}",
            rel(&dv, &want_dv)
        );
    }
}

#[test]
fn vibration_body_rate_is_the_derivative_of_the_attitude() {
    let sc = scenario(vec![dwell(1.0, "s"), pattern3(5.0, [0.3, -1.1, 2.0])]);
    let timeline = MotionTimeline::new(&sc.motion).unwrap();
    let d = 1e-5;
    for t in [1.013, 1.5, 2.777, 4.2] {
        let st = timeline.eval(t);
        let q0 = timeline.eval(t - d).ned_from_body;
        let q1 = timeline.eval(t + d).ned_from_body;
        // Body rate: C^T dC/dt, i.e. the rotation vector of q(t-d)^-1 q(t+d) over 2d.
        let fd = (q0.inverse() * q1).scaled_axis() / (2.0 * d);
        let w = st.omega_nb_body_radps;
        assert!(w.norm() > 1.0, "rate too small to test at t={t}");
        assert!(
            (fd - w).norm() < 1e-6 * w.norm(),
            "t={t}: fd {fd:?} vs {w:?}"
        );
        assert_eq!(st.segment_index, 1);
    }
}

#[test]
fn vibration_starts_continuously_and_ends_at_start_times_r_of_theta_t() {
    let phase = [0.3, -1.1, 2.0];
    let duration_s = 1.234_567;
    let sc = scenario(vec![
        dwell(1.0, "s"),
        pattern3(duration_s, phase),
        dwell(1.0, "s"),
    ]);
    let timeline = MotionTimeline::new(&sc.motion).unwrap();
    let start = start_attitude();
    // Continuous at the start.
    assert!(timeline.eval(1.0 + 1e-9).ned_from_body.angle_to(&start) < 1e-6);
    // End: start · Rz(θz) Ry(θy) Rx(θx), built independently with nalgebra rotations.
    let amp = [8.0 * DEG, 9.0 * DEG, 15.0 * DEG];
    let per = [0.2, 0.1, 0.15];
    let theta: Vec<f64> = (0..3)
        .map(|j| {
            let w = std::f64::consts::TAU / per[j];
            amp[j] * (w * duration_s + phase[j]).sin() - amp[j] * phase[j].sin()
        })
        .collect();
    let r = Rotation3::from_axis_angle(&Vec3::z_axis(), theta[2])
        * Rotation3::from_axis_angle(&Vec3::y_axis(), theta[1])
        * Rotation3::from_axis_angle(&Vec3::x_axis(), theta[0]);
    let want = start.to_rotation_matrix() * r;
    let got = timeline
        .segment_start_ned_from_body(2)
        .unwrap()
        .to_rotation_matrix();
    let err = (got.into_inner() - want.into_inner()).abs().max();
    // The reference's own phase ω T + φ ≈ 77 rad is rounded to ~1e-14 rad.
    assert!(err < 1e-14, "end attitude error {err:e}");
    assert_eq!(timeline.segment_index_at(2.0 + duration_s), 2);
    assert!((timeline.total_duration_s() - (2.0 + duration_s)).abs() < 4e-15);
}
