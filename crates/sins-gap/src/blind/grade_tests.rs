//! Tests of [`super`] (grade.rs).
use super::*;
use crate::blind::plan::HiddenEffect;
use sins_diag::events::{ChannelAlternative, TimeLocalEvent};
use sins_diag::report::{
    CandidateModel, CandidateReport, ChiSquareTest, ComponentEstimate, GapMetrics, ValidationReport,
};

fn test(consistent: bool) -> ChiSquareTest {
    ChiSquareTest {
        chi2: 100.0,
        dof: 100.0,
        p_value: if consistent { 0.5 } else { 1e-9 },
        consistent,
    }
}

fn diagnosis(verdict: Verdict, candidate: Option<(&str, f64, f64, f64)>) -> Diagnosis {
    let candidates = candidate
        .map(|(kind, value, sigma, detectable)| CandidateReport {
            kind: kind.into(),
            description: String::new(),
            unit: "u".into(),
            model: CandidateModel::Regression,
            components: vec![ComponentEstimate {
                label: "x".into(),
                value,
                sigma: Some(sigma),
                retained: true,
                detectable: Some(detectable),
            }],
            dchi2: 50.0,
            dof: 1,
            p_value: 1e-6,
            delta_bic: 40.0,
            plausibility_penalty: 0.0,
            evidence: 40.0,
            passes: true,
            residual: test(true),
            whiteness: None,
            constancy: None,
        })
        .into_iter()
        .collect();
    let validation = candidate
        .map(|(kind, ..)| ValidationReport {
            kind: kind.into(),
            informative: true,
            fitted_on: "a".into(),
            evaluated_on: "b".into(),
            magnitudes: vec![],
            before: GapMetrics {
                max_horizontal_gap_m: 100.0,
                rms_gap_m: 50.0,
            },
            after: GapMetrics {
                max_horizontal_gap_m: 10.0,
                rms_gap_m: 5.0,
            },
            rms_shrinkage_percent: 40.0,
            max_shrinkage_percent: 90.0,
            systematic_before: 20.0,
            systematic_after: 2.0,
            systematic_shrinkage_percent: 90.0,
        })
        .into_iter()
        .collect();
    Diagnosis {
        n_data: 100,
        null_test: test(candidate.is_none()),
        candidates,
        verdict,
        localisation: vec![],
        validation,
        series: vec![],
        notes: vec![],
        events: Default::default(),
        noise_untrusted: vec![],
        rivals: vec![],
        confound: vec![],
    }
}

#[test]
fn withheld_runs_without_a_systematic_gap_do_not_count_as_zero_shrinkage() {
    let by = Verdict::Explained {
        by: "gyro_bias_temp".into(),
    };
    let mut d = diagnosis(by, Some(("gyro_bias_temp", 2.1, 0.1, 0.5)));
    let mut quiet = d.validation[0].clone();
    quiet.systematic_before = 0.0;
    quiet.systematic_after = 0.0;
    quiet.systematic_shrinkage_percent = 0.0;
    quiet.rms_shrinkage_percent = 10.0;
    d.validation.push(quiet.clone());
    let a = answer("c1", Some(("gyro_bias_temp", true, 2.0)));
    let g = grade(&[(a.clone(), d)]);
    // 90 % on the run with a systematic gap; the quiet run counts for RMS only.
    assert_eq!(g.cases[0].shrinkage_percent, Some(90.0));
    assert_eq!(g.cases[0].rms_shrinkage_percent, Some(25.0));
    // Only quiet runs: no systematic figure at all.
    let mut only_quiet = diagnosis(
        Verdict::Explained {
            by: "gyro_bias_temp".into(),
        },
        Some(("gyro_bias_temp", 2.1, 0.1, 0.5)),
    );
    only_quiet.validation = vec![quiet];
    let g = grade(&[(a, only_quiet)]);
    assert_eq!(g.cases[0].shrinkage_percent, None);
    assert_eq!(g.median_shrinkage_percent, None);
}

fn answer(case: &str, kind: Option<(&str, bool, f64)>) -> CaseAnswer {
    CaseAnswer {
        case: case.into(),
        seed: 1,
        hidden: kind.map(|(k, inside, magnitude)| HiddenEffect {
            kind: k.into(),
            in_catalogue: inside,
            component: 0,
            component_label: "x".into(),
            magnitude,
            unit: "u".into(),
            times_typical: 5.0,
            onset_s: None,
            time_constant_s: None,
            run: None,
            duration_s: None,
            scope: None,
        }),
        navigation_experiment: None,
    }
}

fn event(run: &str, channel: &str, onset_s: f64, sigma_s: f64) -> TimeLocalEvent {
    TimeLocalEvent {
        run: run.into(),
        channel: channel.into(),
        shape: "step".into(),
        kind: "gyro_bias_step".into(),
        onset_s,
        onset_sigma_s: sigma_s,
        onset_interval_s: [onset_s - 3.0 * sigma_s, onset_s + 3.0 * sigma_s],
        size: 0.01,
        size_sigma: 0.001,
        unit: "deg/h".into(),
        time_constant_s: None,
        duration_s: None,
        chi2: 100.0,
        p_value: 1e-10,
        explained_by: None,
        alternatives: Vec::new(),
    }
}

#[test]
fn time_local_cases_need_their_channel_run_and_onset() {
    let step = |run: Option<&str>| {
        let mut a = answer("t1", Some(("gyro_bias_step", false, 0.01)));
        if let Some(h) = a.hidden.as_mut() {
            h.component = 1;
            h.component_label = "y".into();
            h.onset_s = Some(10_000.0);
            h.run = run.map(Into::into);
        }
        a
    };
    let none = Verdict::Unexplained;
    let with = |events: Vec<TimeLocalEvent>| {
        let mut d = diagnosis(none.clone(), None);
        d.events.events = events;
        d
    };
    let cases = vec![
        // found: right run and channel, 10 000 within 3 × 400 of 10 900
        (
            step(Some("nav1")),
            with(vec![event("nav1", "gyro y", 10_900.0, 400.0)]),
        ),
        // onset off by more than 3 sigma
        (
            step(Some("nav1")),
            with(vec![event("nav1", "gyro y", 12_000.0, 300.0)]),
        ),
        // wrong run, then wrong channel
        (
            step(Some("nav1")),
            with(vec![event("nav2", "gyro y", 10_000.0, 300.0)]),
        ),
        (
            step(Some("nav1")),
            with(vec![event("nav1", "gyro x", 10_000.0, 300.0)]),
        ),
        // the channel named as one the data cannot tell from the event's own
        (step(Some("nav1")), {
            let mut e = event("nav1", "accel x", 10_000.0, 300.0);
            e.alternatives.push(ChannelAlternative {
                channel: "gyro y".into(),
                shape: "step".into(),
                time_constant_s: None,
                duration_s: None,
                chi2: 95.0,
            });
            with(vec![e])
        }),
        // a null case with an event outside the catalogue: a time-local false alarm
        (
            answer("n1", None),
            with(vec![event("nav1", "gyro x", 5_000.0, 300.0)]),
        ),
    ];
    let g = grade(&cases);
    assert_eq!(g.time_local_found, (2, 5));
    assert_eq!(g.time_local_found_on_channel, (1, 5));
    assert!(
        g.cases[4]
            .time_local
            .as_ref()
            .is_some_and(|t| t.as_alternative)
    );
    assert_eq!(g.time_local_false_alarms, (1, 1));
    // Drawn time-local cases are not counted with the original out-of-catalogue cases.
    assert_eq!(g.out_of_catalogue_unexplained.1, 0);
    assert!(render_grades(&g, "x").contains("onset within 3 sigma"));
}

#[test]
fn grades_count_hits_alarms_outside_cases_and_magnitudes() {
    let explained = |by: &str| Verdict::Explained { by: by.into() };
    let cases = vec![
        // hit, fitted 2.1 ± 0.1 for a hidden 2.0: within 3 sigma
        (
            answer("c1", Some(("gyro_bias_temp", true, 2.0))),
            diagnosis(
                explained("gyro_bias_temp"),
                Some(("gyro_bias_temp", 2.1, 0.1, 0.5)),
            ),
        ),
        // wrong kind named: a miss (the hidden kind is above its detectable level 0.5)
        (
            answer("c2", Some(("size_effect", true, 3.0))),
            diagnosis(
                explained("gyro_bias_temp"),
                Some(("size_effect", 0.2, 0.1, 0.5)),
            ),
        ),
        // below the detectable level: not scored
        (
            answer("c3", Some(("size_effect", true, 0.1))),
            diagnosis(
                Verdict::NoSignificantGap,
                Some(("size_effect", 0.0, 0.1, 0.5)),
            ),
        ),
        // null cases: one quiet, one false alarm
        (
            answer("c4", None),
            diagnosis(Verdict::NoSignificantGap, None),
        ),
        (
            answer("c5", None),
            diagnosis(
                explained("gyro_bias_temp"),
                Some(("gyro_bias_temp", 1.0, 0.1, 0.5)),
            ),
        ),
        // outside the catalogue, reported unexplained
        (
            answer("c6", Some(("accel_bias_step", false, 20.0))),
            diagnosis(Verdict::Unexplained, None),
        ),
    ];
    let g = grade(&cases);
    assert_eq!(g.top1, (1, 2));
    assert_eq!(g.false_alarms, (1, 2));
    assert_eq!(g.out_of_catalogue_unexplained, (1, 1));
    assert_eq!(g.out_of_catalogue_unexplained_with_gap, (1, 1));
    assert_eq!(g.magnitudes_within_3_sigma, (1, 1));
    assert_eq!(g.median_shrinkage_percent, Some(90.0));
    assert_eq!(g.median_rms_shrinkage_percent, Some(40.0));
    assert_eq!(g.confusion["none"]["gyro_bias_temp"], 1);
    assert_eq!(g.confusion["size_effect"]["none"], 1);
    let md = render_grades(&g, "abc");
    assert!(md.contains(
        "| top-1 identification, in-catalogue cases above the detectable level | 1 / 2 (50 %) |"
    ));
}

fn alternative(kind: &str, channel: &str, runs: &str) -> sins_diag::TimeCourseAlternative {
    sins_diag::TimeCourseAlternative {
        kind: kind.into(),
        channel: channel.into(),
        runs: runs.into(),
        shape: "ramp".into(),
        onset_s: 3600.0,
        time_s: None,
        size: 1.0,
        unit: "u".into(),
        dchi2: 30.0,
    }
}

/// A hidden effect of `kind` on component `c` (label x, y, z).
fn hidden(case: &str, kind: &str, c: usize) -> CaseAnswer {
    let k = EffectKind::from_name(kind).unwrap();
    let mut a = answer(case, Some((kind, k.in_catalogue(), 1.0)));
    if let Some(h) = a.hidden.as_mut() {
        h.component = c;
        h.component_label = ["x", "y", "z"][c].into();
        if k.is_time_local() {
            h.onset_s = Some(10_000.0);
        }
    }
    a
}

#[test]
fn confident_misattributions_follow_each_rule() {
    let explained = |by: &str| Verdict::Explained { by: by.into() };
    let not_sep = |c: &[&str], t: Vec<sins_diag::TimeCourseAlternative>| Verdict::NotSeparable {
        candidates: c.iter().map(|s| s.to_string()).collect(),
        time_local: t,
    };
    let plateau = |case: &str| {
        let mut a = hidden(case, "accel_bias_plateau", 0);
        if let Some(h) = a.hidden.as_mut() {
            h.scope = Some(crate::blind::plan::EventScope::AllNavigationRuns);
            h.duration_s = Some(5400.0);
        }
        a
    };
    let mut histories = hidden("h1", "thermal_lag", 2);
    histories.navigation_experiment = Some("navigation_varied_histories".into());
    let d = |v: Verdict| diagnosis(v, None);
    // (answer, verdict, confident misattribution, a cause on the right channel)
    let table: Vec<(CaseAnswer, Verdict, bool, bool)> = vec![
        // A null case: any named cause is wrong; no gap is never a misattribution.
        (answer("n1", None), explained("gyro_bias_temp"), true, false),
        (answer("n2", None), Verdict::NoSignificantGap, false, false),
        (
            answer("n3", None),
            not_sep(&[], vec![alternative("gyro_bias_step", "gyro x", "nav1")]),
            true,
            false,
        ),
        // In the catalogue: the hidden kind is right, another is wrong; one right cause
        // among several is enough.
        (
            hidden("c1", "gyro_bias_temp", 0),
            explained("gyro_bias_temp"),
            false,
            true,
        ),
        (
            hidden("c2", "size_effect", 0),
            explained("gyro_bias_temp"),
            true,
            false,
        ),
        (
            hidden("c3", "size_effect", 0),
            not_sep(&["gyro_bias_temp", "size_effect"], vec![]),
            false,
            true,
        ),
        // Partly explained names a cause as well.
        (
            hidden("c4", "accel_time_offset", 1),
            Verdict::PartlyExplained {
                by: "size_effect".into(),
            },
            true,
            false,
        ),
        // Outside the catalogue: unexplained is right, a catalogue name is not.
        (
            hidden("o1", "gyro_bias_oscillation", 0),
            Verdict::Unexplained,
            false,
            false,
        ),
        (
            hidden("o2", "accel_cross_coupling", 0),
            explained("accel_quadratic_nonlinearity"),
            true,
            false,
        ),
        // Time-local: a time course on the same sensor is right (another channel or
        // shape included), one on the other sensor is not, a catalogue kind is not.
        (
            plateau("w1"),
            not_sep(
                &["gyro_bias_temp_rate"],
                vec![alternative("accel_bias_ramp", "accel y", "all runs")],
            ),
            false,
            false,
        ),
        (
            plateau("w2"),
            not_sep(
                &["thermal_lag"],
                vec![alternative("gyro_bias_step", "gyro x", "all runs")],
            ),
            true,
            false,
        ),
        (plateau("w3"), explained("gyro_bias_temp_rate"), true, false),
        (
            hidden("t1", "gyro_bias_transient", 1),
            not_sep(
                &[],
                vec![alternative("gyro_bias_transient", "gyro y", "all runs")],
            ),
            false,
            true,
        ),
        (
            hidden("t2", "gyro_bias_step", 2),
            explained("gyro_bias_random_walk"),
            true,
            false,
        ),
        // The original accelerometer step is time-local too.
        (
            hidden("t3", "accel_bias_step", 1),
            not_sep(
                &["thermal_lag"],
                vec![alternative("accel_bias_step", "accel y", "nav2")],
            ),
            false,
            true,
        ),
        // Different histories: an in-catalogue case like any other.
        (
            histories,
            not_sep(&["thermal_lag", "accel_bias_temp_rate"], vec![]),
            false,
            true,
        ),
        // Not separable naming nothing names no wrong cause.
        (
            hidden("e1", "size_effect", 0),
            not_sep(&[], vec![]),
            false,
            false,
        ),
    ];
    for (a, v, wrong, channel) in &table {
        let (causes, got) = misattribution(a.hidden.as_ref(), v);
        assert_eq!(got, *wrong, "{}: {causes:?}", a.case);
        assert_eq!(
            causes.iter().any(|c| c.right_channel),
            *channel,
            "{}: {causes:?}",
            a.case
        );
    }
    let cases: Vec<(CaseAnswer, Diagnosis)> = table
        .iter()
        .map(|(a, v, ..)| (a.clone(), d(v.clone())))
        .collect();
    let g = grade(&cases);
    let want: Vec<&str> = table
        .iter()
        .filter(|t| t.2)
        .map(|t| t.0.case.as_str())
        .collect();
    assert_eq!(g.misattributed_cases, want);
    assert_eq!(g.confident_misattributions, (want.len(), table.len()));
    assert_eq!(g.misattributions_by_section["null"], (2, 3));
    assert_eq!(g.misattributions_by_section["in-catalogue"], (2, 5));
    assert_eq!(g.misattributions_by_section["out-of-catalogue"], (1, 2));
    assert_eq!(g.misattributions_by_section["wide time-local"], (2, 3));
    // t1, t2, t3: the time-local section (drawn onsets).
    assert_eq!(g.misattributions_by_section["time-local"], (1, 3));
    assert_eq!(g.misattributions_by_section["different histories"], (0, 1));
    let md = render_grades(&g, "x");
    assert!(md.contains("## Confident misattributions"));
    assert!(md.contains("| all cases | 8 / 17 (47 %) | 0 |"), "{md}");
    assert!(
        md.contains("| w2 | wide time-local | accel_bias_plateau x |"),
        "{md}"
    );
    assert!(md.contains("not separable: thermal_lag / gyro_bias_step gyro x (all runs)"));
}

#[test]
fn wide_cases_are_located_in_their_runs_and_calibration_only_ones_are_not_graded() {
    use crate::blind::plan::{CALIBRATION_SCOPE, EventScope};
    let wide = |case: &str, scope: EventScope, run: Option<&str>| {
        let mut a = hidden(case, "gyro_bias_pulse", 1);
        if let Some(h) = a.hidden.as_mut() {
            h.scope = Some(scope);
            h.run = run.map(Into::into);
            h.duration_s = Some(3600.0);
        }
        a
    };
    let with = |events: Vec<TimeLocalEvent>| {
        let mut d = diagnosis(Verdict::Unexplained, None);
        d.events.events = events;
        d
    };
    let cases = vec![
        // Common to every navigation run: an event in any of them counts.
        (
            wide("w1", EventScope::AllNavigationRuns, None),
            with(vec![event("nav2", "gyro y", 10_300.0, 200.0)]),
        ),
        // One run: the other run's event does not.
        (
            wide("w2", EventScope::OneRun, Some("nav1")),
            with(vec![event("nav2", "gyro y", 10_000.0, 200.0)]),
        ),
        // Calibration only: nothing to locate in the navigation runs, not graded.
        (
            wide("w3", EventScope::CalibrationOnly, Some(CALIBRATION_SCOPE)),
            with(vec![]),
        ),
        // An original time-local case keeps its own figure.
        (
            hidden("t1", "gyro_bias_step", 1),
            with(vec![event("nav1", "gyro y", 10_000.0, 200.0)]),
        ),
    ];
    let g = grade(&cases);
    assert_eq!(g.wide_time_local_found, (1, 2));
    assert_eq!(g.wide_time_local_found_on_channel, (1, 2));
    assert_eq!(g.time_local_found, (1, 1));
    let t3 = g.cases[2].time_local.as_ref().unwrap();
    assert!(!t3.onset_graded && t3.shape == "pulse");
    let md = render_grades(&g, "x");
    assert!(md.contains("widened draw: reported with the onset within 3 sigma"));
    assert!(md.contains("calibration only"));
}
