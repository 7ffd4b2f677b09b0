//! Output to a pipe whose reader is gone (`sinsbench gate ... | head -1`): no panic, the
//! command's own exit code, and every file it was asked to write.

use std::path::{Path, PathBuf};
use std::process::Stdio;

use crate::common;
use common::{csv_without_temperatures, exe, experiments, gate_summary_json, s};

/// What a run with a closed stdout left behind.
struct Closed {
    code: Option<i32>,
    stderr: String,
}

/// Run sinsbench with stdout a pipe whose reader is closed before the child writes; with
/// `close_stderr`, stderr is such a pipe too.
fn run_closed<S: AsRef<std::ffi::OsStr>>(args: &[S], close_stderr: bool) -> Closed {
    let mut child = exe()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn sinsbench");
    drop(child.stdout.take());
    if close_stderr {
        drop(child.stderr.take());
    }
    let out = child.wait_with_output().expect("wait for sinsbench");
    Closed {
        code: out.status.code(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Exit code `code` and no panic (message or backtrace) on stderr.
fn assert_quiet_exit(c: &Closed, code: i32, what: &str) {
    assert!(
        !c.stderr.contains("panicked") && !c.stderr.contains("Broken pipe"),
        "{what}: panic on a closed stdout:\n{}",
        c.stderr
    );
    assert_eq!(c.code, Some(code), "{what}: exit code\n{}", c.stderr);
}

/// A summary with one experiment (2.11 / 3.38 nmi) and thresholds it passes or fails.
fn gate_files(dir: &Path) -> (PathBuf, PathBuf, PathBuf) {
    let summary = dir.join("summary.json");
    std::fs::write(&summary, gate_summary_json(2.11, 3.38)).unwrap();
    let pass = dir.join("pass.toml");
    std::fs::write(
        &pass,
        "schema = 1\n[default]\nmax_horizontal_nmi = { \"42-state\" = 2.5 }\n",
    )
    .unwrap();
    let fail = dir.join("fail.toml");
    std::fs::write(
        &fail,
        "schema = 1\n[default]\nmax_horizontal_nmi = { \"42-state\" = 1.0 }\n",
    )
    .unwrap();
    (summary, pass, fail)
}

#[test]
fn gate_keeps_its_exit_codes_when_stdout_is_closed() {
    let dir = tempfile::tempdir().unwrap();
    let (summary, pass, fail) = gate_files(dir.path());
    let junit = dir.path().join("gate.xml");
    let gate = |t: &Path| {
        [
            "gate",
            "--summary",
            &s(&summary),
            "--thresholds",
            &s(t),
            "--junit",
            &s(&junit),
        ]
        .map(String::from)
    };
    for close_stderr in [false, true] {
        let c = run_closed(&gate(&pass), close_stderr);
        assert_quiet_exit(&c, 0, "gate pass");
        let c = run_closed(&gate(&fail), close_stderr);
        assert_quiet_exit(&c, 1, "gate fail");
        let xml = std::fs::read_to_string(&junit).unwrap();
        assert!(xml.contains("<failure"), "the JUnit file is still written");
    }
    let missing = dir.path().join("missing.json");
    let c = run_closed(
        &["gate", "--summary", &s(&missing), "--thresholds", &s(&pass)],
        false,
    );
    assert_quiet_exit(&c, 2, "gate bad input");
    assert!(c.stderr.contains("missing.json"), "{}", c.stderr);
}

#[test]
fn navigate_prints_into_a_closed_pipe_without_panicking() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("still.csv");
    // 70 s: the self-alignment needs more than its 60 s coarse stage.
    csv_without_temperatures(&csv, 14_000);
    let out = dir.path().join("nav");
    let c = run_closed(
        &[
            "navigate",
            "--dataset",
            &s(&csv),
            "--align-s",
            "61",
            "--out",
            &s(&out),
            "--quiet",
        ],
        false,
    );
    assert_quiet_exit(&c, 0, "navigate");
    assert!(
        out.join("errors.parquet").is_file(),
        "the error track is written"
    );
}

/// Three runs of three seconds each (a dwell; noise and a chamber ramp).
fn tiny_three_run_experiment(dir: &Path) -> PathBuf {
    let exp = experiments();
    let text = format!(
        r#"schema = 1
name = "tiny"
description = "three runs of three seconds"
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
duration_s = 3.0
rate_degc_per_h = 10.0
[motion]
initial_attitude_deg = {{ pitch = 1.0, roll = -91.0, yaw = -91.0 }}
[[motion.segment]]
kind = "dwell"
duration_s = 3.0
label = "still"
[[run]]
name = "r1"
seed = 1
[[run]]
name = "r2"
seed = 2
[[run]]
name = "r3"
seed = 3
"#,
        truth = exp.join("imu/paper_truth.toml").display(),
    );
    let path = dir.join("tiny.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn simulate_writes_every_run_when_stdout_is_closed() {
    let dir = tempfile::tempdir().unwrap();
    let exp = tiny_three_run_experiment(dir.path());
    let out = dir.path().join("data");
    let c = run_closed(
        &[
            "simulate",
            &s(&exp),
            "--out",
            &s(&out),
            "--format",
            "csv",
            "--quiet",
        ],
        false,
    );
    assert_quiet_exit(&c, 0, "simulate");
    for run in ["r1", "r2", "r3"] {
        let f = out.join(format!("{run}.csv"));
        assert!(
            f.is_file(),
            "{} missing: simulate stopped early",
            f.display()
        );
    }
}

#[test]
fn help_and_version_into_a_closed_pipe() {
    for args in [
        &["--help"][..],
        &["--version"],
        &["gate", "--help"],
        &["help"],
    ] {
        let c = run_closed(args, false);
        assert_quiet_exit(&c, 0, &args.join(" "));
    }
}
