//! Helpers shared by the CLI tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The sinsbench binary under test.
pub fn exe() -> Command {
    Command::new(env!("CARGO_BIN_EXE_sinsbench"))
}

/// Run the binary with `args` and `--quiet` (no progress bars), capturing its output.
pub fn run<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> std::process::Output {
    exe()
        .args(args)
        .arg("--quiet")
        .output()
        .expect("run sinsbench")
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> String {
    p.display().to_string()
}

/// The repository's experiments/ folder.
pub fn experiments() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../experiments")
        .canonicalize()
        .expect("experiments/")
}

/// Check an .rrd with Rerun's own reader (`rerun rrd verify`, PyPI rerun-sdk 0.36.3). With
/// `SINSBENCH_RRD_VERIFY=required` (set by scripts/test, hence CI) a missing reader fails the
/// test; otherwise the check is skipped with a note.
pub fn verify_rrd(path: &Path) {
    let required = std::env::var("SINSBENCH_RRD_VERIFY").is_ok_and(|v| v == "required");
    match Command::new("rerun")
        .args(["rrd", "verify"])
        .arg(path)
        .output()
    {
        Ok(o) => assert!(
            o.status.success(),
            "rerun rrd verify {} failed:\n{}{}",
            path.display(),
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ),
        Err(e) if required => {
            panic!("rerun (PyPI rerun-sdk 0.36.3) is required to verify .rrd files: {e}")
        }
        Err(e) => eprintln!("note: not verifying {} with rerun ({e})", path.display()),
    }
}

/// A CSV dataset of a level, stationary IMU without temperature columns (`n` samples, 200 Hz).
pub fn csv_without_temperatures(path: &Path, n: usize) {
    let mut text = String::from(
        "# sinsbench.schema_version = 1\n# sinsbench.sample_rate_hz = 200\n# sinsbench.site_latitude_deg = 28.22\n\
         # sinsbench.site_longitude_deg = 112.99\n# sinsbench.site_height_m = 60\n# sinsbench.description = no temps\n\
         t_s,dtheta_x_rad,dtheta_y_rad,dtheta_z_rad,dv_x_mps,dv_y_mps,dv_z_mps\n",
    );
    for k in 1..=n {
        text.push_str(&format!("{},0,3e-7,1.7e-7,0,0,0.049\n", k as f64 / 200.0));
    }
    std::fs::write(path, text).expect("write csv");
}

/// The paper's calibration experiment with one pass of the 18-step scheme (1.3 h instead of
/// 4.2 h), written into `dir`; returns its path.
pub fn short_calibration_experiment(dir: &Path) -> PathBuf {
    let exp_dir = experiments();
    let text = std::fs::read_to_string(exp_dir.join("paper_calibration.toml"))
        .unwrap()
        .replace("\"imu/", &format!("\"{}/imu/", exp_dir.display()))
        .replace("\"schemes/", &format!("\"{}/schemes/", exp_dir.display()))
        .replace("total_s = 13920.0", "total_s = 3480.0")
        .replace("repeat = 4", "repeat = 1")
        .replace("duration_s = 15120.0", "duration_s = 4680.0");
    let exp = dir.join("short_cal.toml");
    std::fs::write(&exp, text).unwrap();
    exp
}

/// Simulate `experiment` into `out` (asserting success).
pub fn simulate_into(experiment: &Path, out: &Path) {
    let o = exe()
        .args([
            "simulate",
            &experiment.display().to_string(),
            "--out",
            &out.display().to_string(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A `summary.json` with one experiment, `nav1`, whose maximum horizontal error is `with_nmi`
/// under "42-state" and `without_nmi` under "30-state".
pub fn gate_summary_json(with_nmi: f64, without_nmi: f64) -> String {
    sins_config::summary_to_json(&sins_harness::summary::Summary::example(
        with_nmi,
        without_nmi,
    ))
}

/// Exit code 2 and a message on stderr that contains every one of `needles`.
pub fn assert_refused(o: &std::process::Output, needles: &[&str]) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "exit code; stderr:\n{err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "'{n}' missing from:\n{err}");
    }
    err
}
