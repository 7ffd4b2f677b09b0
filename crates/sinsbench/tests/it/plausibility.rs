//! Plausibility and resource guards at the command line: absurd datasets and experiments are
//! refused with exit code 2 and a message naming the file, column/key and row, before anything
//! is written; `--align-s` below the coarse stage is refused with a message that says so.

use std::path::Path;

use crate::common;
use common::{assert_refused, csv_without_temperatures, experiments, run, s};

/// The paper's error-free navigation experiment with `from` replaced by `to`, written into `dir`
/// with its referenced files resolved against the repository.
fn experiment(dir: &Path, name: &str, from: &str, to: &str) -> std::path::PathBuf {
    let exp = experiments();
    let text = std::fs::read_to_string(exp.join("error_free_navigation.toml")).unwrap();
    assert!(text.contains(from), "experiment lacks {from:?}");
    let text = text
        .replacen(from, to, 1)
        .replace("imu/ideal.toml", &s(&exp.join("imu/ideal.toml")))
        .replace(
            "schemes/table4_vibration_patterns.csv",
            &s(&exp.join("schemes/table4_vibration_patterns.csv")),
        );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn navigate_refuses_a_dataset_with_an_absurd_increment_naming_column_and_row() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("spiky.csv");
    csv_without_temperatures(&csv, 400);
    let text = std::fs::read_to_string(&csv).unwrap();
    // Row 249 (line 257: 6 metadata lines and the header first) spins at 10 rad per sample.
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    lines[256] = lines[256].replacen(",0,3e-7,", ",10,3e-7,", 1);
    std::fs::write(&csv, lines.join("\n") + "\n").unwrap();
    let o = run(&["navigate", "--dataset", &s(&csv), "--align-s", "60"]);
    assert_refused(
        &o,
        &[
            "spiky.csv",
            "row 249 (line 257)",
            "'dtheta_x_rad'",
            "1000 deg/s",
        ],
    );
}

#[test]
fn navigate_refuses_an_alignment_shorter_than_its_coarse_stage() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("still.csv");
    csv_without_temperatures(&csv, 400);
    for align in ["30", "2"] {
        let o = run(&["navigate", "--dataset", &s(&csv), "--align-s", align]);
        let err = assert_refused(
            &o,
            &[
                &format!("--align-s {align}"),
                "at least 60 s",
                "coarse alignment",
            ],
        );
        assert!(!err.contains("were given"), "{err}");
    }
}

#[test]
fn simulate_refuses_output_above_the_configured_limit_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    let exp = experiment(dir.path(), "e.toml", "", "");
    let out = dir.path().join("out");
    // 15 h at 200 Hz is estimated at ~0.9 GB; a 0.1 GB limit refuses it.
    let o = run(&[
        "simulate",
        &s(&exp),
        "--out",
        &s(&out),
        "--max-output-gb",
        "0.1",
    ]);
    assert_refused(
        &o,
        &[
            "out",
            "estimated at up to 8",
            "MB",
            "configured limit of 100.0 MB",
        ],
    );
    assert!(!out.exists(), "nothing may be written");
    // The same limit from the environment.
    let o = common::exe()
        .args(["simulate", &s(&exp), "--out", &s(&out), "--quiet"])
        .env("SINSBENCH_MAX_OUTPUT_GB", "0.1")
        .output()
        .unwrap();
    assert_refused(&o, &["configured limit of 100.0 MB"]);
    assert!(!out.exists(), "nothing may be written");
}

#[test]
fn simulate_refuses_output_beyond_the_free_disk_space_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    // 300 days at 10 kHz: 2.6e11 rows, tens of TB.
    let exp = experiment(
        dir.path(),
        "huge.toml",
        "rate_hz = 200.0",
        "rate_hz = 10000.0",
    );
    let text = std::fs::read_to_string(&exp).unwrap().replacen(
        "duration_s = 16800.0",
        "duration_h = 7200.0",
        1,
    );
    std::fs::write(&exp, text).unwrap();
    let out = dir.path().join("out");
    let o = run(&["simulate", &s(&exp), "--out", &s(&out)]);
    assert_refused(
        &o,
        &["estimated at up to", "TB", "are free on the file system"],
    );
    assert!(!out.exists(), "nothing may be written");
}

#[test]
fn simulate_refuses_an_absurd_rate_or_duration_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let exp = experiment(dir.path(), "fast.toml", "rate_hz = 200.0", "rate_hz = 1e9");
    let out = dir.path().join("out");
    let o = run(&["simulate", &s(&exp), "--out", &s(&out)]);
    assert_refused(&o, &["fast.toml", "sampling.rate_hz", "10000 Hz maximum"]);
    let exp = experiment(
        dir.path(),
        "long.toml",
        "duration_s = 1200.0",
        "duration_s = 1e12",
    );
    let o = run(&["simulate", &s(&exp), "--out", &s(&out)]);
    assert_refused(
        &o,
        &["long.toml", "motion.segment[0].duration_s", "366 days"],
    );
    assert!(!out.exists(), "nothing may be written");
}
