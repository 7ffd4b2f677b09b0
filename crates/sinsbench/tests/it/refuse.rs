//! Bad input is refused with exit code 2 and a message naming the file or the option: a gate
//! that would check nothing, a thresholds file that is bad before `gate --config` runs a
//! report, zero worker threads, a self-alignment time that is not a positive number.

use std::path::Path;

use crate::common;
use common::{assert_refused, csv_without_temperatures, experiments, gate_summary_json, run, s};

#[test]
fn gate_refuses_thresholds_that_check_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let summary = dir.path().join("summary.json");
    std::fs::write(&summary, gate_summary_json(2.0, 3.0)).unwrap();
    for (name, text) in [
        ("bare.toml", "schema = 1\n"),
        (
            "empty_tables.toml",
            "schema = 1\n[default]\n[experiment.nav1]\n",
        ),
    ] {
        let t = dir.path().join(name);
        std::fs::write(&t, text).unwrap();
        let o = run(&["gate", "--summary", &s(&summary), "--thresholds", &s(&t)]);
        assert_refused(&o, &[name, "no checks"]);
        assert!(o.stdout.is_empty(), "nothing may be reported as passed");
    }
}

#[test]
fn gate_refuses_a_summary_without_experiments() {
    let dir = tempfile::tempdir().unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&gate_summary_json(2.0, 3.0)).unwrap();
    json["experiments"] = serde_json::json!([]);
    let summary = dir.path().join("hollow.json");
    std::fs::write(&summary, json.to_string()).unwrap();
    let gate = experiments().join("harness/gate_paper.toml");
    let o = run(&["gate", "--summary", &s(&summary), "--thresholds", &s(&gate)]);
    assert_refused(&o, &["hollow.json", "no experiments", "gate_paper.toml"]);
}

/// A report configuration on a dataset (a 42-state set with a dataset that has no
/// temperatures, so that running the report would fail) whose `gate` key names `thresholds`.
fn config_with_gate(dir: &Path, thresholds: &str) -> std::path::PathBuf {
    csv_without_temperatures(&dir.join("nt.csv"), 400);
    let config = dir.join("mine.toml");
    std::fs::write(
        &config,
        format!(
            "schema = 1\nname = \"mine\"\ngate = \"{thresholds}\"\n[[parameter_set]]\nkey = \"42-state\"\n\
             file = \"{}\"\n[navigation]\ndataset = [{{ name = \"run1\", path = \"nt.csv\" }}]\n",
            experiments().join("imu/ideal.toml").display()
        ),
    )
    .unwrap();
    config
}

#[test]
fn gate_config_checks_the_thresholds_before_running_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let reports = dir.path().join("reports");
    std::fs::write(dir.path().join("hollow.toml"), "schema = 1\n").unwrap();
    for (thresholds, needles) in [
        ("absent.toml", &["absent.toml"][..]),
        ("hollow.toml", &["hollow.toml", "no checks"][..]),
    ] {
        let config = config_with_gate(dir.path(), thresholds);
        let o = run(&[
            "gate",
            "--config",
            &s(&config),
            "--reports-dir",
            &s(&reports),
        ]);
        let err = assert_refused(&o, needles);
        assert!(
            !err.contains("temperature"),
            "the report ran before the thresholds were checked:\n{err}"
        );
    }
    let o = run(&[
        "gate",
        "--config",
        &s(&config_with_gate(dir.path(), "hollow.toml")),
        "--thresholds",
        &s(&dir.path().join("gone.toml")),
        "--reports-dir",
        &s(&reports),
    ]);
    assert_refused(&o, &["gone.toml"]);
    assert!(!reports.join("mine").exists(), "no report may be written");
}

#[test]
fn zero_worker_threads_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("d.csv");
    csv_without_temperatures(&csv, 400);
    let (d, params) = (s(&csv), s(&experiments().join("imu/ideal.toml")));
    let commands: [&[&str]; 3] = [
        &["navigate", "--dataset", &d],
        &["calibration-report"],
        &["diagnose", "--dataset", &d, "--params", &params],
    ];
    for command in commands {
        let o = run(&[command, &["--threads", "0"]].concat());
        assert_refused(&o, &["--threads", "0"]);
    }
}

#[test]
fn align_s_must_be_a_positive_finite_number() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("d.csv");
    csv_without_temperatures(&csv, 400);
    for (value, why) in [
        ("-5", "greater than 0"),
        ("0", "greater than 0"),
        ("NaN", "not a finite number"),
        ("inf", "not a finite number"),
        ("ten", "not a number"),
    ] {
        let (d, joined) = (s(&csv), format!("--align-s={value}"));
        for args in [
            vec!["navigate", "--dataset", d.as_str(), "--align-s", value],
            vec!["navigate", "--dataset", d.as_str(), joined.as_str()],
        ] {
            let o = run(&args);
            assert_refused(&o, &["--align-s", why]);
        }
    }
}
