//! Output safety end to end: a user's file or directory where an output goes is refused with
//! an error naming it and left untouched (never moved); stale temporaries of killed runs are
//! removed at the next run and named on stderr; a write that fails (a file-size limit, as on a
//! full disk or an exhausted quota) ends at once with a clear error, leaving the previous output
//! and no temporary behind; SIGINT removes the run's temporaries.

use crate::common;
use common::{csv_without_temperatures, exe, experiments, run, s};
use std::path::Path;
use std::time::{Duration, Instant};

/// A report configuration `mine` on a small CSV without temperatures under a 42-state set: it
/// fails in its run (after the output checks), in well under a second.
fn quick_config(dir: &Path) -> std::path::PathBuf {
    let csv = dir.join("nt.csv");
    csv_without_temperatures(&csv, 400);
    let config = dir.join("mine.toml");
    std::fs::write(
        &config,
        format!(
            "schema = 1\nname = \"mine\"\n[[parameter_set]]\nkey = \"42-state\"\nfile = \"{}\"\n\
             [navigation]\ndataset = [{{ name = \"run1\", path = \"nt.csv\" }}]\n",
            experiments().join("imu/paper_truth.toml").display()
        ),
    )
    .unwrap();
    config
}

/// A report configuration `mine` that runs: an error-free 30-state parameter set on a level,
/// stationary CSV without temperatures (20 min alignment, then `nav_s` of navigation).
fn runnable_config(dir: &Path, nav_s: usize) -> std::path::PathBuf {
    let csv = dir.join("long.csv");
    csv_without_temperatures(&csv, 200 * (1200 + nav_s));
    let ideal = std::fs::read_to_string(experiments().join("imu/ideal.toml")).unwrap();
    let head = ideal
        .split("[accel_temperature]")
        .next()
        .unwrap_or_default();
    std::fs::write(
        dir.join("ideal30.toml"),
        head.replace("model = \"42-state\"", "model = \"30-state\""),
    )
    .unwrap();
    let config = dir.join("mine.toml");
    std::fs::write(
        &config,
        "schema = 1\nname = \"mine\"\n[[parameter_set]]\nkey = \"ideal\"\nfile = \"ideal30.toml\"\n\
         [navigation]\ndataset = [{ name = \"run1\", path = \"long.csv\" }]\n",
    )
    .unwrap();
    config
}

fn hidden_entries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') && n != ".sinsbench-output")
        .collect()
}

/// `report`: a file, a link, another command's output and a directory with a subdirectory where
/// the report directory goes are each refused before the run, named, and left as they were.
#[test]
fn report_refuses_what_is_not_its_own_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    let config = quick_config(dir.path());
    let reports = dir.path().join("reports");
    std::fs::create_dir_all(&reports).unwrap();
    let target = reports.join("mine");
    type Case<'a> = (&'a str, &'a dyn Fn(&Path), &'a str);
    let cases: [Case; 4] = [
        (
            "file",
            &|t| std::fs::write(t, "my thesis").unwrap(),
            "is not a directory",
        ),
        (
            "link",
            &|t| std::os::unix::fs::symlink(dir.path().join("nt.csv"), t).unwrap(),
            "symbolic link",
        ),
        (
            "other command",
            &|t| {
                std::fs::create_dir(t).unwrap();
                std::fs::write(t.join(".sinsbench-output"), "diagnose\n").unwrap();
                std::fs::write(t.join("report.md"), "a diagnosis").unwrap();
            },
            "output of `sinsbench diagnose`",
        ),
        (
            "foreign directory",
            &|t| {
                std::fs::create_dir_all(t.join("photos")).unwrap();
                std::fs::write(t.join("photos/cat.jpg"), "meow").unwrap();
            },
            "which the command does not write",
        ),
    ];
    for (what, make, expected) in cases {
        make(&target);
        let before = snapshot(&target);
        let o = run(&[
            "report",
            "--config",
            &s(&config),
            "--reports-dir",
            &s(&reports),
        ]);
        assert_eq!(o.status.code(), Some(2), "{what}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(&s(&target)) && err.contains(expected) && err.contains("untouched"),
            "{what}: {err}"
        );
        assert_eq!(snapshot(&target), before, "{what}: left as it was");
        assert!(hidden_entries(&reports).is_empty(), "{what}: nothing aside");
        if std::fs::symlink_metadata(&target).is_ok_and(|m| m.is_dir()) {
            std::fs::remove_dir_all(&target).unwrap();
        } else {
            std::fs::remove_file(&target).unwrap();
        }
    }
}

/// Every file (and link target) under `p`, with its bytes; a link is recorded as a link.
fn snapshot(p: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let meta = std::fs::symlink_metadata(p).unwrap();
    if meta.file_type().is_symlink() {
        out.push((
            "->".into(),
            std::fs::read_link(p)
                .unwrap()
                .display()
                .to_string()
                .into_bytes(),
        ));
    } else if meta.is_dir() {
        for e in std::fs::read_dir(p).unwrap() {
            let e = e.unwrap();
            for (n, b) in snapshot(&e.path()) {
                out.push((format!("{}/{n}", e.file_name().to_string_lossy()), b));
            }
        }
    } else {
        out.push((String::new(), std::fs::read(p).unwrap()));
    }
    out.sort();
    out
}

/// `diagnose --out FILE`, `navigate --out FILE` and `calibrate` with a directory where its
/// recording goes are refused before any work, naming the path; nothing is written.
#[test]
fn diagnose_navigate_and_calibrate_refuse_the_wrong_kind_of_path() {
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("nt.csv");
    csv_without_temperatures(&csv, 400);
    let params = experiments().join("imu/paper_truth.toml");
    let file = dir.path().join("notes.txt");
    std::fs::write(&file, "keep me").unwrap();

    let o = run(&[
        "diagnose",
        "--dataset",
        &s(&csv),
        "--params",
        &s(&params),
        "--out",
        &s(&file),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&s(&file)) && err.contains("not a directory"),
        "{err}"
    );

    let o = run(&[
        "navigate",
        "--dataset",
        &s(&csv),
        "--params",
        &s(&params),
        "--out",
        &s(&file),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&s(&file)) && err.contains("not a directory"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep me");

    let rrd_dir = dir.path().join("cal.rrd");
    std::fs::create_dir(&rrd_dir).unwrap();
    let o = run(&[
        "calibrate",
        "--dataset",
        &s(&csv),
        "--states",
        "30",
        "--out",
        &s(&dir.path().join("cal.toml")),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&s(&rrd_dir)) && err.contains("is a directory"),
        "{err}"
    );
    assert!(!dir.path().join("cal.toml").exists(), "nothing written");
    assert!(hidden_entries(dir.path()).is_empty());
}

/// Temporaries left by a killed run (a process that no longer exists) are removed by the next
/// run in that directory and named on stderr; an old report moved aside by a run killed
/// between its two renames is put back.
#[test]
fn stale_temporaries_of_killed_runs_are_removed_at_the_next_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let config = quick_config(dir.path());
    let reports = dir.path().join("reports");
    // Above the kernel's largest pid (4194304): no such process can run.
    let dead = 4_999_999;
    std::fs::create_dir_all(reports.join(format!(".mine.partial-{dead}/sub"))).unwrap();
    std::fs::write(
        reports.join(format!(".mine.partial-{dead}/sub/x.rrd")),
        "half",
    )
    .unwrap();
    std::fs::write(reports.join(format!(".a.json.tmp-{dead}-3")), "half").unwrap();
    std::fs::create_dir_all(reports.join(format!(".old_one.old-{dead}"))).unwrap();
    std::fs::write(
        reports.join(format!(".old_one.old-{dead}/report.md")),
        "good",
    )
    .unwrap();
    std::fs::write(reports.join(".keep-me"), "a user's hidden file").unwrap();
    let o = run(&[
        "report",
        "--config",
        &s(&config),
        "--reports-dir",
        &s(&reports),
    ]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "the run itself fails (no temperatures)"
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&format!(".mine.partial-{dead}"))
            && err.contains(&format!(".a.json.tmp-{dead}-3"))
            && err.contains("restored"),
        "{err}"
    );
    assert_eq!(hidden_entries(&reports), vec![".keep-me".to_string()]);
    assert_eq!(
        std::fs::read_to_string(reports.join("old_one/report.md")).unwrap(),
        "good"
    );
}

/// A write that fails part-way (a 64 KiB file-size limit: the write returns EFBIG, as a full
/// disk returns ENOSPC) ends `report` within seconds with an error naming the file; the previous
/// report is left byte for byte and no temporary remains. Before, a failed `.rrd` flush hung.
#[test]
fn a_failed_write_ends_the_report_with_a_clear_error_and_no_leftovers() {
    let dir = tempfile::tempdir().expect("tempdir");
    let config = runnable_config(dir.path(), 120);
    let reports = dir.path().join("reports");
    std::fs::create_dir_all(reports.join("mine")).unwrap();
    std::fs::write(reports.join("mine/report.md"), "the good old report\n").unwrap();
    let before = snapshot(&reports.join("mine"));
    let started = Instant::now();
    let mut child = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -f 64; exec '{}' report --quiet --config '{}' --reports-dir '{}'",
            env!("CARGO_BIN_EXE_sinsbench"),
            s(&config),
            s(&reports)
        ))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let status = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break st;
        }
        if started.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("report did not end within 60 s of a failed write");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    eprintln!(
        "failed write: exit {:?} after {:.1} s: {}",
        status.code(),
        started.elapsed().as_secs_f64(),
        err.trim()
    );
    assert_eq!(status.code(), Some(2), "{err}");
    assert!(
        err.contains("File too large") && err.contains(".partial-"),
        "names the file being written and the cause: {err}"
    );
    assert_eq!(snapshot(&reports.join("mine")), before);
    assert!(hidden_entries(&reports).is_empty(), "no staging left");
}

/// SIGINT in the middle of a report removes its staging directory and temporary files; the
/// previous report stays.
#[test]
fn sigint_removes_the_runs_temporaries() {
    let dir = tempfile::tempdir().expect("tempdir");
    let config = runnable_config(dir.path(), 600);
    let reports = dir.path().join("reports");
    // One good run first, as the previous output.
    let o = run(&[
        "report",
        "--config",
        &s(&config),
        "--reports-dir",
        &s(&reports),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let before = snapshot(&reports.join("mine"));
    let mut stopped = 0;
    for delay_ms in [50u64, 150, 300, 600] {
        let mut child = exe()
            .args(["report", "--quiet", "--config", &s(&config)])
            .args(["--reports-dir", &s(&reports)])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(delay_ms));
        if child.try_wait().unwrap().is_none() {
            let k = std::process::Command::new("kill")
                .args(["-s", "INT", &child.id().to_string()])
                .status()
                .unwrap();
            assert!(k.success());
            let st = child.wait().unwrap();
            if st.code() == Some(130) {
                stopped += 1;
            }
        } else {
            child.wait().unwrap();
        }
        assert!(hidden_entries(&reports).is_empty(), "after {delay_ms} ms");
        assert!(hidden_entries(&reports.join("mine")).is_empty());
        let now = snapshot(&reports.join("mine"));
        let names = |v: &[(String, Vec<u8>)]| v.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
        assert_eq!(names(&now), names(&before), "a complete report");
    }
    assert!(
        stopped >= 1,
        "at least one run was stopped by SIGINT (exit 130)"
    );
}
