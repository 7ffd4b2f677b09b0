//! The harness's input files: the shipped report configuration, thresholds and Table 5 load and
//! point at files that exist; malformed thresholds and Table 5 rows name the file and key or line.

use sins_config::{load_report_config, load_table5, load_thresholds};
use sins_harness::config::{NavigationSource, ParamOrigin};
use std::path::{Path, PathBuf};

fn harness_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/harness")
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap_or_else(|e| panic!("cannot write {}: {e}", p.display()));
    p
}

const THRESHOLDS: &str = r#"
schema = 1
[default]
max_horizontal_nmi = { "30-state" = 4.0, "42-state" = 2.5 }
min_improvement_percent = 20.0
"#;

#[test]
fn paper_replica_config_and_gate_load() {
    let c = load_report_config(&harness_dir().join("report_paper.toml")).unwrap();
    assert_eq!(c.name, "paper_replica");
    assert_eq!(c.parameter_sets.len(), 3);
    assert!(
        c.parameter_sets
            .iter()
            .all(|s| matches!(s.origin, ParamOrigin::Calibrate(_)))
    );
    // The headline's 30-state set and its variant are calibrated on the two runs the
    // calibration experiment declares.
    let exp = sins_config::load_experiment(&c.calibration.as_ref().unwrap().experiment).unwrap();
    let cmp = c.comparison.as_ref().unwrap();
    assert!(cmp.reason.as_ref().is_some_and(|r| r.len() > 20));
    for key in std::iter::once(&cmp.baseline).chain(&cmp.variant_baselines) {
        let set = c.parameter_sets.iter().find(|s| &s.key == key).unwrap();
        let run = set
            .calibration_run
            .clone()
            .or(c.calibration.as_ref().unwrap().run.clone())
            .unwrap();
        assert!(exp.scenarios.iter().any(|s| s.name == run), "{key}: {run}");
    }
    let NavigationSource::Experiment(nav) = &c.navigation else {
        panic!("the replica simulates its navigation runs");
    };
    assert!(nav.is_file(), "{}", nav.display());
    assert!(c.calibration.as_ref().unwrap().experiment.is_file());
    let rows = load_table5(c.paper_table5.as_ref().unwrap()).unwrap();
    // The paper's Table 5: improvements 37.57 / 28.38 / 39.30 %, consistent with its own columns.
    assert_eq!(rows.len(), 3);
    for r in &rows {
        let imp = 100.0 * (r.without_compensation_nmi - r.with_compensation_nmi)
            / r.without_compensation_nmi;
        assert!((imp - r.improvement_percent).abs() < 0.05, "{r:?}");
    }
    let t = load_thresholds(c.gate.as_ref().unwrap()).unwrap();
    assert_eq!(t.default.max_horizontal_nmi.get("42-state"), Some(&2.65));
}

#[test]
fn a_variant_or_a_calibration_run_that_names_nothing_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(harness_dir().join("report_paper.toml")).unwrap();
    for (from, to, key) in [
        (
            "variant_baselines = [\"30-state-ramp\"]",
            "variant_baselines = [\"30-state-cold\"]",
            "comparison.variant_baselines: '30-state-cold'",
        ),
        (
            "variant_baselines = [\"30-state-ramp\"]",
            "variant_baselines = [\"42-state\"]",
            "already the baseline or the compensated set",
        ),
        (
            "calibrate = 42\n",
            "file = \"p.toml\"\ncalibration_run = \"truth_cal1\"\n",
            "'calibration_run' applies to a set with 'calibrate = 30|42' only",
        ),
    ] {
        assert!(base.contains(from), "{from}");
        let p = write(dir.path(), "report.toml", &base.replace(from, to));
        let msg = load_report_config(&p).unwrap_err().to_string();
        assert!(msg.contains("report.toml") && msg.contains(key), "{msg}");
    }
}

#[test]
fn thresholds_file_with_per_experiment_overrides_loads() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "{THRESHOLDS}\n[experiment.nav1]\nmax_horizontal_nmi = {{ \"42-state\" = 3.0 }}\n[experiment.nav9]\n"
    );
    let t = load_thresholds(&write(dir.path(), "t.toml", &text)).unwrap();
    assert_eq!(t.default.max_horizontal_nmi.len(), 2);
    assert_eq!(t.default.min_improvement_percent, Some(20.0));
    assert_eq!(t.experiment["nav1"].max_horizontal_nmi["42-state"], 3.0);
    assert!(t.experiment["nav9"].is_empty());
}

#[test]
fn malformed_thresholds_name_the_file_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "t.toml",
        "schema = 1\n[default]\nmax_horizontal = 3\n",
    );
    let e = load_thresholds(&p).unwrap_err().to_string();
    assert!(e.contains("t.toml") && e.contains("max_horizontal"), "{e}");
    let p = write(
        dir.path(),
        "t2.toml",
        "schema = 1\n[default]\nmax_horizontal_nmi = { \"42-state\" = -2 }\n",
    );
    let e = load_thresholds(&p).unwrap_err().to_string();
    assert!(e.contains("default.max_horizontal_nmi.\"42-state\""), "{e}");
    let p = write(dir.path(), "t3.toml", &THRESHOLDS.replace("= 1", "= 2"));
    let e = load_thresholds(&p).unwrap_err().to_string();
    assert!(
        e.contains("t3.toml") && e.contains("key 'schema' is 2"),
        "{e}"
    );
}

#[test]
fn thresholds_that_check_nothing_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        ("bare.toml", "schema = 1\n"),
        ("tables.toml", "schema = 1\n[default]\n[experiment.nav1]\n"),
    ] {
        let e = load_thresholds(&write(dir.path(), name, text))
            .unwrap_err()
            .to_string();
        assert!(e.contains(name) && e.contains("no checks"), "{e}");
    }
}

#[test]
fn malformed_table5_names_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "t5.csv",
        "# experiment,with,without,imp\n1,2.11,3.38,37.57\n2,x,3.0,1\n",
    );
    let e = load_table5(&p).unwrap_err().to_string();
    assert!(
        e.contains("t5.csv")
            && e.contains("line 3")
            && e.contains("with_temperature_compensation_nmi 'x'"),
        "{e}"
    );
    let e = load_table5(&dir.path().join("absent.csv"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("absent.csv"), "{e}");
}
