//! The shipped report configuration and thresholds load, and point at files that exist.

use sins_harness::config::{NavigationSource, ParamOrigin, load_report_config};
use sins_harness::gate::Thresholds;
use sins_harness::reference::load_table5;
use std::path::PathBuf;

fn harness_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/harness")
}

#[test]
fn paper_replica_config_and_gate_load() {
    let c = load_report_config(&harness_dir().join("report_paper.toml")).unwrap();
    assert_eq!(c.name, "paper_replica");
    assert_eq!(c.parameter_sets.len(), 2);
    assert!(
        c.parameter_sets
            .iter()
            .all(|s| matches!(s.origin, ParamOrigin::Calibrate(_)))
    );
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
    let t = Thresholds::load(c.gate.as_ref().unwrap()).unwrap();
    assert_eq!(t.default.max_horizontal_nmi.get("42-state"), Some(&2.65));
}
