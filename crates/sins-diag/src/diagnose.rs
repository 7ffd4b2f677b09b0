//! The diagnosis: sensitivities and twin covariance of every run (one pass each, runs in
//! parallel), the gap on the fit grid, the null test, the candidates, the verdict, the
//! localisation and the withheld validation.

use crate::absorb::{Absorption, CalibrationRun, absorption};
use crate::calib::{ParamUncertainty, uncertainty};
use crate::candidates::RegressionFit;
use crate::constancy::{Winner as ConstancyWinner, constancy};
use crate::error::DiagError;
use crate::events::{
    EventScan, EventSignal, ScanRun, TimeLocalEvent, chi2_with, scan_with_signals,
};
use crate::input::{DiagnoseConfig, DiagnosisInput};
use crate::localise::{GapSeries, localise};
use crate::noise::NoiseSpec;
use crate::pass::Grid;
use crate::problem::{Problem, RunFitData, run_fit_data};
use crate::rank::{
    Evaluated, Layout, NullDist, TestContext, evaluate, finish_ranking, regression_evaluated,
    verdict,
};
use crate::refine::{RefineStart, Refinement, refine};
use crate::replay::temperature_series;
use crate::report::Verdict;
use crate::report::{Diagnosis, RunSeries};
use crate::runs::{output_columns, par_runs, track_at};
use crate::sensitivity::{ColumnId, RunSensitivity, SensitivitySetup, run_sensitivity};
use crate::stats::chi2_sf;
use crate::unresolved::add_unresolved_walks;
use crate::validate::{EvalRun, OutputColumns, Winner, validate};
use crate::walk::fit_walk;
use nalgebra::{DMatrix, DVector};
use sins_imu::ImuErrorParams;
use sins_imu::{EffectKind, Linearity};

/// The settings of the base sensitivity pass.
fn base_setup<'a>(
    params: &'a ImuErrorParams,
    noise: &'a NoiseSpec,
    cfg: &'a DiagnoseConfig,
    kinds: &'a [EffectKind],
) -> SensitivitySetup<'a> {
    SensitivitySetup {
        params,
        noise,
        replay: &cfg.replay,
        candidates: kinds,
        grid: Grid {
            output_every_s: cfg.output_interval_s.max(1),
            fit_every: (cfg.fit_interval_s / cfg.output_interval_s.max(1)).max(1),
        },
        refine: None,
        turn_on_taus_s: if cfg.events.enabled {
            &cfg.events.time_constants_s
        } else {
            &[]
        },
    }
}

/// Sensitivities of every run (the temperature series are computed first when missing).
fn sensitivities(
    input: &mut DiagnosisInput,
    cfg: &DiagnoseConfig,
    kinds: &[EffectKind],
) -> Result<Vec<RunSensitivity>, DiagError> {
    let (params, noise) = (input.params, input.noise);
    let setup = base_setup(&params, &noise, cfg, kinds);
    par_runs(&mut input.runs, cfg.threads, |r| {
        if r.temperatures.is_none() {
            r.temperatures = Some(temperature_series(
                r.source.as_mut(),
                cfg.replay.temperature_rate_half_window_s,
            )?);
        }
        let temps = r
            .temperatures
            .as_ref()
            .ok_or_else(|| DiagError::input(&r.name, "temperature series missing"))?;
        run_sensitivity(&r.name, r.source.as_mut(), &r.site, &r.track, temps, &setup)
    })
}

/// The calibration run's absorption of every deterministic candidate, folded into the
/// candidate columns of every run (none without a calibration run among the inputs).
fn calibration_absorption(
    input: &mut DiagnosisInput,
    cfg: &DiagnoseConfig,
    layouts: &[Layout],
    sens: &mut [RunSensitivity],
    notes: &mut Vec<String>,
) -> Result<Option<Absorption>, DiagError> {
    let Some(name) = input.calibration_run.clone() else {
        notes.push(
            "no calibration run among the inputs: the candidates act on the navigation only, \
             not through the coefficients a calibration in their presence would have biased"
                .into(),
        );
        return Ok(None);
    };
    let params = input.params;
    let noise = input.noise;
    let run = input
        .runs
        .iter_mut()
        .find(|r| r.name == name)
        .ok_or_else(|| DiagError::input(&name, "the calibration run is not among the runs"))?;
    let temps = run
        .temperatures
        .as_ref()
        .ok_or_else(|| DiagError::input(&name, "temperature series missing"))?;
    let comps: Vec<(EffectKind, usize)> = layouts
        .iter()
        .flat_map(|l| (0..l.n).map(move |c| (l.kind, c)))
        .collect();
    let cal = CalibrationRun {
        run: &name,
        source: run.source.as_mut(),
        site: &run.site,
        temps,
    };
    let a = absorption(cal, &params, &noise, &comps, cfg.threads)?;
    for s in sens.iter_mut() {
        a.fold(s, None);
    }
    let given = sins_kf::params_to_vec(&params, params.model);
    let sigma = input
        .param_sigma
        .map(|p| sins_kf::params_to_vec(&p, params.model));
    let worst = sigma.map(|sg| {
        given
            .iter()
            .zip(&a.recalibrated)
            .zip(&sg)
            .map(|((g, r), s)| if *s > 0.0 { (g - r).abs() / s } else { 0.0 })
            .fold(0.0, f64::max)
    });
    notes.push(format!(
        "calibration absorption: run '{name}' recalibrated ({}-state filter, twin noise) once as \
         recorded and once per candidate component with it added, {} components; each candidate \
         acts on the navigation directly and through the coefficients it biases{}",
        params.model.n_states(),
        comps.len(),
        worst.map_or(String::new(), |w| format!(
            "; the recalibration reproduces the given set within {w:.2} sigma"
        ))
    ));
    Ok(Some(a))
}

/// Diagnose the gap between the real runs and their twin.
pub fn diagnose(input: &mut DiagnosisInput, cfg: &DiagnoseConfig) -> Result<Diagnosis, DiagError> {
    if input.runs.is_empty() {
        return Err(DiagError::input("", "no run to diagnose"));
    }
    if cfg.output_interval_s == 0 || !cfg.fit_interval_s.is_multiple_of(cfg.output_interval_s) {
        return Err(DiagError::input(
            "",
            "the fit interval must be a whole multiple of the output interval",
        ));
    }
    let kinds = cfg.candidate_kinds().map_err(|e| DiagError::input("", e))?;
    let mut sens = sensitivities(input, cfg, &kinds)?;
    let mut notes = vec![
        "twin mean = error-free floor (zero unless given); twin spread = sensor noise (white + \
         Gauss-Markov biases, linear covariance through the alignment) + calibration one-sigma \
         (independent coefficients, common to all runs) + a white floor"
            .to_string(),
    ];
    // Columns: deterministic candidates in the candidates' units, uncertain coefficients.
    let mut layouts = Vec::new();
    let mut cand_cols = Vec::new();
    let mut walks = Vec::new();
    for &k in &kinds {
        match k.linearity() {
            Linearity::RandomProcess => {
                walks.push((
                    k,
                    if k.sensor() == sins_imu::effects::Sensor::Gyro {
                        0
                    } else {
                        3
                    },
                ));
            }
            _ => {
                layouts.push(Layout {
                    kind: k,
                    first: cand_cols.len(),
                    n: k.n_components(),
                });
                for c in 0..k.n_components() {
                    cand_cols.push((ColumnId::Effect(k, c), k.unit().si));
                }
            }
        }
    }
    let absorption = calibration_absorption(input, cfg, &layouts, &mut sens, &mut notes)?;
    let pu = uncertainty(
        &input.params,
        input.param_sigma.as_ref(),
        input.param_covariance.as_deref(),
    )?;
    if pu.is_none() {
        notes.push("no calibration uncertainty given: calibration errors ignored".into());
    }
    // Gaps and fit data.
    let walk_step = (cfg.walk_step_s / cfg.fit_interval_s).max(1);
    let mut series = Vec::new();
    let mut data = Vec::new();
    for (r, s) in input.runs.iter().zip(&sens) {
        let twin = |t: f64| r.twin_mean.as_deref().map_or([0.0; 2], |m| track_at(m, t));
        let gap: Vec<[f64; 2]> = s
            .times
            .times_s
            .iter()
            .map(|&t| {
                let (a, b) = (track_at(&r.track, t), twin(t));
                [a[0] - b[0], a[1] - b[1]]
            })
            .collect();
        let gap_fit: Vec<[f64; 2]> = s.times.fit_index.iter().map(|&k| gap[k]).collect();
        let fd = run_fit_data(
            s,
            &gap_fit,
            cfg.floor_sigma_m,
            pu.as_ref(),
            &cand_cols,
            walk_step,
            cfg.fit_interval_s as f64,
        )?;
        let sigma_m = envelope(s, pu.as_ref(), cfg.floor_sigma_m);
        series.push(GapSeries {
            run: r.name.clone(),
            nav_start_s: s.times.nav_start_s,
            t_s: s.times.times_s.clone(),
            segment: s.times.segments.clone(),
            twin_m: s.times.times_s.iter().map(|&t| twin(t)).collect(),
            gap_m: gap,
            sigma_m,
        });
        data.push(fd);
    }
    if let Some(u) = add_unresolved_walks(&mut data, &input.noise, cfg.null_alpha)? {
        notes.push(u.note());
    }
    let all: Vec<&RunFitData> = data.iter().collect();
    let problem = Problem::new(&all)?;
    let n = problem.gls.n;
    let floor_var = (cfg.floor_sigma_m.powi(2) - cfg.floor_expected_sigma_m.powi(2)).max(0.0);
    let (mean, var) = problem.null_moments(floor_var);
    let dist = NullDist::from_moments(mean, var);
    let null = dist.test(problem.gls.chi2(), 0, cfg.null_alpha);
    let mut ranked = evaluate(&problem, &layouts, &walks, &dist, cfg);
    // Nonlinear refinement of the leading deterministic candidates whose linear fit leaves an
    // inconsistent residual, and of a leading kind listed in `cfg.refine`.
    let ctx = TestContext::new(&problem, &layouts, &walks);
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
        let setup = base_setup(&params, &noise, cfg, &kinds);
        let start = RefineStart {
            base: &data,
            base_sens: &sens,
            absorption: absorption.as_ref(),
            p0: &problem,
            layout: l,
            rf: &rf,
            chi0: ctx.chi0,
            stop_above: cfg.refine_competitive * best_residual,
        };
        match refine(input, cfg, &setup, &start) {
            Ok(Some(r)) => {
                notes.push(format!(
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
                ));
                best_residual = best_residual.min(ctx.chi0 - r.rf.fit.dchi2);
                ranked[i] = regression_evaluated(&l, r.rf.clone(), &ctx, &dist, cfg);
                refinements.push(r);
            }
            Ok(None) => {}
            Err(e) => notes.push(format!("{}: refinement failed ({e})", l.kind.name())),
        }
    }
    finish_ranking(&mut ranked, ctx.n, cfg);
    let scope = ScanScope {
        refinements: &refinements,
        walks: &walks,
        sens: &sens,
        data: &data,
        n_tests: ctx.n_tests,
    };
    let (events, signals) = time_local_events(&mut ranked, &scope, cfg, &mut notes)?;
    finish_ranking(&mut ranked, ctx.n, cfg);
    if let Some(again) =
        ranked_without_events(&ranked, &events, &signals, &scope, &layouts, floor_var, cfg)?
    {
        notes.push(format!(
            "catalogue ranked again on the gap less the {} time-local event(s) outside it: the \
             leader was {}, it is now {}",
            events
                .events
                .iter()
                .filter(|e| e.explained_by.is_none())
                .count(),
            leader(&ranked),
            leader(&again)
        ));
        ranked = again;
    }
    let names: Vec<String> = input.runs.iter().map(|r| r.name.clone()).collect();
    if let Some(best) = ranked.iter_mut().find(|e| e.report.passes)
        && let Some((l, rf)) = &best.regression
    {
        let refined = refinements.iter().find(|r| r.layout.kind == l.kind);
        let refined_problem = match refined {
            Some(r) => Some(Problem::new(&r.data.iter().collect::<Vec<_>>())?),
            None => None,
        };
        let zero = vec![0.0; rf.retained.len()];
        let w = ConstancyWinner {
            first: l.first,
            retained: &rf.retained,
            labels: l.kind.component_labels(),
            offset: refined.map_or(&zero, |r| &r.theta_lin),
        };
        let residual = &best.report.residual;
        best.report.constancy = constancy(
            refined_problem.as_ref().unwrap_or(&problem),
            &w,
            &names,
            residual.chi2 / residual.dof.max(1.0),
            cfg.alpha,
        );
    }
    let verdict = with_events(verdict(&problem, &ranked, &null, cfg), &events, &mut notes);
    // Localisation.
    let schuler = (sens[0].model.earth.gravity_mps2 / sens[0].model.earth.meridian_plus_h_m).sqrt();
    let mut localisation = Vec::new();
    for ((r, s), fd) in input.runs.iter().zip(&series).zip(&data) {
        let p = Problem::new(&[fd])?;
        let (m, v) = p.null_moments(floor_var);
        let test = NullDist::from_moments(m, v).test(p.gls.chi2(), 0, cfg.null_alpha);
        localisation.push(localise(s, &r.segment_labels, schuler, test));
    }
    // The deterministic winner: fitted on all runs for the series, validated on withheld data.
    let winner: Option<&Evaluated> = ranked
        .first()
        .filter(|e| e.report.passes && e.regression.is_some());
    let mut validation = Vec::new();
    let mut run_series: Vec<RunSeries> = series
        .iter()
        .zip(&input.runs)
        .map(|(s, r)| to_series(s, &r.segment_labels))
        .collect();
    if let Some((l, rf)) = winner.and_then(|w| w.regression.as_ref()) {
        let refined = refinements.iter().find(|r| r.layout.kind == l.kind);
        let linear_cols: Vec<OutputColumns>;
        let about = match refined {
            Some(r) => Linearisation {
                fit_data: &r.data,
                bases: r.corrected_gap.iter().map(|g| g.as_slice()).collect(),
                cols: &r.out_cols,
                offset: r.theta_lin.clone(),
            },
            None => {
                linear_cols = sens.iter().map(|s| output_columns(s, l)).collect();
                Linearisation {
                    fit_data: &data,
                    bases: series.iter().map(|s| s.gap_m.as_slice()).collect(),
                    cols: &linear_cols,
                    offset: vec![0.0; rf.retained.len()],
                }
            }
        };
        let Linearisation {
            fit_data,
            bases,
            cols,
            offset,
        } = about;
        // The fitted effect on each run: gap - base + columns × (θ - θ_lin).
        for (((rs, s), base), cols) in run_series.iter_mut().zip(&series).zip(&bases).zip(cols) {
            for k in 0..rs.t_s.len() {
                let mut f = [s.gap_m[k][0] - base[k][0], s.gap_m[k][1] - base[k][1]];
                for (i, &c) in rf.retained.iter().enumerate() {
                    f[0] += (rf.fit.theta[i] - offset[i]) * cols[c][k][0];
                    f[1] += (rf.fit.theta[i] - offset[i]) * cols[c][k][1];
                }
                rs.fitted_north_m[k] = f[0];
                rs.fitted_east_m[k] = f[1];
            }
        }
        let w = Winner {
            kind: l.kind.name(),
            labels: l.kind.component_labels(),
            first: l.first,
            retained: &rf.retained,
            offset: &offset,
        };
        let eval: Vec<EvalRun<'_>> = series
            .iter()
            .zip(&bases)
            .zip(cols)
            .zip(&sens)
            .zip(&data)
            .map(|((((s, b), c), se), d)| EvalRun {
                series: s,
                base: b,
                cols: c,
                fit_index: &se.times.fit_index,
                metric: d,
            })
            .collect();
        validation = validate(&w, fit_data, &eval, floor_var)?;
    }
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
    })
}

/// What the time-local scan needs from the diagnosis.
struct ScanScope<'a> {
    refinements: &'a [Refinement],
    walks: &'a [(EffectKind, usize)],
    sens: &'a [RunSensitivity],
    data: &'a [RunFitData],
    n_tests: f64,
}

/// The scan's runs against a deterministic winner's fit (refined if it was), or the twin alone;
/// the other deterministic candidates with their linear fits, to tell whether one explains an
/// event.
fn scan_runs<'a>(
    winner: Option<&Evaluated>,
    ranked: &[Evaluated],
    sc: &ScanScope<'a>,
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

/// The time-local scan of every run (see [`crate::events`]) against the deterministic winner's
/// fit, or the twin alone when a random walk or nothing won. A winning walk is then refitted on
/// the gap less the events no deterministic candidate explains: if it is no longer significant,
/// its evidence was the events (a step or a transient is not a walk) and it is refused;
/// otherwise each of those events that the fitted walk's covariance makes insignificant is
/// explained by the walk.
fn time_local_events(
    ranked: &mut [Evaluated],
    sc: &ScanScope<'_>,
    cfg: &DiagnoseConfig,
    notes: &mut Vec<String>,
) -> Result<(EventScan, Vec<EventSignal>), DiagError> {
    let winner = ranked.first().filter(|e| e.report.passes);
    let runs = scan_runs(winner, ranked, sc);
    let (mut events, signals) = scan_with_signals(&runs, &cfg.events)?;
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
    let p_value = (0.5 * chi2_sf(dchi2, 1.0) * sc.n_tests).min(1.0);
    let top = &mut ranked[0].report;
    if let Some(w) = top.whiteness.as_mut() {
        w.without_events_dchi2 = Some(dchi2);
    }
    // A walk's evidence is spread over its independent increments; when all of it is carried by
    // the events, those events are what the data hold, and the walk only fits them more freely
    // (a free intensity absorbs a step or a transient; its chi-square drop can even exceed the
    // event's, since it also bends to the misfit of the event's grid and shape).
    if p_value >= cfg.alpha {
        notes.push(format!(
            "{}: refused; with the {} time-local event(s) outside the catalogue removed its \
             chi-square drop falls from {:.1} to {:.1} (p {:.2}): the walk was absorbing them",
            kind.name(),
            outside.len(),
            top.dchi2,
            dchi2,
            p_value,
        ));
        if let Some(w) = top.whiteness.as_mut() {
            w.consistent = false;
        }
        return Ok((events, signals));
    }
    let unit = kind.unit();
    for &i in &outside {
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
        if chi2_with(r, &cov, &e.contribution, &others)? < events.threshold_chi2 {
            events.events[i].explained_by = Some(kind.name().to_string());
        }
    }
    Ok((events, signals))
}

/// The fit problem of `data` with the events' fitted contributions taken off their runs' gaps.
fn without_events<'a>(
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
fn leader(ranked: &[Evaluated]) -> &str {
    ranked
        .first()
        .filter(|e| e.report.passes)
        .map_or("none", |e| e.report.kind.as_str())
}

/// The catalogue ranked on the gap less the events no catalogue term explains, when that
/// changes the leader (an effect local in time pulls the fit of slow catalogue signatures: a
/// turn-on transient passes for a g-sensitivity); `None` when there is no such event or the
/// leader stays (the first ranking keeps its refinements).
fn ranked_without_events(
    ranked: &[Evaluated],
    events: &EventScan,
    signals: &[EventSignal],
    sc: &ScanScope<'_>,
    layouts: &[Layout],
    floor_var: f64,
    cfg: &DiagnoseConfig,
) -> Result<Option<Vec<Evaluated>>, DiagError> {
    let mut outside = signals
        .iter()
        .zip(&events.events)
        .filter(|(_, e)| e.explained_by.is_none())
        .map(|(s, _)| s)
        .peekable();
    if outside.peek().is_none() {
        return Ok(None);
    }
    let p2 = without_events(sc.data, outside)?;
    let (mean, var) = p2.null_moments(floor_var);
    let again = evaluate(
        &p2,
        layouts,
        sc.walks,
        &NullDist::from_moments(mean, var),
        cfg,
    );
    Ok((leader(&again) != leader(ranked)).then_some(again))
}

/// The verdict once the time-local events are known: an event no catalogue term explains is a
/// gap the catalogue leaves (none -> unexplained, explained -> partly explained).
fn with_events(verdict: Verdict, events: &EventScan, notes: &mut Vec<String>) -> Verdict {
    let outside: Vec<&TimeLocalEvent> = events
        .events
        .iter()
        .filter(|e| e.explained_by.is_none())
        .collect();
    if events.tests > 0 {
        notes.push(format!(
            "time-local scan: {} tests (steps, ramps, transients of {:?} s on six axes, every \
             onset), Bonferroni threshold chi2 {:.1}; {} event(s), {} outside the catalogue",
            events.tests,
            events
                .detectable
                .iter()
                .filter_map(|d| d.time_constant_s)
                .fold(Vec::<f64>::new(), |mut v, t| {
                    if !v.contains(&t) {
                        v.push(t);
                    }
                    v
                }),
            events.threshold_chi2,
            events.events.len(),
            outside.len()
        ));
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

/// The winner's fit data and columns about its linearisation point (zero, or the refined
/// estimate with the gap corrected by it).
struct Linearisation<'a> {
    fit_data: &'a [RunFitData],
    bases: Vec<&'a [[f64; 2]]>,
    cols: &'a [OutputColumns],
    offset: Vec<f64>,
}

/// Twin 1-sigma `[north, east]` at each output time: noise, calibration, floor.
fn envelope(s: &RunSensitivity, pu: Option<&ParamUncertainty>, floor: f64) -> Vec<[f64; 2]> {
    let cols: Vec<Option<usize>> = pu.map_or(Vec::new(), |p| {
        p.ids.iter().map(|&id| s.column(id)).collect()
    });
    (0..s.times.times_s.len())
        .map(|k| {
            let mut v = [
                s.envelope[k][0] + floor * floor,
                s.envelope[k][1] + floor * floor,
            ];
            if let Some(p) = pu {
                for j in 0..p.factor.ncols() {
                    let (mut n, mut e) = (0.0, 0.0);
                    for (i, c) in cols.iter().enumerate() {
                        if let Some(c) = c {
                            n += s.north_m[*c][k] * p.factor[(i, j)];
                            e += s.east_m[*c][k] * p.factor[(i, j)];
                        }
                    }
                    v[0] += n * n;
                    v[1] += e * e;
                }
            }
            [v[0].max(0.0).sqrt(), v[1].max(0.0).sqrt()]
        })
        .collect()
}

fn to_series(s: &GapSeries, labels: &[String]) -> RunSeries {
    let n = s.t_s.len();
    RunSeries {
        run: s.run.clone(),
        t_s: s.t_s.clone(),
        segment: s
            .segment
            .iter()
            .map(|&g| labels.get(g as usize).cloned().unwrap_or_default())
            .collect(),
        gap_north_m: s.gap_m.iter().map(|g| g[0]).collect(),
        gap_east_m: s.gap_m.iter().map(|g| g[1]).collect(),
        sigma_north_m: s.sigma_m.iter().map(|g| g[0]).collect(),
        sigma_east_m: s.sigma_m.iter().map(|g| g[1]).collect(),
        fitted_north_m: vec![0.0; n],
        fitted_east_m: vec![0.0; n],
    }
}
