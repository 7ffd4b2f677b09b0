//! The release gate on summaries: a pass, a failure with a readable reason, malformed input.

use sins_harness::gate::{Thresholds, junit_xml};
use sins_harness::segments::SegmentStretch;
use sins_harness::summary::{
    Comparison, ExperimentSummary, SUMMARY_SCHEMA, SetResult, Summary, improvement_percent,
};
use std::collections::BTreeMap;
use std::path::Path;

fn result(max_nmi: f64) -> SetResult {
    SetResult {
        max_horizontal_nmi: max_nmi,
        max_horizontal_m: max_nmi * 1852.0,
        t_max_s: 36_000.0,
        segment_at_max: "pattern2".into(),
        rms_horizontal_m: 900.0,
        final_horizontal_m: 1000.0,
        navigated_s: 52_800.0,
        segments: vec![SegmentStretch {
            label: "pattern2".into(),
            occurrence: 1,
            start_s: 30_000.0,
            end_s: 40_000.0,
            max_horizontal_m: max_nmi * 1852.0,
            t_max_s: 36_000.0,
            rms_horizontal_m: 800.0,
        }],
    }
}

fn summary(with_nmi: f64, without_nmi: f64) -> Summary {
    let results = BTreeMap::from([
        ("42-state".to_string(), result(with_nmi)),
        ("30-state".to_string(), result(without_nmi)),
    ]);
    Summary {
        schema: SUMMARY_SCHEMA,
        name: "test".into(),
        description: String::new(),
        generated_by: "test".into(),
        parameter_sets: vec![],
        comparison: Some(Comparison {
            baseline: "30-state".into(),
            compensated: "42-state".into(),
        }),
        experiments: vec![ExperimentSummary {
            name: "nav1".into(),
            source: "test".into(),
            duration_h: 15.0,
            results,
            improvement_percent: Some(improvement_percent(without_nmi, with_nmi)),
            paper: None,
        }],
    }
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const THRESHOLDS: &str = r#"
schema = 1
[default]
max_horizontal_nmi = { "30-state" = 4.0, "42-state" = 2.5 }
min_improvement_percent = 20.0
"#;

#[test]
fn passes_within_thresholds() {
    let dir = tempfile::tempdir().unwrap();
    let t = Thresholds::load(&write(dir.path(), "t.toml", THRESHOLDS)).unwrap();
    let s = summary(2.11, 3.38);
    let checks = t.evaluate(&s);
    assert_eq!(checks.len(), 3);
    assert!(checks.iter().all(|c| c.passed), "{checks:?}");
    // improvement (3.38 - 2.11) / 3.38 = 37.57 %, the paper's first experiment
    assert!((s.experiments[0].improvement_percent.unwrap() - 37.57).abs() < 0.01);
}

#[test]
fn fails_with_a_readable_reason_and_junit() {
    let dir = tempfile::tempdir().unwrap();
    let t = Thresholds::load(&write(dir.path(), "t.toml", THRESHOLDS)).unwrap();
    let checks = t.evaluate(&summary(2.65, 3.0));
    let failed: Vec<_> = checks.iter().filter(|c| !c.passed).collect();
    assert_eq!(failed.len(), 2, "{checks:?}");
    assert!(
        failed[0]
            .message
            .contains("'42-state' is 2.650 nmi (limit 2.500 nmi)")
    );
    assert!(failed[0].message.contains("pattern2"));
    assert!(failed[1].message.contains("11.7 % (minimum 20.0 %)"));
    let xml = junit_xml("gate", &checks);
    assert_eq!(xml.matches("<testcase").count(), 3);
    assert_eq!(xml.matches("<failure").count(), 2);
    assert!(xml.contains("failures=\"2\""));
}

#[test]
fn per_experiment_override_and_missing_experiment() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "{THRESHOLDS}\n[experiment.nav1]\nmax_horizontal_nmi = {{ \"42-state\" = 3.0 }}\n[experiment.nav9]\n"
    );
    let t = Thresholds::load(&write(dir.path(), "t.toml", &text)).unwrap();
    let checks = t.evaluate(&summary(2.65, 4.0));
    let bad: Vec<_> = checks.iter().filter(|c| !c.passed).collect();
    assert_eq!(bad.len(), 1, "{checks:?}");
    assert!(bad[0].message.contains("nav9"));
}

#[test]
fn malformed_summary_and_thresholds_name_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "summary.json",
        "{\"schema\": 1, \"name\": \"x\"",
    );
    let e = Summary::from_json_file(&p).unwrap_err().to_string();
    assert!(
        e.contains("summary.json") && e.contains("not a sinsbench summary"),
        "{e}"
    );
    let mut s = summary(1.0, 2.0);
    s.experiments[0]
        .results
        .get_mut("42-state")
        .unwrap()
        .max_horizontal_nmi = -1.0;
    let p = write(dir.path(), "neg.json", &s.to_json());
    let e = Summary::from_json_file(&p).unwrap_err().to_string();
    assert!(
        e.contains("experiments['nav1'].results['42-state'].max_horizontal_nmi"),
        "{e}"
    );
    let p = write(
        dir.path(),
        "t.toml",
        "schema = 1\n[default]\nmax_horizontal = 3\n",
    );
    let e = Thresholds::load(&p).unwrap_err().to_string();
    assert!(e.contains("t.toml") && e.contains("max_horizontal"), "{e}");
    let p = write(
        dir.path(),
        "t2.toml",
        "schema = 1\n[default]\nmax_horizontal_nmi = { \"42-state\" = -2 }\n",
    );
    let e = Thresholds::load(&p).unwrap_err().to_string();
    assert!(e.contains("default.max_horizontal_nmi.\"42-state\""), "{e}");
}

#[test]
fn thresholds_that_check_nothing_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        ("bare.toml", "schema = 1\n"),
        ("tables.toml", "schema = 1\n[default]\n[experiment.nav1]\n"),
    ] {
        let e = Thresholds::load(&write(dir.path(), name, text))
            .unwrap_err()
            .to_string();
        assert!(e.contains(name) && e.contains("no checks"), "{e}");
    }
}

#[test]
fn a_summary_without_experiments_checks_nothing_and_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let t = Thresholds::load(&write(dir.path(), "t.toml", THRESHOLDS)).unwrap();
    let mut s = summary(2.0, 3.0);
    assert_eq!(t.check(&s, Path::new("full.json")).unwrap().len(), 3);
    s.experiments.clear();
    let e = t
        .check(&s, Path::new("hollow.json"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("hollow.json") && e.contains("no experiments"),
        "{e}"
    );
}
