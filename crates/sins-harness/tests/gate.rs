//! The release gate on summaries: a pass, a failure with a readable reason, limits that check
//! nothing. Reading thresholds files and `summary.json` is tested in `sins-config`.

use sins_harness::gate::{Limits, THRESHOLDS_SCHEMA, Thresholds, junit_xml};
use sins_harness::summary::Summary;
use std::collections::BTreeMap;
use std::path::Path;

fn summary(with_nmi: f64, without_nmi: f64) -> Summary {
    Summary::example(with_nmi, without_nmi)
}

/// The limits of `schema = 1`, `[default] max_horizontal_nmi = { "30-state" = 4.0,
/// "42-state" = 2.5 }`, `min_improvement_percent = 20.0`.
fn thresholds() -> Thresholds {
    Thresholds {
        schema: THRESHOLDS_SCHEMA,
        default: Limits {
            max_horizontal_nmi: BTreeMap::from([
                ("30-state".to_string(), 4.0),
                ("42-state".to_string(), 2.5),
            ]),
            min_improvement_percent: Some(20.0),
        },
        experiment: BTreeMap::new(),
    }
}

#[test]
fn passes_within_thresholds() {
    let t = thresholds();
    let s = summary(2.11, 3.38);
    let checks = t.evaluate(&s);
    assert_eq!(checks.len(), 3);
    assert!(checks.iter().all(|c| c.passed), "{checks:?}");
    // improvement (3.38 - 2.11) / 3.38 = 37.57 %, the paper's first experiment
    assert!((s.experiments[0].improvement_percent.unwrap() - 37.57).abs() < 0.01);
}

#[test]
fn fails_with_a_readable_reason_and_junit() {
    let t = thresholds();
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
    let mut t = thresholds();
    let nav1 = Limits {
        max_horizontal_nmi: BTreeMap::from([("42-state".to_string(), 3.0)]),
        min_improvement_percent: None,
    };
    t.experiment.insert("nav1".into(), nav1);
    t.experiment.insert("nav9".into(), Limits::default());
    let checks = t.evaluate(&summary(2.65, 4.0));
    let bad: Vec<_> = checks.iter().filter(|c| !c.passed).collect();
    assert_eq!(bad.len(), 1, "{checks:?}");
    assert!(bad[0].message.contains("nav9"));
}

#[test]
fn unusable_limits_name_the_key() {
    let mut t = thresholds();
    t.default.max_horizontal_nmi.insert("42-state".into(), -2.0);
    let e = t.validate().unwrap_err();
    assert!(e.contains("default.max_horizontal_nmi.\"42-state\""), "{e}");
    let mut t = thresholds();
    t.experiment.insert(
        "nav1".into(),
        Limits {
            max_horizontal_nmi: BTreeMap::new(),
            min_improvement_percent: Some(f64::NAN),
        },
    );
    let e = t.validate().unwrap_err();
    assert!(e.contains("experiment.nav1.min_improvement_percent"), "{e}");
    assert_eq!(thresholds().validate(), Ok(()));
}

#[test]
fn thresholds_that_check_nothing_are_refused() {
    let mut t = Thresholds {
        schema: THRESHOLDS_SCHEMA,
        ..Thresholds::default()
    };
    assert!(t.validate().unwrap_err().contains("no checks"));
    t.experiment.insert("nav1".into(), Limits::default());
    assert!(t.validate().unwrap_err().contains("no checks"));
}

#[test]
fn a_summary_without_experiments_checks_nothing_and_is_refused() {
    let t = thresholds();
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
