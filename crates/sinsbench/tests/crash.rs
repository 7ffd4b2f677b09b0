//! Crash consistency: `report` and `calibrate` killed at pseudo-random moments (a fixed seed;
//! SIGKILL and SIGINT mixed), at least 20 times each. After every kill and the cleanup the next
//! run does ([`sins_config::files::sweep_stale`], what every command runs in its output
//! directories), the previous good output must be there byte for byte (or, when the kill came
//! after the new output was renamed into place, a complete new output whose files equal the
//! previous ones except the `.rrd` recordings, which carry fresh ids and must decode completely),
//! and no temporary file or staging directory may remain. A SIGINT must leave nothing behind
//! even before that cleanup. The counts are printed.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test or an example is its failure message

mod common;
use common::{exe, s, short_calibration_experiment, simulate_into};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Every file under `dir` (relative name, bytes); names starting with '.' other than the
/// output marker count as leftovers and are returned separately.
fn scan(
    dir: &Path,
    prefix: &str,
    files: &mut BTreeMap<String, Vec<u8>>,
    leftovers: &mut Vec<String>,
) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        let rel = format!("{prefix}{name}");
        if name.starts_with('.') && name != ".sinsbench-output" {
            leftovers.push(rel);
            continue;
        }
        if e.file_type().unwrap().is_dir() {
            scan(&e.path(), &format!("{rel}/"), files, leftovers);
        } else {
            files.insert(rel, std::fs::read(e.path()).unwrap());
        }
    }
}

/// SplitMix64: the kill schedule is the same on every run of the test.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[derive(Default, Debug)]
struct Counts {
    kills: usize,
    sigkill: usize,
    sigint: usize,
    finished_before_kill: usize,
    replaced_by_new: usize,
    damaged: usize,
    leftovers_after_sigint: usize,
    leftovers_after_cleanup: usize,
}

/// The part of an output file that must not change between runs: everything but the wall times
/// at the end of `report.md` (its "Run time" section).
fn stable<'a>(name: &str, bytes: &'a [u8]) -> &'a [u8] {
    let marker = b"\n## Run time\n";
    if name.ends_with("report.md")
        && let Some(i) = bytes.windows(marker.len()).position(|w| w == marker)
    {
        return &bytes[..i];
    }
    bytes
}

/// Whether `now` is the previous good output `good` byte for byte, or a complete new one (same
/// names, same bytes except `.rrd`, whose recording decodes completely, and the wall times in
/// `report.md`).
fn judge(
    good: &BTreeMap<String, Vec<u8>>,
    now: &BTreeMap<String, Vec<u8>>,
    root: &Path,
) -> Result<bool, String> {
    if now == good {
        return Ok(false);
    }
    if now.keys().ne(good.keys()) {
        return Err(format!(
            "files differ: {:?} vs {:?}",
            now.keys().collect::<Vec<_>>(),
            good.keys().collect::<Vec<_>>()
        ));
    }
    for (name, bytes) in now {
        if name.ends_with(".rrd") {
            sins_viz::verify_recording(&root.join(name)).map_err(|e| e.to_string())?;
        } else if good.get(name).map(|g| stable(name, g)) != Some(stable(name, bytes)) {
            return Err(format!("{name} differs from the previous output"));
        }
    }
    Ok(true)
}

/// Runs `args` `n_kills` times (at least), killing each run at a moment drawn uniformly in
/// `[0, 1.1 * full_s)`; `outputs` is the directory whose files are the command's outputs and
/// `sweep_dir` where its temporaries go.
fn kill_loop(
    label: &str,
    args: &[String],
    outputs: &Path,
    sweep_dir: &Path,
    full_s: f64,
    rng: &mut Rng,
) -> Counts {
    let mut c = Counts::default();
    let mut good = BTreeMap::new();
    let mut left = Vec::new();
    scan(outputs, "", &mut good, &mut left);
    assert!(
        left.is_empty() && !good.is_empty(),
        "{label}: a clean good output first"
    );
    let mut attempts = 0;
    while c.kills < 20 && attempts < 60 {
        attempts += 1;
        let at = Duration::from_secs_f64(rng.unit() * 1.1 * full_s);
        let sigint = c.kills % 2 == 0;
        let mut child = exe()
            .args(args)
            .arg("--quiet")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(at);
        let killed = if child.try_wait().unwrap().is_none() {
            let sig = if sigint { "INT" } else { "KILL" };
            Command::new("kill")
                .args(["-s", sig, &child.id().to_string()])
                .status()
                .unwrap();
            true
        } else {
            false
        };
        child.wait().unwrap();
        if killed {
            c.kills += 1;
            if sigint {
                c.sigint += 1;
                let (mut f, mut l) = (BTreeMap::new(), Vec::new());
                scan(sweep_dir, "", &mut f, &mut l);
                if !l.is_empty() {
                    eprintln!("{label}: SIGINT at {at:?} left {l:?}");
                    c.leftovers_after_sigint += 1;
                }
            } else {
                c.sigkill += 1;
            }
        } else {
            c.finished_before_kill += 1;
        }
        // The next run's cleanup.
        sins_config::files::sweep_stale(sweep_dir);
        let (mut now, mut l) = (BTreeMap::new(), Vec::new());
        scan(sweep_dir, "", &mut BTreeMap::new(), &mut l);
        if !l.is_empty() {
            eprintln!("{label}: kill at {at:?} left {l:?} after the cleanup");
            c.leftovers_after_cleanup += 1;
        }
        scan(outputs, "", &mut now, &mut Vec::new());
        match judge(&good, &now, outputs) {
            Ok(true) => {
                c.replaced_by_new += 1;
                good = now;
            }
            Ok(false) => {}
            Err(e) => {
                eprintln!("{label}: kill at {at:?} damaged the output: {e}");
                c.damaged += 1;
            }
        }
    }
    eprintln!(
        "crash consistency, {label}: {} kills ({} SIGKILL, {} SIGINT; {} runs ended before their kill), \
         {} damaged outputs, {} leftovers after SIGINT, {} leftovers after the next run's cleanup, \
         {} kills after the new output was in place",
        c.kills,
        c.sigkill,
        c.sigint,
        c.finished_before_kill,
        c.damaged,
        c.leftovers_after_sigint,
        c.leftovers_after_cleanup,
        c.replaced_by_new
    );
    c
}

/// Runs `args` to the end and returns its wall time.
fn timed_run(args: &[String]) -> f64 {
    let t = Instant::now();
    let o = exe().args(args).arg("--quiet").output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    t.elapsed().as_secs_f64()
}

#[test]
fn killed_report_and_calibrate_leave_the_previous_output_intact() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exp = short_calibration_experiment(dir.path());
    let data = dir.path().join("data");
    simulate_into(&exp, &data);
    let mut rng = Rng(20_240_514);

    // calibrate: parameter file, history and recording in cal/.
    let cal_dir = dir.path().join("cal");
    std::fs::create_dir_all(&cal_dir).unwrap();
    let cal_args: Vec<String> = [
        "calibrate",
        "--dataset",
        &s(&data.join("cal1.parquet")),
        "--states",
        "30",
        "--out",
        &s(&cal_dir.join("cal.toml")),
    ]
    .map(String::from)
    .to_vec();
    let full = timed_run(&cal_args);
    let cal = kill_loop("calibrate", &cal_args, &cal_dir, &cal_dir, full, &mut rng);

    // report: the user's own parameter files on the same dataset.
    let imu = common::experiments().join("imu");
    let config = dir.path().join("own.toml");
    std::fs::write(
        &config,
        format!(
            "schema = 1\nname = \"own\"\n\
             [[parameter_set]]\nkey = \"none\"\nfile = \"{}\"\n\
             [[parameter_set]]\nkey = \"truth\"\nfile = \"{}\"\n\
             [navigation]\ndataset = [{{ name = \"cal\", path = \"data/cal1.parquet\" }}]\n",
            imu.join("ideal.toml").display(),
            imu.join("paper_table1.toml").display()
        ),
    )
    .unwrap();
    let reports = dir.path().join("reports");
    let rep_args: Vec<String> = [
        "report",
        "--config",
        &s(&config),
        "--reports-dir",
        &s(&reports),
    ]
    .map(String::from)
    .to_vec();
    let full = timed_run(&rep_args);
    let rep = kill_loop(
        "report",
        &rep_args,
        &reports.join("own"),
        &reports,
        full,
        &mut rng,
    );

    for (label, c) in [("calibrate", &cal), ("report", &rep)] {
        assert!(c.kills >= 20, "{label}: {c:?}");
        assert!(
            c.sigkill >= 5 && c.sigint >= 5,
            "{label}: both signals: {c:?}"
        );
        assert_eq!(c.damaged, 0, "{label}: {c:?}");
        assert_eq!(c.leftovers_after_sigint, 0, "{label}: {c:?}");
        assert_eq!(c.leftovers_after_cleanup, 0, "{label}: {c:?}");
    }
}
