//! `summary.json`: written then read back unchanged; malformed files name the file and field.

use sins_config::{read_summary, summary_to_json};
use sins_harness::segments::SegmentStretch;
use sins_harness::summary::{
    Comparison, ExperimentSummary, SUMMARY_SCHEMA, SetResult, Summary, improvement_percent,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap_or_else(|e| panic!("cannot write {}: {e}", p.display()));
    p
}

#[test]
fn written_summary_reads_back_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let s = summary(2.11, 3.38);
    let p = write(dir.path(), "summary.json", &summary_to_json(&s));
    assert_eq!(read_summary(&p).unwrap(), s);
}

#[test]
fn malformed_summary_names_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "summary.json",
        "{\"schema\": 1, \"name\": \"x\"",
    );
    let e = read_summary(&p).unwrap_err().to_string();
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
    let p = write(dir.path(), "neg.json", &summary_to_json(&s));
    let e = read_summary(&p).unwrap_err().to_string();
    assert!(
        e.contains("experiments['nav1'].results['42-state'].max_horizontal_nmi"),
        "{e}"
    );
    let mut s = summary(1.0, 2.0);
    s.schema = SUMMARY_SCHEMA + 1;
    let p = write(dir.path(), "new.json", &summary_to_json(&s));
    let e = read_summary(&p).unwrap_err().to_string();
    assert!(e.contains("new.json") && e.contains("key 'schema'"), "{e}");
}
