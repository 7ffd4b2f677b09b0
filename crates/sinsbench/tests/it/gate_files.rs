//! `sinsbench gate` and its files: the JUnit report is written aside and renamed into place, and
//! never over the summary, the thresholds or a file the gate did not write (exit 2); threshold
//! keys that match nothing in the summary are bad input (exit 2); the PASS/FAIL lines come
//! before any file is written, and a JUnit report that cannot be written keeps the verdict's
//! exit code (a failed gate 1, a passed one 2).

use crate::common;
use common::{assert_refused, gate_summary_json, run, s};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

/// A summary (nav1: 42-state 2.11 nmi, 30-state 3.38 nmi) and two thresholds files: one it
/// passes (42-state ≤ 2.65 nmi), one it fails (42-state ≤ 1.0 nmi).
fn gate_files(dir: &Path) -> (PathBuf, PathBuf, PathBuf) {
    let summary = dir.join("summary.json");
    std::fs::write(&summary, gate_summary_json(2.11, 3.38)).unwrap();
    let pass = dir.join("pass.toml");
    std::fs::write(
        &pass,
        "schema = 1\n[default]\nmax_horizontal_nmi = { \"42-state\" = 2.65 }\n",
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

fn gate(summary: &Path, thresholds: &Path, junit: &Path) -> std::process::Output {
    run(&[
        "gate",
        "--summary",
        &s(summary),
        "--thresholds",
        &s(thresholds),
        "--junit",
        &s(junit),
    ])
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn junit_never_replaces_an_input_or_a_file_the_gate_did_not_write() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (summary, pass, _) = gate_files(dir);
    let summary_text = std::fs::read(&summary).unwrap();
    let pass_text = std::fs::read(&pass).unwrap();
    std::fs::create_dir(dir.join("sub")).unwrap();
    std::os::unix::fs::symlink(&summary, dir.join("link.xml")).unwrap();
    std::fs::hard_link(&pass, dir.join("hard.xml")).unwrap();
    // The same files by other names: another spelling, a symbolic link, a hard link.
    for (junit, what) in [
        (summary.clone(), "the summary of this gate"),
        (dir.join("sub/../summary.json"), "the summary of this gate"),
        (dir.join("link.xml"), "the summary of this gate"),
        (pass.clone(), "the thresholds of this gate"),
        (dir.join("hard.xml"), "the thresholds of this gate"),
    ] {
        let o = gate(&summary, &pass, &junit);
        assert_refused(&o, &[&s(&junit), what, "never writes over its input"]);
        assert!(o.stdout.is_empty(), "refused before any verdict");
    }
    // A file the gate did not write, and a directory.
    let foreign = dir.join("results.xml");
    std::fs::write(
        &foreign,
        "<testsuites><testsuite name=\"unit\"/></testsuites>\n",
    )
    .unwrap();
    let o = gate(&summary, &pass, &foreign);
    assert_refused(
        &o,
        &[
            "results.xml",
            "is not a JUnit report of `sinsbench gate`",
            "left untouched",
        ],
    );
    let o = gate(&summary, &pass, &dir.join("sub"));
    assert_refused(&o, &["sub", "is a directory"]);
    assert_eq!(std::fs::read(&summary).unwrap(), summary_text);
    assert_eq!(std::fs::read(&pass).unwrap(), pass_text);
    assert_eq!(
        std::fs::read_to_string(&foreign).unwrap(),
        "<testsuites><testsuite name=\"unit\"/></testsuites>\n"
    );
    assert_eq!(
        names(dir),
        [
            "fail.toml",
            "hard.xml",
            "link.xml",
            "pass.toml",
            "results.xml",
            "sub",
            "summary.json"
        ]
    );
}

#[test]
fn junit_is_written_aside_and_replaces_only_its_own_report() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (summary, pass, fail) = gate_files(dir);
    let junit = dir.join("gate.xml");
    assert_eq!(gate(&summary, &pass, &junit).status.code(), Some(0));
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert!(
        xml.starts_with(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"sinsbench gate\">\n"
        ),
        "{xml}"
    );
    let first = std::fs::metadata(&junit).unwrap().ino();
    // Its own report is replaced by a new file renamed into place (a new inode), not rewritten.
    assert_eq!(gate(&summary, &fail, &junit).status.code(), Some(1));
    assert_ne!(std::fs::metadata(&junit).unwrap().ino(), first);
    assert_eq!(
        std::fs::read_to_string(&junit)
            .unwrap()
            .matches("<failure")
            .count(),
        1
    );
    // A report of the gate before the root carried its name is still its own.
    std::fs::write(
        &junit,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"sinsbench gate old\" tests=\"1\" failures=\"0\">\n  </testsuite>\n</testsuites>\n",
    )
    .unwrap();
    assert_eq!(gate(&summary, &pass, &junit).status.code(), Some(0));
    assert!(
        std::fs::read_to_string(&junit)
            .unwrap()
            .contains("name=\"sinsbench gate test\"")
    );
    assert_eq!(
        names(dir),
        ["fail.toml", "gate.xml", "pass.toml", "summary.json"]
    );
}

#[test]
fn threshold_keys_that_match_nothing_are_bad_input() {
    let tmp = tempfile::tempdir().unwrap();
    let (summary, _, _) = gate_files(tmp.path());
    let t = tmp.path().join("misspelt.toml");
    std::fs::write(
        &t,
        "schema = 1\n[default]\nmax_horizontal_nmi = { \"42-state\" = 2.65, \"99-state\" = 1.0 }\n\
         [experiment.NAV1]\nmin_improvement_percent = 0.0\n\
         [experiment.nav1]\nmax_horizontal_nmi = { \"42-State\" = 3.0 }\n",
    )
    .unwrap();
    let o = run(&["gate", "--summary", &s(&summary), "--thresholds", &s(&t)]);
    assert_refused(
        &o,
        &[
            "misspelt.toml",
            "summary.json",
            "default.max_horizontal_nmi.\"99-state\"",
            "experiment.NAV1",
            "experiment.nav1.max_horizontal_nmi.\"42-State\"",
            "the summary's experiments are nav1 and its parameter sets 30-state, 42-state",
        ],
    );
    assert!(o.stdout.is_empty(), "nothing may be reported as checked");
}

#[test]
fn verdict_lines_come_first_and_keep_their_exit_code_when_junit_cannot_be_written() {
    let tmp = tempfile::tempdir().unwrap();
    let (summary, pass, fail) = gate_files(tmp.path());
    let junit = tmp.path().join("no/such/dir/gate.xml");
    let o = gate(&summary, &fail, &junit);
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert_eq!(
        o.status.code(),
        Some(1),
        "a failed gate stays failed: {err}"
    );
    assert!(
        out.starts_with("FAIL nav1: max horizontal error with '42-state'"),
        "{out}"
    );
    for needle in [
        "gate failed: 1 of 1 checks exceeded their thresholds",
        "the JUnit report",
        "gate.xml was not written",
        "No such file or directory",
    ] {
        assert!(err.contains(needle), "'{needle}' missing from:\n{err}");
    }
    let o = gate(&summary, &pass, &junit);
    let err = assert_refused(
        &o,
        &[
            "gate passed (1 of 1 checks), but the JUnit report asked for is missing",
            "gate.xml was not written",
        ],
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.starts_with("PASS nav1: max horizontal error with '42-state'"),
        "{out}"
    );
    assert!(!out.contains("gate passed"), "{out}\n{err}");
}
