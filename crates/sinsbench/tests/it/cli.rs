//! End-to-end checks of the `sinsbench` binary: determinism of `simulate` and clear errors.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common;
use common::{csv_without_temperatures, exe, experiments};

/// A two-minute experiment with every ingredient: noise, quantization, thermal ramp, a
/// rotation and pattern-3 vibration.
fn short_experiment(dir: &Path, extra_top_level: &str) -> PathBuf {
    let exp = experiments();
    let text = format!(
        r#"schema = 1
name = "short"
description = "two minutes of everything"
{extra_top_level}
[site]
latitude_deg = 28.22
longitude_deg = 112.99
height_m = 60.0
[sampling]
rate_hz = 200.0
[imu]
truth = "{truth}"
[imu.noise]
gyro_arw_deg_per_sqrt_h = 0.0005
gyro_bias_instability_deg_per_h = 0.005
gyro_bias_correlation_s = 3600.0
gyro_quantum_arcsec = 1.0
accel_vrw_ug_per_sqrt_hz = 10.0
accel_bias_instability_ug = 20.0
accel_bias_correlation_s = 3600.0
[thermal]
chamber_start_degc = 0.0
accel_time_constant_s = [720.0, 1200.0, 1680.0]
thermometer_noise_degc = 0.01
[[thermal.chamber]]
kind = "ramp"
duration_s = 120.0
rate_degc_per_h = 10.0
[motion]
initial_attitude_deg = {{ pitch = 1.0, roll = -91.0, yaw = -91.0 }}
vibration_patterns = "{patterns}"
[[motion.segment]]
kind = "dwell"
duration_s = 60.0
label = "alignment"
[[motion.segment]]
kind = "rotate"
axis = [0.0, 1.0, 0.0]
angle_deg = 90.0
rate_deg_per_s = 9.0
label = "scheme"
[[motion.segment]]
kind = "vibrate"
pattern = 3
duration_s = 50.0
label = "pattern3"
[[run]]
name = "a"
seed = 7
"#,
        truth = exp.join("imu/paper_truth.toml").display(),
        patterns = exp.join("schemes/table4_vibration_patterns.csv").display(),
    );
    let path = dir.join("short.toml");
    std::fs::write(&path, text).expect("write experiment");
    path
}

fn simulate(exp: &Path, out: &Path, threads: &str, extra: &[&str]) -> Output {
    exe()
        .args([
            "simulate",
            &exp.display().to_string(),
            "--out",
            &out.display().to_string(),
            "--quiet",
        ])
        .args(extra)
        .env("POLARS_MAX_THREADS", threads)
        .output()
        .expect("run sinsbench")
}

#[test]
fn simulate_is_bit_identical_for_a_seed_whatever_the_thread_count() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exp = short_experiment(dir.path(), "");
    let one = dir.path().join("one");
    let two = dir.path().join("two");
    let other = dir.path().join("other");
    for (out, threads, extra) in [
        (&one, "1", &[][..]),
        (&two, "2", &[][..]),
        (&other, "2", &["--seed", "8"][..]),
    ] {
        let o = simulate(&exp, out, threads, extra);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let a = std::fs::read(one.join("a.parquet")).expect("dataset 1");
    let b = std::fs::read(two.join("a.parquet")).expect("dataset 2");
    let c = std::fs::read(other.join("a.parquet")).expect("dataset 3");
    assert!(a.len() > 100_000, "dataset too small: {} bytes", a.len());
    assert!(a == b, "same seed, different bytes (1 vs 2 threads)");
    assert!(a != c, "a different seed must change the data");
}

#[test]
fn csv_and_parquet_carry_the_same_samples() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exp = short_experiment(dir.path(), "");
    let pq = dir.path().join("pq");
    let csv = dir.path().join("csv");
    assert!(simulate(&exp, &pq, "2", &[]).status.success());
    assert!(
        simulate(&exp, &csv, "2", &["--format", "csv"])
            .status
            .success()
    );
    let (ia, a) = sins_data_read(&pq.join("a.parquet"));
    let (ib, b) = sins_data_read(&csv.join("a.csv"));
    assert_eq!(ia, ib);
    assert_eq!(a, b, "CSV and Parquet differ");
}

/// Navigate both files and compare the printed summaries (the same numbers to the last digit).
fn sins_data_read(path: &Path) -> (usize, String) {
    let o = exe()
        .args([
            "navigate",
            "--dataset",
            &path.display().to_string(),
            "--start",
            "truth",
            "--quiet",
        ])
        .output()
        .expect("run");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    let body: Vec<&str> = text.lines().skip(1).collect();
    (body.len(), body.join("\n"))
}

#[test]
fn unknown_experiment_key_names_the_key_and_the_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exp = short_experiment(dir.path(), "colour = \"blue\"");
    let o = simulate(&exp, &dir.path().join("x"), "2", &[]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("colour") && err.contains("short.toml"),
        "unclear error: {err}"
    );
    assert!(
        !dir.path().join("x/a.parquet").exists(),
        "no dataset may be written"
    );
}

#[test]
fn navigate_refuses_a_42_state_set_without_temperatures() {
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("nt.csv");
    csv_without_temperatures(&csv, 400);
    let params = experiments().join("imu/paper_truth.toml");
    let o = exe()
        .args([
            "navigate",
            "--dataset",
            &csv.display().to_string(),
            "--params",
            &params.display().to_string(),
            "--quiet",
        ])
        .output()
        .expect("run");
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("temperature") && err.contains("nt.csv"),
        "unclear error: {err}"
    );
}
