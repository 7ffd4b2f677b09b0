//! Quantization-induced navigation error of the paper's navigation run: replay with and without
//! the gyro quantizer (same seed, so every other noise stream is identical), against the twin's
//! quantization-only spread. Run: `cargo run --release -p sins-diag --example qerr -- [seed]`

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test or an example is its failure message

use sins_diag::diagnose;
use sins_diag::input::{DiagnoseConfig, DiagnosisInput, RunData};
use sins_diag::noise::NoiseSpec;
use sins_diag::replay::{ReplaySetup, replay_run};
use sins_diag::source::SimSource;
use sins_diag::track_at;
use sins_imu::ForwardModel;
use sins_sim::{NoiseModel, Simulator};
use std::path::PathBuf;

fn main() {
    let seed: u64 = std::env::args()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let p =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/paper_navigation.toml");
    let mut sc = sins_config::load_experiment(p)
        .expect("experiment")
        .scenarios
        .remove(0);
    sc.seed += seed;
    let truth = sc.truth;
    let make = |sc: &sins_sim::Scenario| {
        SimSource::new(Simulator::new(sc, ForwardModel::new(sc.truth)).expect("scenario"))
    };
    let setup = ReplaySetup::default();
    let with_q = replay_run("q", &mut make(&sc), &truth, &sc.site, &setup).expect("replay");
    let mut noq = sc.clone();
    noq.noise.gyro_quantum_rad = 0.0;
    let without = replay_run("noq", &mut make(&noq), &truth, &sc.site, &setup).expect("replay");
    let mut qonly = sc.clone();
    qonly.noise = NoiseModel {
        gyro_quantum_rad: sc.noise.gyro_quantum_rad,
        ..Default::default()
    };
    let mut src = make(&qonly);
    let t = replay_run("qonly", &mut src, &truth, &sc.site, &setup).expect("replay");
    let mut noise = NoiseSpec::from(&qonly.noise);
    noise.gyro_quantum_factor = 1.0;
    let mut input = DiagnosisInput {
        runs: vec![RunData {
            name: "q".into(),
            segment_labels: src.segment_labels(),
            source: Box::new(src),
            site: sc.site,
            track: t.points.clone(),
            temperatures: Some(t.temperatures),
            twin_mean: None,
        }],
        params: truth,
        param_sigma: None,
        param_covariance: None,
        noise,
        calibration_run: None,
    };
    let cfg = DiagnoseConfig {
        floor_sigma_m: 1e-3,
        ..Default::default()
    };
    let d = diagnose(&mut input, &cfg).expect("diagnose");
    let s = &d.series[0];
    for k in (0..s.t_s.len()).step_by(180) {
        let tt = s.t_s[k];
        let (a, b) = (track_at(&with_q.points, tt), track_at(&without.points, tt));
        let q = track_at(&t.points, tt);
        println!(
            "{:6.0} {:<10} diff N {:8.2} E {:8.2}  quant-only N {:8.2} E {:8.2}  model(k=1) sigma N {:8.2} E {:8.2}",
            tt,
            s.segment[k],
            a[0] - b[0],
            a[1] - b[1],
            q[0],
            q[1],
            s.sigma_north_m[k],
            s.sigma_east_m[k]
        );
    }
}
