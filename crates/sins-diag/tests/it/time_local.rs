//! The time-local scan end to end on simulated noisy runs (paper noise, 100 Hz, 6 h): a bias
//! step, a ramp, a pulse, a ramp to a plateau and a turn-on transient injected by the simulator
//! are reported as events on their channel with the onset within 3 sigma of the truth (a pulse
//! and a plateau with their own shape, not as a step at one end); runs without an effect raise
//! none.

use crate::common;
use common::*;
use sins_diag::diagnose;
use sins_diag::events::TimeLocalEvent;
use sins_diag::input::DiagnoseConfig;
use sins_diag::report::{Diagnosis, NoteKind, Verdict};
use sins_imu::{EffectKind, EffectSpec};
use sins_nav::Vec3;

/// Two noisy 6 h runs; `effects[i]` is added to run `i` only.
fn diagnosed(effects: [Vec<EffectSpec>; 2]) -> Diagnosis {
    let mut scs = noisy_runs(
        turning_motion,
        100.0,
        6.0,
        &[(10.0, 4.0, 41), (30.0, -3.0, 42)],
        &[],
    );
    for (sc, e) in scs.iter_mut().zip(effects) {
        sc.effects = e;
    }
    let truth = scs[0].truth;
    let mut inp = input(&scs, &truth, None);
    let d = diagnose(&mut inp, &DiagnoseConfig::default()).expect("diagnosis");
    eprintln!("{}", summary(&d));
    for e in &d.events.events {
        eprintln!("{e:?}");
    }
    d
}

fn timed(kind: EffectKind, axis: usize, value: f64, onset_s: f64, tau_s: f64) -> EffectSpec {
    let mut e = effect(kind, axis, value);
    if let EffectSpec::BiasEvent {
        onset_s: o,
        time_constant_s: t,
        ..
    } = &mut e
    {
        *o = onset_s;
        *t = tau_s;
    }
    if let EffectSpec::AccelBiasStep { time_s, .. } = &mut e {
        *time_s = onset_s;
    }
    e
}

fn found<'a>(d: &'a Diagnosis, run: &str, channel: &str) -> &'a TimeLocalEvent {
    d.events
        .events
        .iter()
        .find(|e| e.run == run && e.channel == channel)
        .unwrap_or_else(|| panic!("no event on {run} {channel}: {:?}", d.events.events))
}

#[test]
fn no_effect_no_event() {
    let d = diagnosed([vec![], vec![]]);
    assert!(d.events.events.is_empty(), "{:?}", d.events.events);
    assert!(d.events.tests > 1000, "{}", d.events.tests);
    // Detectable levels exist for every channel and shape of both runs.
    assert!(d.events.detectable.len() >= 2 * 6 * 3);
    // The scan's note is typed: its figures are the scan's own.
    let note = d
        .notes
        .iter()
        .find(|n| n.kind == NoteKind::TimeLocal && n.text.starts_with("time-local scan"))
        .expect("the scan's note");
    let figure = |name: &str| {
        note.figures
            .iter()
            .find(|f| f.name == name)
            .map(|f| f.value)
    };
    assert_eq!(figure("tests"), Some(d.events.tests as f64), "{note:?}");
    assert_eq!(figure("threshold_chi2"), Some(d.events.threshold_chi2));
    assert_eq!(figure("events"), Some(0.0));
}

#[test]
fn a_gyro_bias_step_in_one_run_is_found_with_its_onset() {
    let onset = 3.0 * 3600.0 + 517.0;
    let d = diagnosed([
        vec![],
        vec![timed(EffectKind::GyroBiasStep, 1, 0.01, onset, 1.0)],
    ]);
    let e = found(&d, "run1", "gyro y");
    assert!((e.onset_s - onset).abs() <= 3.0 * e.onset_sigma_s, "{e:?}");
    assert!(e.explained_by.is_none(), "{e:?}");
    assert!(
        !d.events.events.iter().any(|e| e.run == "run0"),
        "{:?}",
        d.events.events
    );
    assert!(!matches!(
        d.verdict,
        Verdict::NoSignificantGap | Verdict::Explained { .. }
    ));
}

#[test]
fn an_accelerometer_ramp_is_found_with_its_onset() {
    let onset = 2.0 * 3600.0 + 1234.0;
    let d = diagnosed([
        vec![timed(EffectKind::AccelBiasRamp, 0, 20.0, onset, 1.0)],
        vec![],
    ]);
    let e = found(&d, "run0", "accel x");
    assert!((e.onset_s - onset).abs() <= 3.0 * e.onset_sigma_s, "{e:?}");
}

/// A pulse or a ramp to a plateau on one axis: `level` (SI) from `onset_s`, lasting or rising
/// over `duration_s`.
fn profile(kind: EffectKind, axis: usize, level: f64, onset_s: f64, duration_s: f64) -> EffectSpec {
    let mut magnitude_si = Vec3::zeros();
    magnitude_si[axis] = level;
    EffectSpec::BiasProfile {
        kind,
        magnitude_si,
        onset_s,
        duration_s,
        time_constant_s: 1.0,
    }
}

#[test]
fn an_accelerometer_pulse_is_found_as_a_pulse_at_its_start() {
    // 150 ug for 1500 s from 1.5 h, while the axis is level (the widened blind draw's case44,
    // 1931 s on a level axis, was found as a step at the pulse's end before the scan had
    // pulses).
    let onset = 1.5 * 3600.0;
    let level = 150e-6 * 9.80665;
    let d = diagnosed([
        vec![],
        vec![profile(EffectKind::AccelBiasPulse, 0, level, onset, 1500.0)],
    ]);
    let e = found(&d, "run1", "accel x");
    assert_eq!(e.shape, "pulse", "{e:?}");
    assert!((e.onset_s - onset).abs() <= 3.0 * e.onset_sigma_s, "{e:?}");
    let duration = e.duration_s.expect("a pulse's duration");
    assert!((1200.0..=2400.0).contains(&duration), "{e:?}");
    assert!(
        (e.size - 150.0).abs() <= 3.0 * e.size_sigma + 0.25 * 150.0,
        "{e:?}"
    );
}

#[test]
fn a_gyro_ramp_to_a_plateau_is_found_with_its_onset() {
    // 0.03 deg/h reached over 40 min from 1.7 h, in one run.
    let onset = 1.7 * 3600.0;
    let level = 0.03 * sins_nav::DEG_PER_H;
    let d = diagnosed([
        vec![profile(
            EffectKind::GyroBiasPlateau,
            2,
            level,
            onset,
            2400.0,
        )],
        vec![],
    ]);
    let e = found(&d, "run0", "gyro z");
    assert!((e.onset_s - onset).abs() <= 3.0 * e.onset_sigma_s, "{e:?}");
    assert!(
        !d.events.events.iter().any(|e| e.run == "run1"),
        "{:?}",
        d.events.events
    );
}

#[test]
fn a_turn_on_gyro_transient_is_found_in_both_runs() {
    let t = timed(EffectKind::GyroBiasTransient, 0, 0.05, 0.0, 2700.0);
    let d = diagnosed([vec![t.clone()], vec![t]]);
    for run in ["run0", "run1"] {
        let e = found(&d, run, "gyro x");
        assert!(e.explained_by.is_none(), "{e:?}");
    }
    // The gyro walk absorbs much of it (the external suite's failure), but is refused: its
    // evidence vanishes with the events removed, and its increments bunch at turn-on.
    let walk = d
        .candidates
        .iter()
        .find(|c| c.kind == "gyro_bias_random_walk")
        .expect("walk candidate");
    assert!(!walk.passes, "{walk:?}");
    assert!(
        !matches!(&d.verdict, sins_diag::report::Verdict::Explained { .. }),
        "{:?}",
        d.verdict
    );
}

/// A level accelerometer's turn-on transient that decays inside the 1200 s alignment leaves,
/// through the alignment's gains, mostly a tilt, which a gyro's turn-on transient also leaves:
/// propagated through the alignment replica, the signal is found with its true size, and the
/// event names its channel, as the event's or as one the data cannot tell from it.
#[test]
fn a_turn_on_accelerometer_transient_shorter_than_the_alignment_names_its_channel() {
    let t = timed(EffectKind::AccelBiasTransient, 0, -500.0, 0.0, 750.0);
    let d = diagnosed([vec![t.clone()], vec![t]]);
    for run in ["run0", "run1"] {
        let e = d
            .events
            .events
            .iter()
            .find(|e| {
                e.run == run
                    && (e.channel == "accel x"
                        || e.alternatives.iter().any(|a| a.channel == "accel x"))
            })
            .unwrap_or_else(|| panic!("accel x not named in {run}: {:?}", d.events.events));
        assert_eq!(e.shape, "turn-on transient", "{e:?}");
        assert!(e.explained_by.is_none(), "{e:?}");
        if e.channel == "accel x" {
            // Its size is the injected one within 3 sigma plus the time-constant grid's bias
            // (the nearest grid time constants, 600 and 1200 s, fit -490 and -485 ug).
            assert!((e.size + 500.0).abs() < 3.0 * e.size_sigma + 25.0, "{e:?}");
        }
    }
}
