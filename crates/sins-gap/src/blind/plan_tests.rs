//! Tests of [`super`] (plan.rs).
use super::*;

#[test]
fn suite_has_the_requested_shape_and_is_reproducible() {
    let shape = SuiteShape::default();
    let a = draw_cases(&shape, 7);
    assert_eq!(a, draw_cases(&shape, 7));
    assert_ne!(a, draw_cases(&shape, 8));
    assert_eq!(a.len(), 30);
    assert_eq!(a.iter().filter(|c| c.hidden.is_none()).count(), 5);
    let outside = a
        .iter()
        .filter(|c| c.hidden.as_ref().is_some_and(|h| !h.in_catalogue))
        .count();
    assert_eq!(outside, 3);
    // every catalogue kind appears
    for k in EffectKind::catalogue() {
        assert!(
            a.iter()
                .any(|c| c.hidden.as_ref().is_some_and(|h| h.kind == k.name())),
            "{k}"
        );
    }
    for c in &a {
        if let Some(h) = &c.hidden {
            let range = if h.in_catalogue {
                1.99..=20.01
            } else {
                9.99..=50.01
            };
            assert!(range.contains(&h.times_typical), "{h:?}");
            let spec = c.spec().unwrap();
            let m = spec.magnitudes_si();
            let kind = EffectKind::from_name(&h.kind).unwrap();
            assert!(
                (m[h.component] - kind.unit().to_si(h.magnitude)).abs()
                    <= 1e-12 * m[h.component].abs()
            );
        }
    }
}

#[test]
fn time_local_cases_follow_the_original_draw_and_cover_every_time_local_kind() {
    let base = SuiteShape::default();
    let shape = SuiteShape {
        time_local: 12,
        ..base.clone()
    };
    let with = draw_cases(&shape, 5);
    let without = draw_cases(&base, 5);
    // The first cases are those of the suite without time-local cases.
    assert_eq!(&with[..30], &without[..]);
    assert_eq!(with.len(), 42);
    assert_eq!(with, draw_cases(&shape, 5));
    let tl: Vec<&HiddenEffect> = with[30..]
        .iter()
        .filter_map(|c| c.hidden.as_ref())
        .collect();
    assert_eq!(tl.len(), 12);
    for k in EffectKind::ORIGINAL_TIME_LOCAL {
        assert!(tl.iter().any(|h| h.kind == k.name()), "{k}");
    }
    for (c, h) in with[30..].iter().zip(&tl) {
        assert!(h.is_time_local() && h.drawn_time_local() && !h.in_catalogue);
        let kind = EffectKind::from_name(&h.kind).unwrap();
        if kind.sensor() == sins_imu::effects::Sensor::Accel {
            assert!(h.component < 2, "{h:?}");
        }
        let onset = h.onset_time_s();
        // Turn-on transients act in every run; the others in one navigation run, inside
        // the onset window.
        match &h.run {
            None => assert_eq!(onset, 0.0, "{h:?}"),
            Some(r) => {
                assert!(shape.time_local_runs.contains(r));
                assert!((3600.0..=11.0 * 3600.0).contains(&onset), "{h:?}");
            }
        }
        // The spec carries the onset and the magnitude.
        let spec = c.spec().unwrap();
        let m = spec.magnitudes_si();
        assert!(
            (m[h.component] - kind.unit().to_si(h.magnitude)).abs() <= 1e-12 * m[h.component].abs()
        );
        if let EffectSpec::BiasEvent {
            onset_s,
            time_constant_s,
            ..
        } = spec
        {
            assert_eq!(onset_s, onset);
            if let Some(t) = h.time_constant_s {
                assert_eq!(time_constant_s, t);
            }
        }
    }
}

/// The suite SHA-256 of the blind45 campaign (seed 5) as sealed by the code before the
/// widened draw existed (`sealed/index.json` of a blind45 run).
const BLIND45_SUITE_SHA256: &str =
    "e9da26ec615f3a18987c39d8b4c4d14e7b06e648a076446fcc2d66a62b64eaad";

fn blind45() -> SuiteShape {
    SuiteShape {
        cases: 30,
        null_cases: 5,
        out_of_catalogue: 3,
        time_local: 15,
        time_local_runs: vec!["nav1".into(), "nav2".into()],
        ..SuiteShape::default()
    }
}

#[test]
fn blind45_draws_bit_identical_manifests_and_the_wide_cases_come_after() {
    let dir = tempfile::tempdir().unwrap();
    let old = draw_cases(&blind45(), 5);
    let index = crate::blind::seal::seal(dir.path(), 5, &old).unwrap();
    assert_eq!(index.suite_sha256, BLIND45_SUITE_SHA256);
    // blind30 is its first 30 cases (its own seal is that of the same manifests).
    let b30 = SuiteShape {
        time_local: 0,
        ..blind45()
    };
    assert_eq!(draw_cases(&b30, 5), old[..30].to_vec());
    // The widened sections add cases after the old ones and change none of them; an old
    // campaign file (no new key) reads as a shape without them.
    let wide = SuiteShape {
        wide_time_local: 20,
        different_histories: 5,
        ..blind45()
    };
    let new = draw_cases(&wide, 5);
    assert_eq!(new.len(), 70);
    assert_eq!(&new[..45], &old[..]);
    let read: SuiteShape = serde_json::from_str(
        r#"{"cases": 30, "null_cases": 5, "out_of_catalogue": 3, "times_typical": [2.0, 20.0], "time_local": 15}"#,
    )
    .unwrap();
    assert_eq!((read.wide_time_local, read.different_histories), (0, 0));
    // The shape's Debug (campaign fingerprints) is that of the old fields unless the new
    // sections draw cases.
    assert!(!format!("{:?}", blind45()).contains("wide"));
    assert!(format!("{wide:?}").contains("wide_time_local: 20"));
}

#[test]
fn wide_time_local_cases_cover_shapes_sensors_and_scopes_in_their_ranges() {
    let shape = SuiteShape {
        wide_time_local: 20,
        ..blind45()
    };
    let all = draw_cases(&shape, 5);
    assert_eq!(all, draw_cases(&shape, 5));
    let wide: Vec<&CaseAnswer> = all[45..].iter().collect();
    assert_eq!(wide.len(), 20);
    let mut shapes = std::collections::BTreeSet::new();
    let mut scopes = std::collections::BTreeSet::new();
    let mut sensors = std::collections::BTreeSet::new();
    for (j, c) in wide.iter().enumerate() {
        assert_eq!(c.case, format!("case{:02}", 46 + j));
        assert_eq!(c.section(), "wide time-local");
        let h = c.hidden.as_ref().unwrap();
        let kind = EffectKind::from_name(&h.kind).unwrap();
        assert!(kind.is_time_local() && !h.in_catalogue && h.drawn_time_local());
        shapes.insert(j % 6);
        sensors.insert(format!("{:?}", kind.sensor()));
        let scope = h.scope.unwrap();
        scopes.insert(format!("{scope:?}"));
        if kind.sensor() == sins_imu::effects::Sensor::Accel {
            assert!(h.component < 2, "{h:?}");
        }
        assert!((2.99..=30.01).contains(&h.times_typical), "{h:?}");
        let onset = h.onset_time_s();
        let in_h = |x: Option<f64>, (a, b): (f64, f64)| {
            x.is_some_and(|x| (3600.0 * a - 1.0..=3600.0 * b + 1.0).contains(&x))
        };
        match scope {
            EventScope::OneRun => {
                assert!(shape.time_local_runs.contains(h.run.as_ref().unwrap()));
                assert!((3600.0..=39_600.0).contains(&onset));
                assert!(h.acts_on("nav1") != h.acts_on("nav2"));
                assert!(!h.acts_on(CALIBRATION_RUN));
            }
            EventScope::AllNavigationRuns => {
                assert_eq!(h.run, None);
                assert!((3600.0..=39_600.0).contains(&onset));
                assert!(h.acts_on("nav1") && h.acts_on("nav2") && h.acts_on("all runs"));
                assert!(!h.acts_on(CALIBRATION_RUN));
            }
            EventScope::CalibrationOnly => {
                assert!(h.calibration_only());
                assert!((1800.0..=9000.0).contains(&onset));
                assert!(h.acts_on(CALIBRATION_RUN) && h.acts_on(CALIBRATION_SCOPE));
                assert!(!h.acts_on("nav1") && !h.acts_on("nav2"));
            }
        }
        match kind {
            EffectKind::GyroBiasPlateau | EffectKind::AccelBiasPlateau => {
                assert!(in_h(h.duration_s, WIDE_RISE_H), "{h:?}")
            }
            EffectKind::GyroBiasPulse | EffectKind::AccelBiasPulse => {
                assert!(in_h(h.duration_s, WIDE_PULSE_H), "{h:?}")
            }
            EffectKind::GyroBiasDecayingOscillation | EffectKind::AccelBiasDecayingOscillation => {
                assert!(in_h(h.duration_s, WIDE_PERIOD_H), "{h:?}");
                assert!(in_h(h.time_constant_s, WIDE_DECAY_H), "{h:?}");
            }
            EffectKind::GyroBiasTransient | EffectKind::AccelBiasTransient => {
                let t = h.time_constant_s.unwrap();
                assert!((600.0..=5400.0).contains(&t), "{h:?}");
            }
            _ => assert_eq!((h.duration_s, h.time_constant_s), (None, None)),
        }
        // The spec carries onset, times and magnitude.
        let spec = c.spec().unwrap();
        assert_eq!(spec.kind(), kind);
        let m = spec.magnitudes_si();
        assert!(
            (m[h.component] - kind.unit().to_si(h.magnitude)).abs() <= 1e-12 * m[h.component].abs()
        );
        match spec {
            EffectSpec::BiasProfile {
                onset_s,
                duration_s,
                time_constant_s,
                ..
            } => {
                assert_eq!(onset_s, onset);
                assert_eq!(Some(duration_s), h.duration_s);
                if let Some(t) = h.time_constant_s {
                    assert_eq!(time_constant_s, t);
                }
            }
            EffectSpec::BiasEvent { onset_s, .. } => assert_eq!(onset_s, onset),
            EffectSpec::AccelBiasStep { time_s, .. } => assert_eq!(time_s, onset),
            other => panic!("{other:?}"),
        }
    }
    assert_eq!(shapes.len(), 6);
    assert_eq!(sensors.len(), 2);
    assert_eq!(scopes.len(), 3);
    // A manifest reads back to the same answer.
    for c in &wide {
        let text = serde_json::to_string_pretty(c).unwrap();
        assert_eq!(&serde_json::from_str::<CaseAnswer>(&text).unwrap(), *c);
    }
}

#[test]
fn different_history_cases_are_temperature_driven_and_name_their_experiment() {
    let shape = SuiteShape {
        wide_time_local: 3,
        different_histories: 5,
        ..SuiteShape::default()
    };
    let all = draw_cases(&shape, 9);
    assert_eq!(all.len(), 38);
    let dh = &all[33..];
    for (c, k) in dh.iter().zip(TEMPERATURE_DRIVEN) {
        let h = c.hidden.as_ref().unwrap();
        assert_eq!(h.kind, k.name());
        assert!(h.in_catalogue && !h.is_time_local());
        assert!((1.99..=20.01).contains(&h.times_typical));
        assert_eq!(
            c.navigation_experiment.as_deref(),
            Some("navigation_varied_histories")
        );
        assert_eq!(c.section(), "different histories");
        assert!(h.acts_on(CALIBRATION_RUN) && h.acts_on("nav1"));
    }
    // Old answers (no new field) serialize as before.
    let old = &all[0];
    assert!(
        !serde_json::to_string(old)
            .unwrap()
            .contains("navigation_experiment")
    );
}

#[test]
fn the_varied_histories_experiment_has_three_distinct_chamber_histories() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments");
    let paper = sins_config::load_experiment(dir.join("paper_navigation.toml")).unwrap();
    let varied =
        sins_config::load_experiment(dir.join("blind/navigation_varied_histories.toml")).unwrap();
    assert_eq!(varied.name, default_histories_experiment());
    let names = |e: &sins_config::Experiment| -> Vec<String> {
        e.scenarios.iter().map(|s| s.name.clone()).collect()
    };
    // The same run names, noise and motion as the paper's runs; the histories differ.
    assert_eq!(names(&varied), names(&paper));
    for (v, p) in varied.scenarios.iter().zip(&paper.scenarios) {
        assert_eq!(format!("{:?}", v.noise), format!("{:?}", p.noise));
        assert_eq!(format!("{:?}", v.motion), format!("{:?}", p.motion));
        assert_eq!(v.seed, p.seed);
        assert_eq!(format!("{:?}", v.truth), format!("{:?}", p.truth));
    }
    let chambers: Vec<String> = varied
        .scenarios
        .iter()
        .map(|s| format!("{:?}", s.thermal))
        .collect();
    assert!(chambers[0] != chambers[1] && chambers[1] != chambers[2]);
    assert!(chambers[0] != chambers[2]);
}
