//! The time-local stage of the diagnosis: the scan for steps, ramps and transients against the
//! catalogue's leader (see [`crate::events`]), a winning walk refused when the events carried
//! its evidence, the catalogue ranked again without the events, and the verdict amended.

use crate::candidates::RegressionFit;
use crate::context::Context;
use crate::error::DiagError;
use crate::events::{
    DetectableCurve, EventScan, EventSignal, Prepared, ScanRun, TimeLocalEvent, chi2_with,
    scan_prepared, scan_with_signals,
};
use crate::input::DiagnoseConfig;
use crate::problem::{Problem, RunFitData};
use crate::rank::{Evaluated, Layout, NullDist, evaluate, finish_ranking, passes_but_for_shape};
use crate::report::{CandidateReport, ChiSquareTest, Note, NoteKind, Verdict};
use crate::stats::chi2_sf;
use crate::walk::fit_walk;
use nalgebra::{DMatrix, DVector};
use sins_imu::EffectKind;

/// The scan's runs against a deterministic winner's fit (refined if it was), or the twin alone;
/// the other deterministic candidates with their linear fits, to tell whether one explains an
/// event.
pub(crate) fn scan_runs<'a>(
    winner: Option<&Evaluated>,
    ranked: &[Evaluated],
    sc: &Context<'a>,
) -> Vec<ScanRun<'a>> {
    let candidates: Vec<(String, &Layout, &RegressionFit)> = ranked
        .iter()
        .filter_map(|e| {
            e.regression
                .as_ref()
                .map(|(l, rf)| (e.kind.name().to_string(), l, rf))
        })
        .collect();
    let det = winner.and_then(|w| w.regression.as_ref());
    let refined = det.and_then(|(l, _)| sc.refinements.iter().find(|r| r.layout.kind == l.kind));
    let fit_data: &[RunFitData] = refined.map_or(sc.data, |r| &r.data);
    fit_data
        .iter()
        .zip(sc.sens)
        .map(|(fd, s)| {
            let mut residual = fd.gap.clone();
            let mut nuisance = DMatrix::zeros(fd.gap.len(), 0);
            if let Some((l, rf)) = det {
                let offset = refined.map_or(vec![0.0; rf.retained.len()], |r| r.theta_lin.clone());
                let cols: Vec<usize> = rf.retained.iter().map(|&c| l.first + c).collect();
                nuisance = fd.columns.select_columns(cols.iter());
                for (i, &c) in cols.iter().enumerate() {
                    residual.axpy(-(rf.fit.theta[i] - offset[i]), &fd.columns.column(c), 1.0);
                }
            }
            ScanRun {
                sens: s,
                fit: fd,
                residual,
                nuisance,
                extra_cov: None,
                candidates: candidates
                    .iter()
                    .map(|(name, l, rf)| {
                        let mut c = DVector::zeros(fd.gap.len());
                        for (i, &k) in rf.retained.iter().enumerate() {
                            c.axpy(rf.fit.theta[i], &fd.columns.column(l.first + k), 1.0);
                        }
                        (name.clone(), c)
                    })
                    .collect(),
            }
        })
        .collect()
}

/// The time-local scan of every run (see [`crate::events`]; on `prepared` runs when given)
/// against the deterministic winner's fit, or the twin alone when a random walk or nothing won. A winning walk is then refitted on
/// the gap less the events no deterministic candidate explains: if it is no longer significant,
/// its evidence was the events (a step or a transient is not a walk) and it is refused;
/// otherwise each of those events that the fitted walk's covariance makes insignificant is
/// explained by the walk.
pub(crate) fn time_local_events(
    ranked: &mut [Evaluated],
    sc: &Context<'_>,
    prepared: Option<&mut [Prepared]>,
    cfg: &DiagnoseConfig,
    notes: &mut Vec<Note>,
) -> Result<(EventScan, Vec<EventSignal>), DiagError> {
    let winner = ranked.first().filter(|e| e.report.passes);
    let runs = scan_runs(winner, ranked, sc);
    let (mut events, signals) = match prepared {
        Some(p) => scan_prepared(p, &runs, &cfg.events, cfg.threads)?,
        None => scan_with_signals(&runs, &cfg.events)?,
    };
    let walk = winner
        .filter(|w| w.regression.is_none())
        .and_then(|w| sc.walks.iter().find(|(k, _)| *k == w.kind).copied());
    // The events no deterministic candidate explains.
    let outside: Vec<usize> = (0..signals.len())
        .filter(|&i| events.events[i].explained_by.is_none())
        .collect();
    let (Some((kind, first)), false) = (walk, outside.is_empty()) else {
        return Ok((events, signals));
    };
    // The walk refitted on the gap less those events.
    let p2 = without_events(sc.data, outside.iter().map(|&i| &signals[i]))?;
    let dchi2 = (0..3)
        .map(|a| {
            let b = first + a;
            fit_walk(
                &p2,
                &p2.walks[b],
                &p2.walk_blocks[b],
                kind.typical_magnitude_si(),
            )
            .dchi2
        })
        .fold(0.0, f64::max);
    let p_value = (0.5 * chi2_sf(dchi2, 1.0) * sc.tests.n_tests).min(1.0);
    let top = &mut ranked[0].report;
    if let Some(w) = top.whiteness.as_mut() {
        w.without_events_dchi2 = Some(dchi2);
    }
    // A walk's evidence is spread over its independent increments; when all of it is carried by
    // the events, those events are what the data hold, and the walk only fits them more freely
    // (a free intensity absorbs a step or a transient; its chi-square drop can even exceed the
    // event's, since it also bends to the misfit of the event's grid and shape).
    if p_value >= cfg.alpha {
        // Unless the events are the walk's excursions, fitted one by one (see `excursions`).
        let kept = excursions(&runs, &signals, &events, &outside, top, first, kind, sc)?;
        if let Some((walk_bic, events_bic)) = kept {
            let text = format!(
                "{}: kept; the {} time-local event(s) outside the catalogue are insignificant \
                 under its fitted wander, and it explains the gap with fewer parameters (BIC \
                 gain {:.1} against {:.1} for the events)",
                kind.name(),
                outside.len(),
                walk_bic,
                events_bic
            );
            notes.push(
                Note::new(NoteKind::TimeLocal, text)
                    .subject(kind.name())
                    .figure("walk_bic", walk_bic)
                    .figure("events_bic", events_bic),
            );
            for &i in &outside {
                events.events[i].explained_by = Some(kind.name().to_string());
            }
            return Ok((events, signals));
        }
        let text = format!(
            "{}: refused; with the {} time-local event(s) outside the catalogue removed its \
             chi-square drop falls from {:.1} to {:.1} (p {:.2}): the walk was absorbing them",
            kind.name(),
            outside.len(),
            top.dchi2,
            dchi2,
            p_value,
        );
        notes.push(
            Note::new(NoteKind::TimeLocal, text)
                .subject(kind.name())
                .figure("dchi2", top.dchi2)
                .figure("dchi2_without_events", dchi2)
                .figure("p_value", p_value),
        );
        if let Some(w) = top.whiteness.as_mut() {
            w.consistent = false;
        }
        return Ok((events, signals));
    }
    let under = under_walk(
        &runs,
        &signals,
        &outside,
        top,
        first,
        kind,
        events.threshold_chi2,
    )?;
    for (&i, u) in outside.iter().zip(under) {
        if u {
            events.events[i].explained_by = Some(kind.name().to_string());
        }
    }
    Ok((events, signals))
}

/// The walk `top` keeps its evidence against the events `outside` when every one is a pulse or
/// a ramp to a plateau, its BIC gain beats theirs (Δχ² − k ln n: one intensity per retained
/// component against size, onset and duration per event), and its fitted wander makes each
/// insignificant: the events are then its excursions, fitted one by one. A step or a ramp is
/// refused as before: a walk fits one more freely than its single intensity counts for, and at
/// the walk's 20 min lumps a step is no outlier increment. Returns the two BIC gains when kept.
#[allow(clippy::too_many_arguments)]
fn excursions(
    runs: &[ScanRun<'_>],
    signals: &[EventSignal],
    events: &EventScan,
    outside: &[usize],
    top: &CandidateReport,
    first: usize,
    kind: EffectKind,
    sc: &Context<'_>,
) -> Result<Option<(f64, f64)>, DiagError> {
    let shapes_only = outside
        .iter()
        .all(|&i| matches!(events.events[i].shape.as_str(), "pulse" | "plateau"));
    if !shapes_only {
        return Ok(None);
    }
    let rows: usize = sc.data.iter().map(|d| d.gap.len()).sum();
    let ln_n = (rows.max(2) as f64).ln();
    let k_walk = top.components.iter().filter(|c| c.retained).count() as f64;
    let walk_bic = top.dchi2 - k_walk * ln_n;
    let events_bic: f64 = outside
        .iter()
        .map(|&i| {
            let e = &events.events[i];
            e.chi2 - event_parameters(&e.shape) * ln_n
        })
        .sum();
    if walk_bic <= events_bic {
        return Ok(None);
    }
    let under = under_walk(
        runs,
        signals,
        outside,
        top,
        first,
        kind,
        events.threshold_chi2,
    )?;
    Ok(under.iter().all(|&u| u).then_some((walk_bic, events_bic)))
}

/// Whether each of the events `outside` is insignificant (below `threshold`) under the
/// covariance of the walk `top` (kind `kind`, first bias axis `first`) at its fitted
/// intensity, with the run's other events projected out.
fn under_walk(
    runs: &[ScanRun<'_>],
    signals: &[EventSignal],
    outside: &[usize],
    top: &CandidateReport,
    first: usize,
    kind: EffectKind,
    threshold: f64,
) -> Result<Vec<bool>, DiagError> {
    let unit = kind.unit();
    outside
        .iter()
        .map(|&i| {
            let e = &signals[i];
            let r = &runs[e.run];
            let mut cov = DMatrix::zeros(r.residual.len(), r.residual.len());
            for (a, c) in top.components.iter().enumerate() {
                if let Some(v) = r.fit.walks.get(first + a).filter(|_| c.retained) {
                    cov += v * v.transpose() * unit.to_si(c.value).powi(2);
                }
            }
            let others: Vec<&DVector<f64>> = signals
                .iter()
                .enumerate()
                .filter(|(j, o)| *j != i && o.run == e.run)
                .map(|(_, o)| &o.contribution)
                .collect();
            Ok(chi2_with(r, &cov, &e.contribution, &others)? < threshold)
        })
        .collect()
}

/// Free parameters of an event of `shape`: its size and onset, and a time constant, duration
/// or rise time when it has one (a turn-on transient's onset is known).
fn event_parameters(shape: &str) -> f64 {
    match shape {
        "step" | "ramp" | "turn-on transient" => 2.0,
        _ => 3.0,
    }
}

/// The fit problem of `data` with the events' fitted contributions taken off their runs' gaps.
pub(crate) fn without_events<'a>(
    data: &[RunFitData],
    events: impl Iterator<Item = &'a EventSignal>,
) -> Result<Problem, DiagError> {
    let mut corrected = data.to_vec();
    for e in events {
        corrected[e.run].gap -= &e.contribution;
    }
    Problem::new(&corrected.iter().collect::<Vec<_>>())
}

/// The leading passing candidate's name, or `none`.
pub(crate) fn leader(ranked: &[Evaluated]) -> &str {
    ranked
        .first()
        .filter(|e| e.report.passes)
        .map_or("none", |e| e.report.kind.as_str())
}

/// The located events the catalogue is ranked again without.
pub(crate) struct Located<'a> {
    /// The scan.
    pub events: &'a EventScan,
    /// Each event's fitted contribution (in the order of `events.events`).
    pub signals: &'a [EventSignal],
    /// The calibration run's events through the coefficients (see `crate::cal_events`).
    pub absorbed: &'a [EventSignal],
}

/// The catalogue ranked on the gap less the events no catalogue term explains (and the
/// calibration run's events' path through the coefficients), when that changes the leader
/// (an effect local in time pulls the fit of slow catalogue signatures: a turn-on transient
/// passes for a g-sensitivity), and the null test of that gap: when the located events leave
/// no significant gap, the catalogue gets no credit. `None`s when there is no such event; no
/// ranking when the leader stays (the first ranking keeps its refinements).
pub(crate) fn ranked_without_events(
    ranked: &[Evaluated],
    located: &Located<'_>,
    sc: &Context<'_>,
    notes: &mut Vec<Note>,
) -> Result<(Option<Vec<Evaluated>>, Option<ChiSquareTest>), DiagError> {
    let cfg = sc.cfg;
    let events = located.events;
    let mut outside = located
        .signals
        .iter()
        .zip(&events.events)
        .filter(|(_, e)| e.explained_by.is_none())
        .map(|(s, _)| s)
        .peekable();
    if outside.peek().is_none() {
        return Ok((None, None));
    }
    let p2 = without_events(sc.data, outside.chain(located.absorbed))?;
    let (mean, var) = p2.null_moments(sc.floor_var);
    let dist = NullDist::from_moments(mean, var);
    // The events' sizes and onsets were fitted: one size and one onset each.
    let fitted = 2 * events
        .events
        .iter()
        .filter(|e| e.explained_by.is_none())
        .count();
    let left = dist.test(p2.gls.chi2(), fitted, cfg.null_alpha);
    let mut again = evaluate(&p2, sc.layouts, sc.walks, &dist, cfg);
    let carried = keep_shape_refusals(&mut again, ranked);
    if !carried.is_empty() {
        finish_ranking(&mut again, sc.tests.n, cfg);
    }
    // Said of the walks the rule kept out: those that pass every other test there.
    for e in again.iter().filter(|e| carried.contains(&e.kind)) {
        let r = &e.report;
        if !passes_but_for_shape(r, cfg) {
            continue;
        }
        let lag1_z = r.whiteness.as_ref().map_or(f64::NAN, |w| w.lag1_z);
        let text = format!(
            "{}: not named; on the gap less the events it is significant (chi-square drop \
             {:.1}) and its increments pass the shape test (lag-one z {:.1}), but they failed \
             it on the whole gap: a walk must pass with the events in place as well",
            r.kind, r.dchi2, lag1_z
        );
        notes.push(
            Note::new(NoteKind::TimeLocal, text)
                .subject(r.kind.clone())
                .figure("dchi2_without_events", r.dchi2)
                .figure("lag1_z_without_events", lag1_z),
        );
    }
    let changed = leader(&again) != leader(ranked);
    Ok((changed.then_some(again), Some(left)))
}

/// A noise term whose increments failed the shape test on the whole gap is not promoted by
/// removing the events: with pulses in the scan, the half-cycles of an oscillation are taken
/// one by one as pulses, and what they leave can pass for a walk of another channel
/// (tests/it/walk_shape.rs, lag-one z −2.1 on the gap less the pulses against below −3 on the
/// whole gap). A walk must pass with the events in place as well as without them. Returns the
/// kinds whose refusal was carried over.
fn keep_shape_refusals(again: &mut [Evaluated], before: &[Evaluated]) -> Vec<EffectKind> {
    let mut carried = Vec::new();
    for e in again.iter_mut() {
        let refused = before
            .iter()
            .find(|b| b.kind == e.kind)
            .and_then(|b| b.report.whiteness.as_ref())
            .is_some_and(|w| !w.consistent);
        if let Some(w) = e
            .report
            .whiteness
            .as_mut()
            .filter(|w| w.consistent && refused)
        {
            w.consistent = false;
            carried.push(e.kind);
        }
    }
    carried
}

/// The verdict once the time-local events are known: an event no catalogue term explains is a
/// gap the catalogue leaves (none -> unexplained, explained -> partly explained).
pub(crate) fn with_events(verdict: Verdict, events: &EventScan, notes: &mut Vec<Note>) -> Verdict {
    let outside: Vec<&TimeLocalEvent> = events
        .events
        .iter()
        .filter(|e| e.explained_by.is_none())
        .collect();
    if events.tests > 0 {
        let distinct = |shape: &str, time: fn(&DetectableCurve) -> Option<f64>| {
            events
                .detectable
                .iter()
                .filter(|d| d.shape == shape)
                .filter_map(time)
                .fold(Vec::<f64>::new(), |mut v, t| {
                    if !v.contains(&t) {
                        v.push(t);
                    }
                    v
                })
        };
        let text = format!(
            "time-local scan: {} tests (steps, ramps, transients of {:?} s, pulses of {:?} s, \
             ramps to a plateau rising over {:?} s, on six axes, every onset), Bonferroni \
             threshold chi2 {:.1}; {} event(s), {} outside the catalogue",
            events.tests,
            distinct("transient", |d| d.time_constant_s),
            distinct("pulse", |d| d.duration_s),
            distinct("plateau", |d| d.duration_s),
            events.threshold_chi2,
            events.events.len(),
            outside.len()
        );
        notes.push(
            Note::new(NoteKind::TimeLocal, text)
                .figure("tests", events.tests as f64)
                .figure("threshold_chi2", events.threshold_chi2)
                .figure("events", events.events.len() as f64)
                .figure("events_outside", outside.len() as f64),
        );
    }
    if outside.is_empty() {
        return verdict;
    }
    match verdict {
        Verdict::NoSignificantGap => Verdict::Unexplained,
        Verdict::Explained { by } => Verdict::PartlyExplained { by },
        v => v,
    }
}
