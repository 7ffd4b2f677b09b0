//! Output sets replaced whole or not at all, and one writer per output directory (issue 30):
//! an interrupted `simulate` leaves every previous dataset byte for byte and says so, and a
//! second `simulate` into a directory that another one is writing is refused at once, naming the
//! other process, in 20 trials out of 20; `calibration-report` is refused while its output is
//! locked.

use crate::common;
use common::{exe, leftovers, s, short_navigation_experiment, visible_files};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[cfg(unix)]
fn inode(p: &Path) -> Option<u64> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(p).ok().map(|m| m.ino())
}

/// Whether the run writing into `out` has finished its first dataset: `nav1.parquet` replaced
/// (a run that renames each dataset into place as it ends) or the second dataset begun in a
/// staging directory (a run that moves the set into place at the end).
fn first_run_done(out: &Path, nav1_inode: Option<u64>) -> bool {
    if inode(&out.join("nav1.parquet")) != nav1_inode {
        return true;
    }
    let Ok(entries) = std::fs::read_dir(out) else {
        return false;
    };
    entries.flatten().any(|e| {
        e.file_type().is_ok_and(|t| t.is_dir())
            && std::fs::read_dir(e.path()).is_ok_and(|r| {
                r.flatten()
                    .any(|f| f.file_name().to_string_lossy().contains("nav2"))
            })
    })
}

/// Finding 1 of issue 30: `simulate E --out D --seed 5` interrupted (SIGINT, then SIGTERM) once
/// its first run has finished must leave the three previous datasets byte for byte, remove its
/// temporaries, exit 128 + signal and say that the previous datasets are unchanged.
#[test]
fn an_interrupted_simulate_leaves_every_previous_dataset_unchanged() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exp = short_navigation_experiment(dir.path(), "nav.toml", 1200.0, 300.0, 120.0);
    let out = dir.path().join("D");
    common::simulate_into(&exp, &out);
    let good = visible_files(&out);
    assert_eq!(good.len(), 3, "{:?}", good.keys());
    let mut mixed = 0;
    for (signal, code) in [("INT", 130), ("TERM", 143), ("INT", 130), ("TERM", 143)] {
        let nav1 = inode(&out.join("nav1.parquet"));
        let child = exe()
            .args(["simulate", &s(&exp), "--out", &s(&out), "--seed", "5"])
            .arg("--quiet")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let t0 = Instant::now();
        while !first_run_done(&out, nav1) && t0.elapsed() < Duration::from_secs(60) {
            std::thread::sleep(Duration::from_millis(2));
        }
        Command::new("kill")
            .args(["-s", signal, &child.id().to_string()])
            .status()
            .unwrap();
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        let now = visible_files(&out);
        let changed: Vec<&String> = now
            .iter()
            .filter(|(k, v)| good.get(*k) != Some(*v))
            .map(|(k, _)| k)
            .collect();
        eprintln!(
            "SIG{signal} after the first run: exit {:?}, datasets changed: {changed:?}",
            o.status.code()
        );
        if !changed.is_empty() {
            mixed += 1;
            continue;
        }
        assert_eq!(o.status.code(), Some(code), "{err}");
        assert!(
            err.contains(&format!(
                "the previous datasets in {} are unchanged",
                s(&out)
            )),
            "{err}"
        );
        assert!(leftovers(&out).is_empty(), "{:?}", leftovers(&out));
        assert!(
            !out.join(".sinsbench.lock").exists(),
            "the lock file goes with an interrupted run"
        );
    }
    assert_eq!(
        mixed, 0,
        "interrupted runs that changed the previous datasets"
    );
}

/// Findings 4 and 6 of issue 30: two `simulate` into the same `--out`, 20 trials. The second is
/// refused every time (exit 2, naming the directory and the first process), the first completes,
/// and the directory holds exactly the first one's datasets.
#[test]
fn a_second_writer_into_the_same_directory_is_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exp = short_navigation_experiment(dir.path(), "nav.toml", 1200.0, 300.0, 120.0);
    let seeds = ["11", "12"];
    let mut reference: Vec<BTreeMap<String, Vec<u8>>> = Vec::new();
    for seed in seeds {
        let r = dir.path().join(format!("ref{seed}"));
        let o = common::run(&["simulate", &s(&exp), "--out", &s(&r), "--seed", seed]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        reference.push(visible_files(&r));
    }
    assert_ne!(reference[0], reference[1]);
    let out = dir.path().join("D");
    let lock = out.join(".sinsbench.lock");
    let (mut refused, mut both_ran, mut mixed, mut left) = (0, 0, 0, 0);
    for trial in 0..20 {
        let (first, second) = (trial % 2, 1 - trial % 2);
        let a = exe()
            .args([
                "simulate",
                &s(&exp),
                "--out",
                &s(&out),
                "--seed",
                seeds[first],
            ])
            .arg("--quiet")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // The first holds the lock once its file names it (or, for a build without locks, once
        // it has had time to start).
        let t0 = Instant::now();
        while t0.elapsed() < Duration::from_millis(300)
            && !std::fs::read_to_string(&lock)
                .is_ok_and(|t| t.starts_with(&format!("{}\n", a.id())))
        {
            std::thread::sleep(Duration::from_millis(1));
        }
        let b = common::run(&[
            "simulate",
            &s(&exp),
            "--out",
            &s(&out),
            "--seed",
            seeds[second],
        ]);
        let b_err = String::from_utf8_lossy(&b.stderr).into_owned();
        let a_pid = a.id();
        let a_out = a.wait_with_output().unwrap();
        assert!(
            a_out.status.success(),
            "the first writer fails: {}",
            String::from_utf8_lossy(&a_out.stderr)
        );
        if b.status.code() == Some(2)
            && b_err.contains(&s(&out))
            && b_err.contains(&format!("pid {a_pid}"))
            && b_err.contains("simulate")
        {
            refused += 1;
        } else {
            both_ran += 1;
            eprintln!(
                "trial {trial}: the second writer was not refused (exit {:?}): {b_err}",
                b.status.code()
            );
        }
        if visible_files(&out) != reference[first] {
            mixed += 1;
            eprintln!("trial {trial}: the directory does not hold the first writer's set");
        }
        if !leftovers(&out).is_empty() || lock.exists() {
            left += 1;
            eprintln!("trial {trial}: left {:?}", leftovers(&out));
        }
    }
    eprintln!(
        "concurrent writers: 20 trials, second refused {refused}, both ran {both_ran}, \
         directory not the first writer's set {mixed}, leftovers {left}"
    );
    assert_eq!((refused, both_ran, mixed, left), (20, 0, 0, 0));
}

/// Issue 30, one writer per output: `calibration-report`, whose output directory's lock is held
/// by another process, is refused at once (exit 2, naming the holder) and writes nothing (before
/// this session it took no lock, ran its study and replaced the other process's report). The lock is held here by the test itself, as a running
/// sinsbench would hold it (flock on the lock file, pid and command line inside).
#[test]
fn calibration_report_is_refused_while_another_holds_its_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    let reports = dir.path().join("reports");
    // calibration-report writes reports/calibration/ (its lock: reports/.calibration.sinsbench.lock).
    std::fs::create_dir_all(&reports).unwrap();
    let lock_path = reports.join(".calibration.sinsbench.lock");
    let mut lock = std::fs::File::create(&lock_path).unwrap();
    lock.try_lock().expect("the test takes the lock");
    std::io::Write::write_all(
        &mut lock,
        b"4242\nsinsbench calibration-report --seeds 10\n",
    )
    .unwrap();
    let o = common::run(&[
        "calibration-report",
        "--seeds",
        "2",
        "--reports-dir",
        &s(&reports),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("another sinsbench process") && err.contains("pid 4242"),
        "{err}"
    );
    assert!(!reports.join("calibration").exists());
    drop(lock);
}
