//! Probe: attitude drift and velocity (sculling) error of the increment algorithms under the
//! Table 4 vibration patterns, against the simulator's exact attitude.
//!
//! Each algorithm turns the simulated increments into per-update `(φ, ΔV)`. The attitude is
//! propagated exactly apart from them (`q ← exp(−ζ) q exp(φ)`, `ζ = ω_ie^n T`; no velocity
//! coupling), and the specific-force integral `Σ (C_b^n(t_k) ΔV − ½ ζ × C_b^n(t_k) ΔV)` uses the
//! true attitude at the update start, so the two errors isolate the coning and the
//! sculling/rotation errors of the algorithm. For a turntable at a fixed site the exact
//! specific-force integral is `−g^n T`.

use sins_imu::{Compensator, ImuErrorParams, ParamModel};
use sins_nav::attitude::{attitude_error_ned_rad, quat_from_rotation_vector};
use sins_nav::reconstruct::{ReconstructConfig, reconstruct_all};
use sins_nav::*;
use sins_sim::{MotionSegment, Simulator};
use std::path::PathBuf;

/// Table 4 patterns: amplitudes (deg) and periods (s) about x, y, z.
const PATTERNS: [([f64; 3], [f64; 3]); 3] = [
    ([2.0, 4.0, 2.0], [0.1, 0.2, 0.3]),
    ([6.0, 5.0, 6.0], [0.1, 0.2, 0.15]),
    ([8.0, 9.0, 15.0], [0.2, 0.1, 0.15]),
];

#[derive(Clone, Copy, Debug)]
enum Method {
    OnePlusPrevious,
    TwoSample,
    Reconstruct(ReconstructConfig),
}

/// Simulated compensated increments of a vibration and the true attitude at every boundary.
fn simulate(
    amp_deg: [f64; 3],
    period_s: [f64; 3],
    dur_s: f64,
    rate_hz: f64,
) -> (Vec<Increment>, Vec<Quat>, Geodetic) {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../experiments/error_free_navigation.toml");
    let mut sc = sins_config::load_experiment(p).unwrap().scenarios.remove(0);
    sc.motion.segments = vec![MotionSegment::Vibrate {
        duration_s: dur_s,
        amplitude_rad: Vec3::from(amp_deg) * DEG,
        period_s: Vec3::from(period_s),
        phase_rad: Vec3::zeros(),
        label: "v".into(),
    }];
    sc.with_reference = true;
    sc.rate_hz = rate_hz;
    let h = 1.0 / rate_hz;
    let mut sim = Simulator::from_scenario(&sc).unwrap();
    let comp = Compensator::new(ImuErrorParams::ideal(ParamModel::States30)).unwrap();
    let (mut incs, mut att) = (Vec::new(), vec![sc.motion.initial_ned_from_body]);
    sim.run(65536, |b| {
        for (s, r) in b.samples.iter().zip(b.reference.as_ref().unwrap()) {
            incs.push(Increment {
                dtheta_rad: comp.dtheta_rad(&s.dtheta_rad, h),
                dv_mps: comp.dv_mps(&s.dv_mps, h, &s.temp_degc),
            });
            att.push(r.ned_from_body);
        }
        Ok::<(), ()>(())
    })
    .unwrap();
    (incs, att, sc.site)
}

/// Per-update `(φ, ΔV)` and samples per update, as `mechanization.rs` computes them.
fn updates(incs: &[Increment], m: Method) -> (Vec<(Vec3, Vec3)>, usize) {
    match m {
        Method::OnePlusPrevious => {
            let mut prev: Option<Increment> = None;
            let out = incs
                .iter()
                .map(|c| {
                    let (th, v) = (c.dtheta_rad, c.dv_mps);
                    let (mut con, mut scul) = (Vec3::zeros(), Vec3::zeros());
                    if let Some(p) = prev {
                        con = p.dtheta_rad.cross(&th) / 12.0;
                        scul = (p.dtheta_rad.cross(&v) + p.dv_mps.cross(&th)) / 12.0;
                    }
                    prev = Some(*c);
                    (th + con, v + 0.5 * th.cross(&v) + scul)
                })
                .collect();
            (out, 1)
        }
        Method::TwoSample => {
            let out = incs
                .chunks_exact(2)
                .map(|s| {
                    let (a, b) = (s[0], s[1]);
                    let (th, v) = (a.dtheta_rad + b.dtheta_rad, a.dv_mps + b.dv_mps);
                    let con = 2.0 / 3.0 * a.dtheta_rad.cross(&b.dtheta_rad);
                    let scul =
                        2.0 / 3.0 * (a.dtheta_rad.cross(&b.dv_mps) + a.dv_mps.cross(&b.dtheta_rad));
                    (th + con, v + 0.5 * th.cross(&v) + scul)
                })
                .collect();
            (out, 2)
        }
        Method::Reconstruct(c) => {
            let out = reconstruct_all(c, incs, &[]);
            assert!(out.iter().all(|r| r.intervals == c.intervals_per_update));
            (
                out.iter().map(|r| (r.phi_rad, r.dv_body_mps)).collect(),
                c.intervals_per_update,
            )
        }
    }
}

/// Attitude drift (deg/h, NED components) and specific-force error (ug, NED components) of an
/// algorithm over the whole record.
fn probe(incs: &[Increment], att: &[Quat], site: &Geodetic, h: f64, m: Method) -> (Vec3, Vec3) {
    let (ups, step) = updates(incs, m);
    let earth = EarthAt::new(site.lat_rad, site.height_m);
    let zeta = earth.earth_rate_ned_radps * (h * step as f64);
    let q_nn = quat_from_rotation_vector(&(-zeta));
    let (mut q, mut dv) = (att[0], Vec3::zeros());
    for (u, (phi, dvb)) in ups.iter().enumerate() {
        let dvn = att[u * step] * dvb;
        dv += dvn - 0.5 * zeta.cross(&dvn);
        q = Quat::new_normalize((q_nn * q * quat_from_rotation_vector(phi)).into_inner());
    }
    let t = ups.len() as f64 * step as f64 * h;
    let e = attitude_error_ned_rad(&q, &att[ups.len() * step]);
    (
        e / t / DEG_PER_H,
        (dv + earth.gravity_ned_mps2() * t) / t / UG,
    )
}

#[test]
#[ignore = "exploration: drift and sculling error of every algorithm under patterns 1-3 (about a minute)"]
fn probe_patterns() {
    let d = ReconstructConfig::default();
    let methods = [
        ("1+prev", Method::OnePlusPrevious),
        ("2-sample", Method::TwoSample),
        (
            "recon L=6 S=1",
            Method::Reconstruct(ReconstructConfig { substeps: 1, ..d }),
        ),
        ("recon default", Method::Reconstruct(d)),
        (
            "recon L=8 S=4",
            Method::Reconstruct(ReconstructConfig {
                half_width: 8,
                substeps: 4,
                ..d
            }),
        ),
    ];
    for (i, &(amp, per)) in PATTERNS.iter().enumerate() {
        let (incs, att, site) = simulate(amp, per, 600.0, 200.0);
        for (name, m) in methods {
            let (a, v) = probe(&incs, &att, &site, 0.005, m);
            eprintln!(
                "pattern {} {name:<14} drift {:.2e} deg/h [{:+.1e} {:+.1e} {:+.1e}]  accel {:.2e} ug [{:+.1e} {:+.1e} {:+.1e}]",
                i + 1,
                a.norm(),
                a.x,
                a.y,
                a.z,
                v.norm(),
                v.x,
                v.y,
                v.z
            );
        }
    }
}

#[test]
#[ignore = "exploration: h^4 convergence of the classical algorithms under pattern 3"]
fn probe_rates() {
    for rate in [200.0, 400.0, 800.0, 1600.0] {
        let (incs, att, site) = simulate(PATTERNS[2].0, PATTERNS[2].1, 300.0, rate);
        for (name, m) in [
            ("1+prev", Method::OnePlusPrevious),
            ("2-sample", Method::TwoSample),
        ] {
            let (a, v) = probe(&incs, &att, &site, 1.0 / rate, m);
            eprintln!(
                "pattern 3 at {rate} Hz {name}: drift {:.3e} deg/h, accel {:.3e} ug",
                a.norm(),
                v.norm()
            );
        }
    }
}
