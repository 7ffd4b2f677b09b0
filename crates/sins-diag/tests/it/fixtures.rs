//! The diagnosis's output pinned on fixtures: three simulated sets, one per path through the
//! stages: a gyro temperature coefficient, ranked, named and validated on withheld runs; a gyro
//! step in one run, located by the time-local scan, after which the catalogue is ranked on the
//! gap less it and the verdict is "unexplained"; a size effect beyond the linear range, which the
//! refine stage replays away and takes over from the linear fits. Each fixture file holds the
//! SHA-256 of the whole serialised [`Diagnosis`] (every figure to the last bit, the series and
//! notes included) and a readable summary, compared first so that a change shows as a diff. A
//! restructuring of the stages must leave both unchanged (the fixtures were written by the code
//! before sins-diag became typed stages); a change of method updates them once
//! (`SINS_BLESS=1 cargo test -p sins-diag --test it fixtures`), saying why in its commit.

use crate::common;
use common::*;
use sha2::{Digest, Sha256};
use sins_diag::diagnose;
use sins_diag::input::DiagnoseConfig;
use sins_diag::report::Diagnosis;
use sins_imu::{EffectKind, EffectSpec};

fn fixture_path(name: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/diagnosis")
        .join(format!("{name}.txt"))
}

/// The summary (verdict, candidates, validation, events, rivals) and the hash of the JSON.
fn pinned(d: &Diagnosis) -> String {
    let json = serde_json::to_string(d).expect("json");
    let hash: String = Sha256::digest(json.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    let mut s = format!("sha256 {hash}\n{}", summary(d));
    for e in &d.events.events {
        s += &format!(
            "  event {} {} {} onset {:.1} ± {:.1} s, size {:.6e} {}\n",
            e.run, e.channel, e.shape, e.onset_s, e.onset_sigma_s, e.size, e.unit
        );
    }
    for r in &d.rivals {
        s += &format!("  rival {r:?}\n");
    }
    s
}

/// Compares `d` with the fixture `name` (or writes it, under `SINS_BLESS=1`).
fn check(name: &str, d: &Diagnosis) {
    let got = pinned(d);
    let path = fixture_path(name);
    if std::env::var_os("SINS_BLESS").is_some() {
        std::fs::write(&path, &got).expect("write fixture");
        return;
    }
    let want = std::fs::read_to_string(&path).expect("fixture");
    let (want_hash, want_rest) = want.split_once('\n').expect("hash line");
    let (got_hash, got_rest) = got.split_once('\n').expect("hash line");
    assert_eq!(got_rest, want_rest, "{name}: the summary changed");
    assert_eq!(
        got_hash, want_hash,
        "{name}: a figure changed below the summary's digits"
    );
}

fn timed(kind: EffectKind, axis: usize, value: f64, onset_s: f64) -> EffectSpec {
    let mut e = effect(kind, axis, value);
    if let EffectSpec::BiasEvent { onset_s: o, .. } = &mut e {
        *o = onset_s;
    }
    e
}

fn diagnosed(hours: f64, runs: &[(f64, f64, u64)], effects: Vec<Vec<EffectSpec>>) -> Diagnosis {
    let mut scs = noisy_runs(turning_motion, 100.0, hours, runs, &[]);
    for (sc, e) in scs.iter_mut().zip(effects) {
        sc.effects = e;
    }
    let truth = scs[0].truth;
    let mut inp = input(&scs, &truth, None);
    diagnose(&mut inp, &DiagnoseConfig::default()).expect("diagnosis")
}

#[test]
fn a_named_temperature_coefficient_diagnoses_as_pinned() {
    let e = vec![effect(EffectKind::GyroBiasTemp, 2, 0.006)];
    let d = diagnosed(
        3.0,
        &[(10.0, 8.0, 21), (30.0, -6.0, 22)],
        vec![e.clone(), e],
    );
    check("temperature_coefficient", &d);
}

#[test]
fn a_located_step_in_one_run_diagnoses_as_pinned() {
    let step = timed(EffectKind::GyroBiasStep, 1, 0.01, 3.0 * 3600.0 + 517.0);
    let d = diagnosed(
        6.0,
        &[(10.0, 4.0, 41), (30.0, -3.0, 42)],
        vec![vec![], vec![step]],
    );
    assert!(!d.events.events.is_empty(), "the step was not located");
    check("step_in_one_run", &d);
}

/// A size effect far beyond the linear range (Table 4 vibration, -8 mm): the refine stage
/// replays the runs with the effect removed and takes the lead from the linear fits.
#[test]
fn a_refined_size_effect_diagnoses_as_pinned() {
    let scs = noisy_runs(
        vibration_motion,
        200.0,
        3.0,
        &[(10.0, 8.0, 31), (30.0, -6.0, 32)],
        &[effect(EffectKind::SizeEffect, 0, -8.0)],
    );
    let truth = scs[0].truth;
    let mut inp = input(&scs, &truth, None);
    let d = diagnose(&mut inp, &DiagnoseConfig::default()).expect("diagnosis");
    assert!(
        d.notes.iter().any(|n| n.text.contains("refined by")),
        "the refinement did not run"
    );
    check("refined_size_effect", &d);
}
