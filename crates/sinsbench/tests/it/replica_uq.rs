//! `replica-uq` end to end on a shortened replica (1.3 h calibration, three 55 min navigation
//! runs): the summary is byte-identical in one process and in two shards; a finished study
//! resumes without rerunning; bad inputs are refused with the file, key or option named and
//! nothing of the user's is touched.

use crate::common;

use common::{experiments, run, s as p};
use std::path::{Path, PathBuf};

/// A small study in `dir`: short experiments, a report configuration, an assumptions file.
fn small_study(dir: &Path) -> PathBuf {
    let e = experiments();
    let abs = |t: String| {
        t.replace("\"imu/", &format!("\"{}/imu/", e.display()))
            .replace("\"schemes/", &format!("\"{}/schemes/", e.display()))
    };
    let cal = abs(std::fs::read_to_string(e.join("paper_truth_calibration.toml")).unwrap())
        .replace("total_s = 13920.0", "total_s = 3480.0")
        .replace("repeat = 4", "repeat = 1")
        .replace("duration_s = 15120.0", "duration_s = 4680.0");
    std::fs::write(dir.join("cal.toml"), cal).unwrap();
    let nav = abs(std::fs::read_to_string(e.join("paper_navigation.toml")).unwrap())
        .replace("duration_s = 16800.0", "duration_s = 600.0")
        .replace("duration_s = 9600.0", "duration_s = 300.0")
        .replace("duration_h = 1.0", "duration_s = 300.0");
    std::fs::write(dir.join("nav.toml"), nav).unwrap();
    let report = std::fs::read_to_string(e.join("harness/report_paper.toml"))
        .unwrap()
        .replace("\"../paper_truth_calibration.toml\"", "\"cal.toml\"")
        .replace("\"../paper_navigation.toml\"", "\"nav.toml\"")
        .replace("\"../reference/", &format!("\"{}/reference/", e.display()))
        .replace(
            "gate = \"gate_paper.toml\"",
            &format!("gate = \"{}/harness/gate_paper.toml\"", e.display()),
        );
    std::fs::write(dir.join("report.toml"), report).unwrap();
    let study = format!(
        r#"schema = 1
name = "small"
replica = "report.toml"
paper_table5 = "{e}/reference/table5_navigation_results.csv"
paper_table2 = "{e}/reference/table2_repeatability.csv"
samples = 4
seed = 5
choose_on = ["exp1 without"]

[[assumption]]
name = "cal30_chamber"
knob = "cal30_chamber"
group = "calibration"
choice = {{ labels = ["ramp", "stable"], weights = [0.5, 0.5] }}
justification = "section 5.2 does not say"

[[assumption]]
name = "drop"
knob = "nav_temperature_drop"
group = "navigation temperature"
unit = "degC"
uniform = [10.0, 30.0]
justification = "figure 8 is not in the text"

[[assumption]]
name = "phase"
knob = "vibration_phase"
group = "vibration"
unit = "deg"
uniform = [0.0, 360.0]
justification = "Table 4 gives no phases"

[[candidate]]
name = "as_built"
samples = 2
set = {{ cal30_chamber = "ramp" }}
justification = "the replica as built"

[[candidate]]
name = "stable"
samples = 2
set = {{ cal30_chamber = "stable" }}
justification = "stable chamber"
"#,
        e = e.display()
    );
    let f = dir.join("assumptions.toml");
    std::fs::write(&f, study).unwrap();
    f
}

#[test]
fn sharded_and_single_process_summaries_are_identical() {
    let tmp = tempfile::tempdir().unwrap();
    let a = small_study(tmp.path());
    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    let o = run(&[
        "replica-uq",
        "--assumptions",
        &p(&a),
        "--out",
        &p(&one),
        "--threads",
        "2",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(
        table.contains("| exp1 without |") && table.contains("chosen"),
        "{table}"
    );
    for shard in ["1/2", "0/2"] {
        let o = run(&[
            "replica-uq",
            "--assumptions",
            &p(&a),
            "--out",
            &p(&two),
            "--threads",
            "1",
            "--shard",
            shard,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(
            two.join("summary.json").exists(),
            shard == "0/2",
            "summary only once every sample is in"
        );
    }
    for f in [
        "summary.json",
        "report.md",
        "intervals.png",
        "sensitivity.png",
    ] {
        assert_eq!(
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(two.join(f)).unwrap(),
            "{f} differs"
        );
    }
    // The summary is physics, not a shape: the point replica's exp1 30-state cell is a positive
    // error in nmi, inside a plausible band for a 55 min run, and the 5-95 % interval holds the
    // median.
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(one.join("summary.json")).unwrap()).unwrap();
    let c = &s["cells"][0];
    let (lo, med, hi) = (
        c["p05"].as_f64().unwrap(),
        c["median"].as_f64().unwrap(),
        c["p95"].as_f64().unwrap(),
    );
    assert!(lo <= med && med <= hi && lo > 0.0 && hi < 50.0, "{c}");
    // Resume: a finished study reruns nothing (no sample file is rewritten) and rewrites the
    // same summary bytes.
    let before = std::fs::read(one.join("summary.json")).unwrap();
    let stamps = |d: &Path| -> Vec<(std::ffi::OsString, std::time::SystemTime)> {
        let mut v: Vec<_> = std::fs::read_dir(d.join("samples"))
            .unwrap()
            .map(|e| e.unwrap())
            .map(|e| (e.file_name(), e.metadata().unwrap().modified().unwrap()))
            .collect();
        v.sort();
        v
    };
    let samples_before = stamps(&one);
    let o = run(&["replica-uq", "--assumptions", &p(&a), "--out", &p(&one)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        samples_before,
        stamps(&one),
        "a finished sample was run again"
    );
    assert_eq!(before, std::fs::read(one.join("summary.json")).unwrap());
    // Another seed in the same directory is refused (its samples would mix).
    let o = run(&[
        "replica-uq",
        "--assumptions",
        &p(&a),
        "--out",
        &p(&one),
        "--seed",
        "6",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("manifest.json differs"));
    // The pick-freeze design extends the same study (same manifest): 2 rows of B and of the 4
    // groups' A_B^g (3 file groups and the noise realisation); the main cells do not move.
    let o = run(&[
        "replica-uq",
        "--assumptions",
        &p(&a),
        "--out",
        &p(&one),
        "--pick-freeze",
        "2",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let t: serde_json::Value =
        serde_json::from_slice(&std::fs::read(one.join("summary.json")).unwrap()).unwrap();
    assert_eq!(t["pick_freeze_samples"], 2);
    assert_eq!(t["cells"][0]["median"], s["cells"][0]["median"]);
    let groups = t["cells"][0]["sensitivity"]["groups"].as_array().unwrap();
    let names: Vec<&str> = groups
        .iter()
        .map(|g| g["group"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "calibration",
            "navigation temperature",
            "vibration",
            "noise realisation"
        ]
    );
    for g in groups {
        let total = g["total"][0].as_f64().unwrap();
        assert!(total.is_finite() && total >= 0.0, "{g}");
    }
    // The 30-state calibration condition cannot move the 42-state cell: index exactly 0.
    let with = &t["cells"][1];
    assert_eq!(with["cell"], "exp1 with");
    assert_eq!(with["sensitivity"]["groups"][0]["total"][0], 0.0, "{with}");
    assert!(
        std::fs::read_to_string(one.join("report.md"))
            .unwrap()
            .contains("Grouped first-order and total indices (pick-freeze, 2 rows)")
    );
    // A report configuration naming the study shows its intervals (the `uq` key).
    let cfg = tmp.path().join("report_uq.toml");
    let text = std::fs::read_to_string(tmp.path().join("report.toml")).unwrap();
    let text = text.replace("uq = \"../replica/study\"", "uq = \"one\"");
    assert!(text.contains("uq = \"one\""));
    std::fs::write(&cfg, &text).unwrap();
    let reports = tmp.path().join("reports");
    let o = run(&[
        "report",
        "--config",
        &p(&cfg),
        "--reports-dir",
        &p(&reports),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let name = text
        .lines()
        .find_map(|l| l.strip_prefix("name = \""))
        .and_then(|l| l.strip_suffix('"'))
        .unwrap();
    let md = std::fs::read_to_string(reports.join(name).join("report.md")).unwrap();
    assert!(
        md.contains("## Table 5 as a prediction") && md.contains("4 main samples, seed 5"),
        "{md}"
    );
}

#[test]
fn bad_inputs_are_refused_and_nothing_is_touched() {
    let tmp = tempfile::tempdir().unwrap();
    let a = small_study(tmp.path());
    // An existing file where the directory goes: refused, left as it was.
    let file = tmp.path().join("mine.txt");
    std::fs::write(&file, "user data").unwrap();
    let o = run(&["replica-uq", "--assumptions", &p(&a), "--out", &p(&file)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a directory"));
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "user data");
    // A non-empty directory that is not a study: refused, untouched.
    let dir = tmp.path().join("notes");
    std::fs::create_dir(&dir).unwrap();
    std::fs::write(dir.join("keep.md"), "x").unwrap();
    let o = run(&["replica-uq", "--assumptions", &p(&a), "--out", &p(&dir)]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    // Shard out of range, zero threads: clap errors naming the option.
    for (flag, value) in [
        ("--shard", "2/2"),
        ("--shard", "x"),
        ("--threads", "0"),
        ("--samples", "1"),
    ] {
        let o = run(&[
            "replica-uq",
            "--assumptions",
            &p(&a),
            "--out",
            &p(&tmp.path().join("z")),
            flag,
            value,
        ]);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}");
        assert!(
            String::from_utf8_lossy(&o.stderr).contains(flag),
            "{flag}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    // Summarising a study with missing samples lists them and writes no summary.
    let o = run(&[
        "replica-uq",
        "--assumptions",
        &p(&a),
        "--out",
        &p(&tmp.path().join("empty")),
        "--summarize-only",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("samples are missing"));
    assert!(!tmp.path().join("empty/summary.json").exists());
    // A broken sample file is named.
    let one = tmp.path().join("one");
    let _ = run(&[
        "replica-uq",
        "--assumptions",
        &p(&a),
        "--out",
        &p(&one),
        "--summarize-only",
    ]);
    std::fs::write(one.join("samples/point-00000.json"), "{ not json").unwrap();
    let o = run(&[
        "replica-uq",
        "--assumptions",
        &p(&a),
        "--out",
        &p(&one),
        "--summarize-only",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("point-00000.json"));
}
