//! The shipped assumptions file loads, declares every input with a justification, centres the
//! truth's temperature coefficients on the paper's Table 3, and refuses bad entries by name.

use sins_report::load_uq_study;
use sins_uq::assumptions::{Distribution, Knob};
use std::path::PathBuf;

fn experiments() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments")
}

#[test]
fn shipped_assumptions_load_with_justifications_and_table3_means() {
    let study = load_uq_study(&experiments().join("replica/assumptions.toml")).unwrap();
    let set = &study.set;
    assert!(
        set.assumptions.len() >= 40,
        "{} assumptions",
        set.assumptions.len()
    );
    assert!(
        set.assumptions.iter().all(|a| a.justification.len() > 20),
        "every entry justified"
    );
    // Table 3 "proposed" column (the paper's reference CSV), in the state order of eq (8).
    let t3 = std::fs::read_to_string(
        experiments().join("reference/table3_temperature_coefficients.csv"),
    )
    .unwrap();
    let proposed: Vec<f64> = t3
        .lines()
        .filter(|l| !l.starts_with('#') && l.contains(','))
        .filter_map(|l| l.split(',').nth(3)?.trim().parse().ok())
        .collect();
    let means: Vec<(usize, f64, f64)> = set
        .assumptions
        .iter()
        .filter_map(|a| match (a.knob, &a.distribution) {
            (Knob::TruthCoefficient(i), Distribution::Normal { mean, .. }) if i >= 21 => {
                Some((i, mean / a.unit_si, a.unit_si))
            }
            _ => None,
        })
        .collect();
    assert_eq!(means.len(), 12, "all 12 temperature coefficients drawn");
    assert_eq!(proposed.len(), 12, "Table 3 CSV: {t3}");
    for (i, m, _) in &means {
        assert!(
            (m - proposed[i - 21]).abs() < 1e-9,
            "coefficient {i}: mean {m} vs Table 3 {}",
            proposed[i - 21]
        );
    }
    // The base replica is the report's: three 15 h runs and the 4.2 h calibration.
    assert_eq!(study.base.navigation.len(), 3);
    assert_eq!(study.paper.cells.len(), 9);
    assert_eq!(
        study
            .paper
            .table2
            .iter()
            .map(|g| g.paper_std.len())
            .sum::<usize>(),
        33
    );
    assert_eq!(set.candidates[0].name, "as_built");
}

#[test]
fn bad_entries_are_refused_by_name() {
    let dir = std::env::temp_dir().join(format!("uq_bad_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(experiments().join("replica/assumptions.toml"))
        .unwrap()
        .replace("../", &format!("{}/", experiments().display()));
    for (from, to, expect) in [
        (
            "knob = \"accel_offset_scale\"",
            "knob = \"accel_offset_scael\"",
            "unknown knob 'accel_offset_scael'",
        ),
        (
            "uniform = [10.0, 30.0]",
            "uniform = [30.0, 10.0]",
            "nav_temperature_drop",
        ),
        (
            "set = { cal30_chamber = \"ramp\" }",
            "set = { cal30_chamber = \"warm\" }",
            "'warm' is not one of",
        ),
        (
            "choose_on = [\"exp1 without\"]",
            "choose_on = [\"exp9 without\"]",
            "beyond the replica's 3 runs",
        ),
        (
            "knob = \"truth:TB_ax\"",
            "knob = \"truth:TB_qx\"",
            "unknown knob 'truth:TB_qx'",
        ),
        (
            "pick_freeze_samples = 0",
            "pick_freeze_samples = 33",
            "'pick_freeze_samples': must be 0 or 2..=32",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        let f = dir.join("a.toml");
        std::fs::write(&f, text.replacen(from, to, 1)).unwrap();
        let err = load_uq_study(&f).unwrap_err().to_string();
        assert!(
            err.contains(expect) && err.contains("a.toml"),
            "{from} -> {err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
