//! Helpers shared by the CLI tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The sinsbench binary under test; `SINSBENCH_TEST_BIN` names another one (e.g. a build from
/// before a fix, to see a test fail against it).
pub fn exe() -> Command {
    match std::env::var_os("SINSBENCH_TEST_BIN") {
        Some(bin) => Command::new(bin),
        None => Command::new(env!("CARGO_BIN_EXE_sinsbench")),
    }
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

/// The paper's three navigation runs (`nav1`, `nav2`, `nav3`, seeds 101-103) with every segment
/// scaled down: the stationary start `stationary_s` (alignment included), each vibration
/// pattern `pattern_s` and each stationary stretch between them `between_s`. Written into
/// `dir` as `name`; returns its path.
pub fn short_navigation_experiment(
    dir: &Path,
    name: &str,
    stationary_s: f64,
    pattern_s: f64,
    between_s: f64,
) -> PathBuf {
    let exp_dir = experiments();
    let text = std::fs::read_to_string(exp_dir.join("paper_navigation.toml")).unwrap();
    let align = (stationary_s / 2.0).min(1200.0);
    let text = text
        .replace("\"imu/", &format!("\"{}/imu/", exp_dir.display()))
        .replace("\"schemes/", &format!("\"{}/schemes/", exp_dir.display()))
        .replacen(
            "duration_s = 1200.0",
            &format!("duration_s = {align:.1}"),
            1,
        )
        .replacen(
            "duration_s = 16800.0",
            &format!("duration_s = {:.1}", stationary_s - align),
            1,
        )
        .replace(
            "duration_s = 9600.0",
            &format!("duration_s = {pattern_s:.1}"),
        )
        .replacen(
            "duration_h = 1.0\nlabel",
            &format!("duration_s = {between_s:.1}\nlabel"),
            2,
        );
    let exp = dir.join(name);
    std::fs::write(&exp, text).unwrap();
    exp
}

/// Whether this process runs as root (the full-disk tests mount a tmpfs).
pub fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// A small tmpfs mounted for a test, unmounted when dropped (also when the test panics).
pub struct Tmpfs {
    /// The mount point.
    pub path: PathBuf,
    _holder: tempfile::TempDir,
}

impl Tmpfs {
    /// Mounts a tmpfs of `size` (`mount -t tmpfs -o size=SIZE`), or says why not (not root, no
    /// permission to mount).
    pub fn mount(size: &str) -> Result<Self, String> {
        if !is_root() {
            return Err("not running as root".into());
        }
        let holder = tempfile::tempdir().map_err(|e| e.to_string())?;
        let path = holder.path().join("fs");
        std::fs::create_dir(&path).map_err(|e| e.to_string())?;
        let o = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(&path)
            .output()
            .map_err(|e| e.to_string())?;
        if !o.status.success() {
            return Err(format!(
                "mount failed: {}",
                String::from_utf8_lossy(&o.stderr).trim()
            ));
        }
        Ok(Self {
            path,
            _holder: holder,
        })
    }

    /// Fills the file system with `filler` until it is full, then gives back `leave` bytes
    /// (rounded to pages by tmpfs). Returns the filler's size.
    pub fn fill(&self, filler: &Path, leave: u64) -> u64 {
        use std::io::Write;
        let mut f = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(filler)
            .unwrap();
        let chunk = vec![0x5a_u8; 64 * 1024];
        loop {
            match f.write(&chunk) {
                Ok(0) => break,
                Ok(_) => {}
                Err(e) if e.raw_os_error() == Some(28) => break,
                Err(e) => panic!("filling {}: {e}", filler.display()),
            }
        }
        // Single bytes up to the last page.
        while f.write(&[0x5a]).is_ok_and(|n| n == 1) {}
        let len = f.metadata().unwrap().len();
        let keep = len.saturating_sub(leave);
        f.set_len(keep).unwrap();
        keep
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let o = Command::new("umount").arg(&self.path).output();
        if !o.as_ref().is_ok_and(|o| o.status.success()) {
            let _ = Command::new("umount").arg("-l").arg(&self.path).output();
        }
    }
}

/// Every file directly in `dir`: name and bytes; hidden names (temporaries) are left out, and so
/// are the output marker and lock files.
pub fn visible_files(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut m = std::collections::BTreeMap::new();
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if !name.starts_with('.') && e.file_type().is_ok_and(|t| t.is_file()) {
                m.insert(name, std::fs::read(e.path()).unwrap());
            }
        }
    }
    m
}

/// Hidden entries of `dir` that are neither the output marker nor a lock file: temporaries or
/// staging directories left behind.
pub fn leftovers(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| {
                    n.starts_with('.')
                        && n != ".sinsbench-output"
                        && !sins_files::lock::is_lock_file(n)
                })
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// A 30-state set with every coefficient zero (the ideal IMU without its temperature table).
pub fn ideal30(dir: &Path) -> PathBuf {
    let ideal = std::fs::read_to_string(experiments().join("imu/ideal.toml")).unwrap();
    let head = ideal
        .split("[accel_temperature]")
        .next()
        .unwrap_or_default();
    let p = dir.join("ideal30.toml");
    std::fs::write(
        &p,
        head.replace("model = \"42-state\"", "model = \"30-state\""),
    )
    .unwrap();
    p
}
