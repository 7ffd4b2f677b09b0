//! Shared helpers of the integration tests (included with `mod common;`).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The repository's `experiments/` folder.
pub fn experiments_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments")
}

/// Absolute path of a file under `experiments/`, as a TOML-safe string.
pub fn exp_file(rel: &str) -> String {
    let p = experiments_dir().join(rel);
    let p = p.canonicalize().unwrap_or(p);
    p.display().to_string().replace('\\', "/")
}

/// A small valid experiment referencing the repository's files by absolute path; `extra_top` is
/// inserted at the top level, `segments` replaces the motion segments.
pub fn experiment_text(extra_top: &str, segments: &str) -> String {
    format!(
        r#"schema = 1
name = "t"
{extra_top}
[site]
latitude_deg = 28.22
longitude_deg = 112.99

[sampling]
rate_hz = 200.0

[imu]
truth = "{truth}"

[thermal]
chamber_start_degc = 0.0
accel_time_constant_s = [600.0, 600.0, 600.0]

[[thermal.chamber]]
kind = "ramp"
duration_h = 1.0
rate_degc_per_h = 10.0

[motion]
initial_attitude_deg = {{ pitch = 0.0, roll = 0.0, yaw = 0.0 }}
vibration_patterns = "{patterns}"
{segments}

[[run]]
name = "r1"
seed = 1
"#,
        truth = exp_file("imu/paper_table1.toml"),
        patterns = exp_file("schemes/table4_vibration_patterns.csv"),
    )
}

/// Default motion segments for [`experiment_text`].
pub const SEGMENTS: &str = r#"
[[motion.segment]]
kind = "dwell"
duration_s = 60.0
label = "alignment"

[[motion.segment]]
kind = "rotate"
axis = [0, 0, 1]
angle_deg = 90.0
rate_deg_per_s = 9.0
"#;

/// Writes `text` as `name` in a fresh temporary directory; returns the directory guard and path.
pub fn write_temp(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join(name);
    std::fs::write(&path, text).expect("write temp file");
    (dir, path)
}
