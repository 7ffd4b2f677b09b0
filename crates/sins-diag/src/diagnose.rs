//! The diagnosis as a pipeline of typed stages. Each stage is a function from the values of the
//! stages before it to a value of its own; none changes a value that another stage made (a
//! stage that takes the ranking takes it by value and hands on its own). The stages after the
//! gaps read one [`Context`]; every stage writes its notes to one list, in stage order.
//!
//! | stage | function | value | what the value owns |
//! |---|---|---|---|
//! | twin | `twin_stage` | `Twin` | the candidate kinds and the catalogue as columns; every run's sensitivity pass with the calibration run's absorption folded in; the calibration uncertainty |
//! | gaps | `gap_stage` | `Gaps` | gap series and fit data (walks an identification left open in the twin); the fit problem, its null distribution and test; the catalogue's ranking |
//! | refine | `refine_leaders` (`refine`) | `Refined` | the ranking with its leaders refined; the refinements |
//! | scan | `scan_stage` | `Scanned` | the time-local events and their signals; the ranking once a leading walk has met them; the whitened runs |
//! | rerank | `rerank_stage` | `Reranked` | the calibration run's events through the coefficients; the ranking on the gap less the located events; the gap they leave |
//! | judge | `judge_stage` (`judge`) | `Judged` | the winner's constancy; the verdict after the events, the rival time courses and the design's confounds |
//! | check | `calibration_check` (`cal_innovations`) | `Judged` | the verdict once the calibration run's filter innovations are explained by a named cause, or "unexplained" |
//! | report | `report_stage` | `Diagnosis` | each run's localisation; the winner's fitted series and withheld validation |

use crate::cal_events::absorbed_events;
use crate::cal_innovations::calibration_check;
use crate::calib::{ParamUncertainty, uncertainty};
use crate::catalogue::{Catalogue, catalogue};
use crate::context::{Context, GapFit};
use crate::error::DiagError;
use crate::events::{EventScan, EventSignal};
use crate::gaps::gaps;
use crate::input::{DiagnoseConfig, DiagnosisInput};
use crate::judge::{Judged, Reranked, judge_stage};
use crate::localise::localise;
use crate::problem::{Problem, RunFitData};
use crate::rank::{Evaluated, NullDist, evaluate, finish_ranking, with_scan_multiplicity};
use crate::refine::{Refined, refine_leaders};
use crate::report::{ChiSquareTest, Diagnosis, Note, NoteKind, RunLocalisation};
use crate::sensitivity::RunSensitivity;
use crate::stacked::Stacked;
use crate::timelocal::{Located, leader, ranked_without_events, scan_runs, time_local_events};
use crate::twin::{fold_absorption, twin_passes};
use crate::unresolved::{add_unresolved_walks, leader_contribution, widen_envelopes};
use crate::winner::winner_series;
use sins_imu::EffectKind;

/// Diagnose the gap between the real runs and their twin.
pub fn diagnose(input: &mut DiagnosisInput, cfg: &DiagnoseConfig) -> Result<Diagnosis, DiagError> {
    check_request(input, cfg)?;
    let (cfg, grid_note) = grid_for_duration(cfg, longest_span_s(input));
    let cfg = &cfg;
    let mut notes = vec![Note::new(
        NoteKind::Twin,
        "twin mean = error-free floor (zero unless given); twin spread = sensor noise (white + \
         Gauss-Markov biases, linear covariance through the alignment) + calibration one-sigma \
         (independent coefficients, common to all runs) + a white floor",
    )];
    notes.extend(grid_note);
    let twin = twin_stage(input, cfg, &mut notes)?;
    let Gaps { fit, null, ranked } = gap_stage(input, &twin, cfg, &mut notes)?;
    let absorption = twin.absorption.as_ref();
    let base = Context::new(cfg, &twin.kinds, &twin.cat, &twin.sens, absorption, &fit);
    let Refined {
        ranked,
        refinements,
    } = refine_leaders(input, &base, ranked, &mut notes);
    let ctx = base.with_refinements(&refinements);
    let Scanned {
        ranked,
        events,
        signals,
        stacked,
    } = scan_stage(&ctx, ranked, &mut notes)?;
    let reranked = rerank_stage(input, &ctx, &null, ranked, &events, &signals, &mut notes)?;
    let names: Vec<String> = input.runs.iter().map(|r| r.name.clone()).collect();
    let judged = judge_stage(&ctx, &names, &null, reranked, &events, stacked, &mut notes)?;
    let judged = calibration_check(input, &ctx, judged, &mut notes)?;
    report_stage(input, &ctx, null, events, judged, notes)
}

/// The twin stage's value.
struct Twin {
    /// The candidate kinds.
    kinds: Vec<EffectKind>,
    /// The catalogue as fit columns and walks.
    cat: Catalogue,
    /// Every run's sensitivity pass (the calibration run's absorption folded in).
    sens: Vec<RunSensitivity>,
    /// How the calibration absorbs the candidates, when a calibration run was given.
    absorption: Option<crate::absorb::Absorption>,
    /// The calibration's uncertainty, when given.
    pu: Option<ParamUncertainty>,
}

/// The twin: sensitivities, the calibration run's absorption, the calibration uncertainty.
fn twin_stage(
    input: &mut DiagnosisInput,
    cfg: &DiagnoseConfig,
    notes: &mut Vec<Note>,
) -> Result<Twin, DiagError> {
    let kinds = cfg.candidate_kinds().map_err(|e| DiagError::input("", e))?;
    let cat = catalogue(&kinds);
    let (mut sens, absorption) = twin_passes(input, cfg, &kinds, &cat.layouts)?;
    fold_absorption(input, absorption.as_ref(), &mut sens, notes);
    let pu = uncertainty(
        &input.params,
        input.param_sigma.as_ref(),
        input.param_covariance.as_deref(),
    )?;
    if pu.is_none() {
        notes.push(Note::new(
            NoteKind::CalibrationUncertainty,
            "no calibration uncertainty given: calibration errors ignored",
        ));
    }
    Ok(Twin {
        kinds,
        cat,
        sens,
        absorption,
        pu,
    })
}

/// The gap stage's value: the gaps and fit problem the context lends, the null test and the
/// catalogue's ranking.
struct Gaps {
    fit: GapFit,
    null: ChiSquareTest,
    ranked: Vec<Evaluated>,
}

/// The gaps, the null test and the catalogue's ranking. Slow noise an identification left open
/// is fitted on the gap less the leading candidate's fit (a walk fitted on the gap alone
/// absorbs part of a deterministic effect) and joins the twin; the catalogue is then ranked
/// again with the walks in the twin, whose envelope they widen.
fn gap_stage(
    input: &DiagnosisInput,
    twin: &Twin,
    cfg: &DiagnoseConfig,
    notes: &mut Vec<Note>,
) -> Result<Gaps, DiagError> {
    let (mut series, mut data) = gaps(input, &twin.sens, twin.pu.as_ref(), &twin.cat.columns, cfg)?;
    let floor_var = (cfg.floor_sigma_m.powi(2) - cfg.floor_expected_sigma_m.powi(2)).max(0.0);
    let mut ranking = rank_catalogue(&data, &twin.cat, floor_var, cfg)?;
    let leading_fit = input
        .noise
        .unresolved_walk_per_sqrt_s
        .and_then(|_| leader_contribution(&ranking.ranked, &data));
    if let Some(u) = add_unresolved_walks(&mut data, &input.noise, cfg.null_alpha, leading_fit)? {
        ranking = rank_catalogue(&data, &twin.cat, floor_var, cfg)?;
        notes.push(Note::new(NoteKind::UnresolvedWalks, u.note()));
        let index: Vec<&[usize]> = twin
            .sens
            .iter()
            .map(|s| s.times.fit_index.as_slice())
            .collect();
        widen_envelopes(&mut series, &data, &index, &u);
    }
    let Ranking {
        problem,
        dist,
        null,
        ranked,
    } = ranking;
    let fit = GapFit {
        series,
        data,
        floor_var,
        problem,
        dist,
    };
    Ok(Gaps { fit, null, ranked })
}

/// The fit problem of all runs, the null distribution of its chi-square, the null test and the
/// catalogue evaluated and ranked on it.
struct Ranking {
    problem: Problem,
    dist: NullDist,
    null: ChiSquareTest,
    ranked: Vec<Evaluated>,
}

fn rank_catalogue(
    data: &[RunFitData],
    cat: &Catalogue,
    floor_var: f64,
    cfg: &DiagnoseConfig,
) -> Result<Ranking, DiagError> {
    let problem = Problem::new(&data.iter().collect::<Vec<_>>())?;
    let (mean, var) = problem.null_moments(floor_var);
    let dist = NullDist::from_moments(mean, var);
    let null = dist.test(problem.gls.chi2(), 0, cfg.null_alpha);
    let ranked = evaluate(&problem, &cat.layouts, &cat.walks, &dist, cfg);
    Ok(Ranking {
        problem,
        dist,
        null,
        ranked,
    })
}

/// The scan stage's value.
struct Scanned {
    /// The ranking once a leading walk has met the events.
    ranked: Vec<Evaluated>,
    /// The time-local events.
    events: EventScan,
    /// Each event's fitted contribution (in the order of `events.events`).
    signals: Vec<EventSignal>,
    /// Every run whitened once, for the scan, the rival time courses and the confounds.
    stacked: Option<Stacked>,
}

/// Effects local in time (see `crate::timelocal`).
fn scan_stage(
    ctx: &Context<'_>,
    mut ranked: Vec<Evaluated>,
    notes: &mut Vec<Note>,
) -> Result<Scanned, DiagError> {
    let cfg = ctx.cfg;
    let mut stacked = match cfg.events.enabled {
        true => Some(Stacked::new(&scan_runs(None, &ranked, ctx), &cfg.events)?),
        false => None,
    };
    let prepared = stacked.as_mut().map(|s| s.runs.as_mut_slice());
    let (events, signals) = time_local_events(&mut ranked, ctx, prepared, cfg, notes)?;
    finish_ranking(&mut ranked, ctx.tests.n, cfg);
    Ok(Scanned {
        ranked,
        events,
        signals,
        stacked,
    })
}

/// What the calibration run's events did to the coefficients, in every run's gap; the
/// catalogue ranked again without the located events; the scan's multiplicity.
fn rerank_stage(
    input: &mut DiagnosisInput,
    ctx: &Context<'_>,
    null: &ChiSquareTest,
    mut ranked: Vec<Evaluated>,
    events: &EventScan,
    signals: &[EventSignal],
    notes: &mut Vec<Note>,
) -> Result<Reranked, DiagError> {
    let cfg = ctx.cfg;
    let absorbed = match absorbed_events(input, ctx.absorption, events, ctx.sens, cfg)? {
        Some(a) => {
            notes.push(a.note);
            a.signals
        }
        None => Vec::new(),
    };
    let located = Located {
        events,
        signals,
        absorbed: &absorbed,
    };
    let (again, left) = ranked_without_events(&ranked, &located, ctx, notes)?;
    if let Some(again) = again {
        notes.push(ranked_again_note(events, &ranked, &again));
        ranked = again;
    }
    if null.consistent {
        with_scan_multiplicity(&mut ranked, &ctx.tests, events.tests, cfg);
    }
    Ok(Reranked {
        ranked,
        left,
        absorbed,
    })
}

/// The diagnosis: each run's localisation, the winner's fitted series and withheld validation.
fn report_stage(
    input: &DiagnosisInput,
    ctx: &Context<'_>,
    null: ChiSquareTest,
    events: EventScan,
    judged: Judged,
    notes: Vec<Note>,
) -> Result<Diagnosis, DiagError> {
    let Judged {
        ranked,
        verdict,
        rivals,
        confound,
    } = judged;
    let localisation = localise_runs(input, ctx)?;
    let winner = ranked
        .first()
        .filter(|e| e.report.passes && e.regression.is_some());
    let (series, validation) = winner_series(winner, ctx, &input.runs)?;
    Ok(Diagnosis {
        events,
        n_data: ctx.problem.gls.n,
        null_test: null,
        candidates: ranked.into_iter().map(|e| e.report).collect(),
        verdict,
        localisation,
        validation,
        series,
        notes,
        noise_untrusted: Vec::new(),
        rivals,
        confound,
    })
}

/// The note on the catalogue ranked again without the time-local events outside it.
fn ranked_again_note(events: &EventScan, before: &[Evaluated], after: &[Evaluated]) -> Note {
    let outside = events
        .events
        .iter()
        .filter(|e| e.explained_by.is_none())
        .count();
    let text = format!(
        "catalogue ranked again on the gap less the {outside} time-local event(s) outside it: the \
         leader was {}, it is now {}",
        leader(before),
        leader(after)
    );
    Note::new(NoteKind::TimeLocal, text).figure("events_outside", outside as f64)
}

/// Refuse a request the stages cannot serve.
fn check_request(input: &DiagnosisInput, cfg: &DiagnoseConfig) -> Result<(), DiagError> {
    if input.runs.is_empty() {
        return Err(DiagError::input("", "no run to diagnose"));
    }
    if cfg.output_interval_s == 0 || !cfg.fit_interval_s.is_multiple_of(cfg.output_interval_s) {
        return Err(DiagError::input(
            "",
            "the fit interval must be a whole multiple of the output interval",
        ));
    }
    Ok(())
}

/// The longest time any run's track spans (s).
fn longest_span_s(input: &DiagnosisInput) -> f64 {
    input
        .runs
        .iter()
        .filter_map(|r| Some(r.track.last()?.t_s - r.track.first()?.t_s))
        .fold(0.0, f64::max)
}

/// Fit times per run at most. The twin's covariance of a run is dense (its noise is correlated
/// in time), and its factorisation, the inverse Gram of the fit and the time-local scan's
/// whitened signals cost the cube (and memory the square) of the number of fit times: 450 for
/// the paper's 15 h runs, 4500 for a 150 h run at the default grid, which took more than 10 min
/// and 6.7 GB for one run where 15 h took 25 s.
pub const MAX_FIT_TIMES_PER_RUN: usize = 1024;

/// `cfg` with the fit grid and the scan's onset grid coarsened by the same whole factor when
/// the longest run (navigating `span_s` seconds) would have more than
/// [`MAX_FIT_TIMES_PER_RUN`] fit times, so that the cost per sample of a diagnosis stays flat
/// with the length of the runs; and the note saying so.
fn grid_for_duration(cfg: &DiagnoseConfig, span_s: f64) -> (DiagnoseConfig, Option<Note>) {
    let fit_times = span_s / cfg.fit_interval_s.max(1) as f64;
    let factor = (fit_times / MAX_FIT_TIMES_PER_RUN as f64).ceil() as usize;
    if factor <= 1 {
        return (cfg.clone(), None);
    }
    let mut coarse = cfg.clone();
    coarse.fit_interval_s *= factor;
    coarse.events.onset_every_s *= factor;
    let text = format!(
        "the longest run navigates {:.1} h: the fit grid is every {} s and the time-local scan's \
         onsets every {} s ({factor} times the configured grid), so that no run has more than \
         {MAX_FIT_TIMES_PER_RUN} fit times (the dense twin covariance costs the cube of their \
         number); onsets are located to that grid",
        span_s / 3600.0,
        coarse.fit_interval_s,
        coarse.events.onset_every_s
    );
    let note = Note::new(NoteKind::Twin, text)
        .figure("fit_interval_s", coarse.fit_interval_s as f64)
        .figure("onset_every_s", coarse.events.onset_every_s as f64);
    (coarse, Some(note))
}

/// Each run's gap localised, with its own null test.
fn localise_runs(
    input: &DiagnosisInput,
    ctx: &Context<'_>,
) -> Result<Vec<RunLocalisation>, DiagError> {
    let earth = &ctx.sens[0].model.earth;
    let schuler = (earth.gravity_mps2 / earth.meridian_plus_h_m).sqrt();
    let mut localisation = Vec::new();
    for ((r, s), fd) in input.runs.iter().zip(ctx.series).zip(ctx.data) {
        let p = Problem::new(&[fd])?;
        let (m, v) = p.null_moments(ctx.floor_var);
        let test = NullDist::from_moments(m, v).test(p.gls.chi2(), 0, ctx.cfg.null_alpha);
        localisation.push(localise(s, &r.segment_labels, schuler, test));
    }
    Ok(localisation)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's 15 h runs keep the configured grid; a 150 h run gets a grid five times
    /// coarser, whole multiples of the output interval, with at most the cap of fit times.
    #[test]
    fn long_runs_get_a_coarser_grid_and_short_ones_keep_theirs() {
        let cfg = DiagnoseConfig::default();
        let (same, note) = grid_for_duration(&cfg, 15.0 * 3600.0);
        assert_eq!(same.fit_interval_s, cfg.fit_interval_s);
        assert_eq!(same.events.onset_every_s, cfg.events.onset_every_s);
        assert!(note.is_none());
        let span_s = 150.0 * 3600.0;
        let (coarse, note) = grid_for_duration(&cfg, span_s);
        assert_eq!(coarse.fit_interval_s, 5 * cfg.fit_interval_s);
        assert_eq!(coarse.events.onset_every_s, 5 * cfg.events.onset_every_s);
        assert!(
            coarse
                .fit_interval_s
                .is_multiple_of(coarse.output_interval_s)
        );
        assert!(span_s / coarse.fit_interval_s as f64 <= MAX_FIT_TIMES_PER_RUN as f64);
        assert!(note.is_some_and(|n| n.text.contains("every 600 s")));
    }
}
