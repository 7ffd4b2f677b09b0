//! The diagnosis through files: a short navigation run with a hidden gyro bias temperature
//! coefficient, written as a dataset, is diagnosed from the file and the effect is identified
//! with its magnitude; the same run without the effect shows no gap. The outputs are written
//! and (when Rerun's reader is installed) the recording verifies.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test or an example is its failure message

use sins_diag::input::DiagnoseConfig;
use sins_diag::noise::NoiseSpec;
use sins_diag::report::Verdict;
use sins_gap::{DiagnoseRequest, diagnose_datasets, write_diagnosis};
use sins_imu::{EffectKind, EffectSpec};
use sins_sim::MotionSegment;
use std::path::{Path, PathBuf};

struct Quiet;
impl sins_report::Progress for Quiet {
    fn begin(&mut self, _: &str, _: u64) {}
    fn advance(&mut self, _: u64) {}
    fn end(&mut self) {}
}

fn experiments() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments")
}

/// nav1 of the paper's navigation experiment cut to 3 h: alignment, 2 h stationary, 40 min of
/// pattern 1; the chamber cools as in nav1.
fn short_nav(effect: Option<EffectSpec>, dir: &Path) -> PathBuf {
    let exp = sins_config::load_experiment(experiments().join("paper_navigation.toml")).unwrap();
    let mut sc = exp.scenarios[0].clone();
    let mut segs = Vec::new();
    for s in sc.motion.segments.iter().take(3) {
        let mut s = s.clone();
        match &mut s {
            MotionSegment::Dwell { duration_s, label } if label == "stationary" => {
                *duration_s = 7200.0
            }
            MotionSegment::Vibrate { duration_s, .. } => *duration_s = 2400.0,
            _ => {}
        }
        segs.push(s);
    }
    sc.motion.segments = segs;
    sc.effects.extend(effect);
    let file = dir.join(format!("nav_{}.parquet", sc.effects.len()));
    sins_report::simulate_to_dataset("short", &sc, &file, &mut Quiet).unwrap();
    file
}

/// The paper navigation experiment's sensor noise (the twin's).
fn paper_noise() -> NoiseSpec {
    let exp = sins_config::load_experiment(experiments().join("paper_navigation.toml")).unwrap();
    NoiseSpec::from(&exp.scenarios[0].noise)
}

fn request(file: PathBuf) -> DiagnoseRequest {
    let truth = sins_config::load_params(experiments().join("imu/paper_truth.toml")).unwrap();
    DiagnoseRequest {
        datasets: vec![("short".into(), file)],
        params: truth.params,
        param_sigma: None,
        param_covariance: None,
        calibration_run: None,
        config: DiagnoseConfig::default(),
    }
}

#[test]
fn hidden_gyro_temperature_coefficient_is_found_from_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let kind = EffectKind::GyroBiasTemp;
    let magnitude = 10.0 * kind.typical_magnitude(); // deg/h/degC on x
    let spec = EffectSpec::unit(kind, 0).scaled(kind.unit().to_si(magnitude));
    let o = diagnose_datasets(&request(short_nav(Some(spec), dir.path())), paper_noise()).unwrap();
    let by = match &o.diagnosis.verdict {
        Verdict::Explained { by } | Verdict::PartlyExplained { by } => by.clone(),
        v => panic!("expected the effect to be found, got {v:?}"),
    };
    assert_eq!(by, kind.name());
    let c = &o.diagnosis.candidates[0];
    assert_eq!(c.kind, kind.name());
    let x = &c.components[0];
    let sigma = x.sigma.expect("identifiable");
    assert!(
        (x.value - magnitude).abs() <= 3.0 * sigma,
        "fitted {} ± {sigma}, hidden {magnitude}",
        x.value
    );
    let out = write_diagnosis(dir.path(), "diag", &o).unwrap();
    for f in [
        "report.md",
        "diagnosis.json",
        "diagnosis.rrd",
        "gap_short.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("gyro_bias_temp"));
    let required = std::env::var("SINSBENCH_RRD_VERIFY").is_ok_and(|v| v == "required");
    match std::process::Command::new("rerun")
        .args(["rrd", "verify"])
        .arg(out.join("diagnosis.rrd"))
        .output()
    {
        Ok(r) => assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr)),
        Err(e) => assert!(!required, "rerun is required: {e}"),
    }
}

#[test]
fn the_same_run_without_the_effect_shows_no_gap() {
    let dir = tempfile::tempdir().unwrap();
    let o = diagnose_datasets(&request(short_nav(None, dir.path())), paper_noise()).unwrap();
    assert_eq!(
        o.diagnosis.verdict,
        Verdict::NoSignificantGap,
        "{:?}",
        o.diagnosis.null_test
    );
}
