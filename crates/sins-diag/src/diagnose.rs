//! The diagnosis, stage by stage: the twin of every run (`twin`), the gaps and fit data
//! (`gaps`), slow noise an identification left open (`unresolved`), the null test and the
//! catalogue's ranking (`rank`), the nonlinear refinement of the leaders (`refine`), the
//! time-local scan (`timelocal`), the winner's constancy, the verdict, the localisation, and
//! the winner's fitted series and withheld validation (`winner`).

use crate::cal_events::absorbed_events;
use crate::calib::uncertainty;
use crate::confound::confounds;
use crate::error::DiagError;
use crate::events::{EventScan, EventSignal, ScanRun};
use crate::gaps::{Catalogue, catalogue, gaps};
use crate::input::{DiagnoseConfig, DiagnosisInput};
use crate::localise::{GapSeries, localise};
use crate::problem::{Problem, RunFitData};
use crate::rank::{
    Evaluated, NullDist, TestContext, evaluate, finish_ranking, regression_evaluated, verdict,
    with_scan_multiplicity,
};
use crate::refine::{RefineStart, Refinement, refine};
use crate::report::{
    ChiSquareTest, Confound, Diagnosis, Note, NoteKind, RunLocalisation, TimeCourseAlternative,
    Verdict,
};
use crate::rival::{JudgeScope, challenge, named};
use crate::sensitivity::RunSensitivity;
use crate::stacked::Stacked;
use crate::timelocal::{
    Located, ScanScope, leader, ranked_without_events, scan_runs, time_local_events, with_events,
};
use crate::twin::{base_setup, calibration_absorption, sensitivities};
use crate::unresolved::{add_unresolved_walks, leader_contribution, widen_envelopes};
use crate::winner::{WinnerScope, winner_constancy, winner_series};
use sins_imu::EffectKind;

/// Diagnose the gap between the real runs and their twin.
pub fn diagnose(input: &mut DiagnosisInput, cfg: &DiagnoseConfig) -> Result<Diagnosis, DiagError> {
    check_request(input, cfg)?;
    let longest_s = input
        .runs
        .iter()
        .filter_map(|r| Some(r.track.last()?.t_s - r.track.first()?.t_s))
        .fold(0.0, f64::max);
    let (cfg, grid_note) = grid_for_duration(cfg, longest_s);
    let cfg = &cfg;
    let kinds = cfg.candidate_kinds().map_err(|e| DiagError::input("", e))?;
    // The twin: sensitivities, noise covariance, the calibration run's absorption.
    let mut sens = sensitivities(input, cfg, &kinds)?;
    let mut notes = vec![Note::new(
        NoteKind::Twin,
        "twin mean = error-free floor (zero unless given); twin spread = sensor noise (white + \
         Gauss-Markov biases, linear covariance through the alignment) + calibration one-sigma \
         (independent coefficients, common to all runs) + a white floor",
    )];
    notes.extend(grid_note);
    let cat = catalogue(&kinds);
    let absorption = calibration_absorption(input, cfg, &cat.layouts, &mut sens, &mut notes)?;
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
    // The gaps, the null test and the catalogue's ranking.
    let (mut series, mut data) = gaps(input, &sens, pu.as_ref(), &cat.columns, cfg)?;
    let floor_var = (cfg.floor_sigma_m.powi(2) - cfg.floor_expected_sigma_m.powi(2)).max(0.0);
    let mut ranking = rank_catalogue(&data, &cat, floor_var, cfg)?;
    // Slow noise an identification left open, fitted on the gap less the leading candidate's
    // fit (a walk fitted on the gap alone absorbs part of a deterministic effect).
    let leading_fit = input
        .noise
        .unresolved_walk_per_sqrt_s
        .and_then(|_| leader_contribution(&ranking.ranked, &data));
    if let Some(u) = add_unresolved_walks(&mut data, &input.noise, cfg.null_alpha, leading_fit)? {
        // The catalogue ranked again with the walks in the twin, whose envelope they widen.
        ranking = rank_catalogue(&data, &cat, floor_var, cfg)?;
        notes.push(Note::new(NoteKind::UnresolvedWalks, u.note()));
        let index: Vec<&[usize]> = sens.iter().map(|s| s.times.fit_index.as_slice()).collect();
        widen_envelopes(&mut series, &data, &index, &u);
    }
    let Ranking {
        problem,
        dist,
        null,
        mut ranked,
    } = ranking;
    let n = problem.gls.n;
    let ctx = TestContext::new(&problem, &cat.layouts, &cat.walks);
    // Refinement of the leaders.
    let stage = RefineStage {
        kinds: &kinds,
        data: &data,
        sens: &sens,
        absorption: absorption.as_ref(),
        problem: &problem,
        ctx: &ctx,
        dist: &dist,
    };
    let refinements = refine_leaders(input, cfg, &stage, &mut ranked, &mut notes);
    finish_ranking(&mut ranked, ctx.n, cfg);
    // Effects local in time.
    let scope = ScanScope {
        refinements: &refinements,
        walks: &cat.walks,
        sens: &sens,
        data: &data,
        n_tests: ctx.n_tests,
    };
    // Every run whitened once, for the scan, the rival time courses and the confounds.
    let mut stacked = match cfg.events.enabled {
        true => Some(Stacked::new(
            &scan_runs(None, &ranked, &scope),
            &cfg.events,
        )?),
        false => None,
    };
    let (events, signals) = time_local_events(
        &mut ranked,
        &scope,
        stacked.as_mut().map(|s| s.runs.as_mut_slice()),
        cfg,
        &mut notes,
    )?;
    finish_ranking(&mut ranked, ctx.n, cfg);
    // What the calibration run's events did to the coefficients, in every run's gap.
    let absorbed = absorbed_events(input, absorption.as_ref(), &events, &sens, cfg)?;
    let absorbed: Vec<EventSignal> = match absorbed {
        Some(a) => {
            notes.push(a.note);
            a.signals
        }
        None => Vec::new(),
    };
    let located = Located {
        events: &events,
        signals: &signals,
        absorbed: &absorbed,
    };
    let (again, left) =
        ranked_without_events(&ranked, &located, &scope, &cat.layouts, floor_var, cfg)?;
    if let Some(again) = again {
        notes.push(ranked_again_note(&events, &ranked, &again));
        ranked = again;
    }
    if null.consistent {
        with_scan_multiplicity(&mut ranked, &ctx, events.tests, cfg);
    }
    // The verdict, the localisation, the winner's series and validation.
    let names: Vec<String> = input.runs.iter().map(|r| r.name.clone()).collect();
    winner_constancy(&mut ranked, &refinements, &problem, &names, cfg)?;
    let verdict = with_events(verdict(&problem, &ranked, &null, cfg), &events, &mut notes);
    let challenged = Challenge {
        scope: &scope,
        data: &data,
        layouts: &cat.layouts,
        floor_var,
        n_tests: ctx.n_tests,
        left,
        absorbed: &absorbed,
    };
    let (verdict, rivals, confound) =
        challenged.run(verdict, stacked.as_mut(), &ranked, cfg, &mut notes)?;
    let localisation = localise_runs(input, &sens, &series, &data, floor_var, cfg)?;
    let winner = ranked
        .first()
        .filter(|e| e.report.passes && e.regression.is_some());
    let (run_series, validation) = winner_series(
        winner,
        &WinnerScope {
            refinements: &refinements,
            sens: &sens,
            data: &data,
            series: &series,
            runs: &input.runs,
            floor_var,
        },
    )?;
    Ok(Diagnosis {
        events,
        n_data: n,
        null_test: null,
        candidates: ranked.into_iter().map(|e| e.report).collect(),
        verdict,
        localisation,
        validation,
        series: run_series,
        notes,
        noise_untrusted: Vec::new(),
        rivals,
        confound,
    })
}

/// What the last checks of a verdict read: the located events' leftover gap, the rival time
/// courses and the confound of the design.
struct Challenge<'a> {
    scope: &'a ScanScope<'a>,
    data: &'a [RunFitData],
    layouts: &'a [crate::rank::Layout],
    floor_var: f64,
    n_tests: f64,
    left: Option<ChiSquareTest>,
    /// The calibration run's events through the coefficients, taken off every run's gap.
    absorbed: &'a [EventSignal],
}

impl Challenge<'_> {
    /// The verdict once the located events and the rival time courses have been weighed,
    /// the rivals it cites and the confounds of the temperature-driven candidates.
    fn run(
        &self,
        verdict: Verdict,
        stacked: Option<&mut Stacked>,
        ranked: &[Evaluated],
        cfg: &DiagnoseConfig,
        notes: &mut Vec<Note>,
    ) -> Result<(Verdict, Vec<TimeCourseAlternative>, Vec<Confound>), DiagError> {
        let Some(stacked) = stacked else {
            return Ok((verdict, Vec::new(), Vec::new()));
        };
        // The twin-alone gap in the leader's linearisation when it was refined (its linear
        // columns would leave its nonlinearity to the rivals).
        let leader = named(&verdict).into_iter().next();
        let refined = self
            .scope
            .refinements
            .iter()
            .find(|r| leader.as_deref() == Some(r.layout.kind.name()));
        let mut runs = match refined {
            Some(r) => refined_runs(r, self.scope.sens),
            None => scan_runs(None, ranked, self.scope),
        };
        for a in self.absorbed {
            runs[a.run].residual -= &a.contribution;
        }
        stacked.take(&runs, &cfg.events)?;
        let stacked = &*stacked;
        let confound = confounds(
            stacked,
            self.data,
            self.layouts,
            cfg.events.onset_every_s as f64,
        );
        let names_cause = !named(&verdict).is_empty();
        if let Some(left) = self.left.as_ref().filter(|t| t.consistent && names_cause) {
            let text = format!(
                "the time-local events outside the catalogue leave no significant gap (chi2 \
                 {:.1} for {:.1} expected, p {:.2}): the catalogue gets no credit",
                left.chi2, left.dof, left.p_value
            );
            notes.push(
                Note::new(NoteKind::NoCredit, text)
                    .figure("chi2", left.chi2)
                    .figure("dof", left.dof)
                    .figure("p_value", left.p_value),
            );
            return Ok((Verdict::Unexplained, Vec::new(), confound));
        }
        if !names_cause {
            return Ok((verdict, Vec::new(), confound));
        }
        let sc = JudgeScope {
            data: refined.map_or(self.data, |r| &r.data),
            layouts: self.layouts,
            walks: self.scope.walks,
            floor_var: self.floor_var,
            n_tests: self.n_tests,
            absorbed: self.absorbed,
        };
        let (verdict, rivals) = challenge(verdict, stacked, ranked, &sc, cfg, notes)?;
        Ok((verdict, rivals, confound))
    }
}

/// The runs of refinement `r` with the gap of the twin alone in its linearisation: the
/// corrected gap plus the refined columns at the linearisation point.
fn refined_runs<'a>(r: &'a Refinement, sens: &'a [RunSensitivity]) -> Vec<ScanRun<'a>> {
    r.data
        .iter()
        .zip(sens)
        .map(|(fd, s)| {
            let mut residual = fd.gap.clone();
            for (&c, &t) in r.rf.retained.iter().zip(&r.theta_lin) {
                residual.axpy(t, &fd.columns.column(r.layout.first + c), 1.0);
            }
            ScanRun {
                sens: s,
                fit: fd,
                residual,
                nuisance: nalgebra::DMatrix::zeros(fd.gap.len(), 0),
                extra_cov: None,
                candidates: Vec::new(),
            }
        })
        .collect()
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
    sens: &[RunSensitivity],
    series: &[GapSeries],
    data: &[RunFitData],
    floor_var: f64,
    cfg: &DiagnoseConfig,
) -> Result<Vec<RunLocalisation>, DiagError> {
    let earth = &sens[0].model.earth;
    let schuler = (earth.gravity_mps2 / earth.meridian_plus_h_m).sqrt();
    let mut localisation = Vec::new();
    for ((r, s), fd) in input.runs.iter().zip(series).zip(data) {
        let p = Problem::new(&[fd])?;
        let (m, v) = p.null_moments(floor_var);
        let test = NullDist::from_moments(m, v).test(p.gls.chi2(), 0, cfg.null_alpha);
        localisation.push(localise(s, &r.segment_labels, schuler, test));
    }
    Ok(localisation)
}

/// What the refinement of the leaders reads of the diagnosis so far.
struct RefineStage<'a> {
    kinds: &'a [EffectKind],
    data: &'a [RunFitData],
    sens: &'a [RunSensitivity],
    absorption: Option<&'a crate::absorb::Absorption>,
    problem: &'a Problem,
    ctx: &'a TestContext,
    dist: &'a NullDist,
}

/// Nonlinear refinement of the leading deterministic candidates whose linear fit leaves an
/// inconsistent residual, and of a leading kind listed in `cfg.refine`; each refined candidate's
/// entry in `ranked` is replaced by its refined evaluation.
fn refine_leaders(
    input: &mut DiagnosisInput,
    cfg: &DiagnoseConfig,
    st: &RefineStage<'_>,
    ranked: &mut [Evaluated],
    notes: &mut Vec<Note>,
) -> Vec<Refinement> {
    let ctx = st.ctx;
    // Candidates are taken by chi-square drop among the significant ones, not by evidence:
    // a linear fit that an effect's nonlinearity has pushed to an implausible magnitude fails
    // the plausibility prior before its refinement can correct it.
    let mut by_drop: Vec<usize> = (0..ranked.len())
        .filter(|&i| ranked[i].regression.is_some() && ranked[i].report.p_value < cfg.alpha)
        .collect();
    by_drop.sort_by(|&a, &b| ranked[b].report.dchi2.total_cmp(&ranked[a].report.dchi2));
    // The best residual chi-square of a deterministic candidate so far.
    let mut best_residual = ranked
        .iter()
        .filter(|e| e.regression.is_some())
        .map(|e| ctx.chi0 - e.report.dchi2)
        .fold(f64::INFINITY, f64::min);
    let best_linear = best_residual;
    let targets: Vec<usize> = by_drop
        .into_iter()
        .take(cfg.refine_top)
        .filter(|&i| {
            !ranked[i].report.residual.consistent || cfg.refine_kinds().contains(&ranked[i].kind)
        })
        .filter(|&i| ctx.chi0 - ranked[i].report.dchi2 <= cfg.refine_within * best_linear)
        .collect();
    let mut refinements: Vec<Refinement> = Vec::new();
    for i in targets {
        let Some((l, rf)) = ranked[i].regression.clone() else {
            continue;
        };
        let (params, noise) = (input.params, input.noise);
        let setup = base_setup(&params, &noise, cfg, st.kinds);
        let start = RefineStart {
            base: st.data,
            base_sens: st.sens,
            absorption: st.absorption,
            p0: st.problem,
            layout: l,
            rf: &rf,
            chi0: ctx.chi0,
            stop_above: cfg.refine_competitive * best_residual,
        };
        match refine(input, cfg, &setup, &start) {
            Ok(Some(r)) => {
                let text = format!(
                    "{}: refined by {} Gauss-Newton step(s) on the runs replayed with the fitted \
                     effect removed ({}; residual chi-square {:.1} -> {:.1})",
                    l.kind.name(),
                    r.steps,
                    if r.converged {
                        "converged"
                    } else if r.uncompetitive {
                        "stopped: its predicted residual stays far above the best candidate's"
                    } else {
                        "not converged"
                    },
                    ctx.chi0 - rf.fit.dchi2,
                    ctx.chi0 - r.rf.fit.dchi2,
                );
                notes.push(
                    Note::new(NoteKind::Refinement, text)
                        .subject(l.kind.name())
                        .figure("steps", r.steps as f64)
                        .figure("chi2_before", ctx.chi0 - rf.fit.dchi2)
                        .figure("chi2_after", ctx.chi0 - r.rf.fit.dchi2),
                );
                best_residual = best_residual.min(ctx.chi0 - r.rf.fit.dchi2);
                ranked[i] = regression_evaluated(&l, r.rf.clone(), ctx, st.dist, cfg);
                refinements.push(r);
            }
            Ok(None) => {}
            Err(e) => notes.push(
                Note::new(
                    NoteKind::Refinement,
                    format!("{}: refinement failed ({e})", l.kind.name()),
                )
                .subject(l.kind.name()),
            ),
        }
    }
    refinements
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
