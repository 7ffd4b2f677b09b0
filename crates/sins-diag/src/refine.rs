//! Nonlinear refinement of a deterministic candidate: Gauss-Newton about the fitted effect.
//!
//! The ranking fits every candidate with columns linearised about the twin (no effect). An
//! effect large enough to bend the error dynamics (a size effect under 10 Hz vibration that
//! drives the position error to hundreds of km, a 35 ppm gyro asymmetry) or whose
//! perturbation feeds its own inputs (the time offset) is then misjudged: its magnitude is
//! biased and its residual looks inconsistent, so a random walk may win instead. Each
//! refinement step replays the real runs with the current estimate removed from every raw
//! sample ([`crate::replay::replay_corrected`], the real pipeline itself), takes the corrected
//! gap as the new data, recomputes the candidate's columns about the corrected run (one
//! sensitivity pass, the perturbation removed from the increments) and fits the update. The
//! residual chi-square of a refined candidate is that of the corrected runs after the last
//! (small) linear step: a nonlinear likelihood, not an extrapolation.

use crate::absorb::{Absorption, CalibrationRun};
use crate::candidates::{RegressionFit, forward_select, select};
use crate::context::Context;
use crate::error::DiagError;
use crate::input::{DiagnoseConfig, DiagnosisInput};
use crate::problem::{Problem, RunFitData};
use crate::rank::{Evaluated, Layout, finish_ranking, regression_evaluated};
use crate::refinement::Refinement;
use crate::replay::replay_corrected;
use crate::report::{Note, NoteKind};
use crate::runs::{output_columns, par_runs, track_at};
use crate::sensitivity::{RunSensitivity, SensitivitySetup, run_sensitivity};
use crate::twin::base_setup;
use crate::validate::OutputColumns;
use sins_imu::{EffectKind, EffectSpec, ImuErrorParams};

/// One corrected pass of every run: the corrected gap (output grid) and the candidate's
/// columns about the corrected runs.
fn corrected_pass(
    input: &mut DiagnosisInput,
    cfg: &DiagnoseConfig,
    setup: &SensitivitySetup<'_>,
    spec: &EffectSpec,
) -> Result<Vec<CorrectedRun>, DiagError> {
    let params = *setup.params;
    par_runs(&mut input.runs, cfg.threads, |r| {
        let temps = r
            .temperatures
            .as_ref()
            .ok_or_else(|| DiagError::input(&r.name, "temperature series missing"))?;
        let mut effect = spec.build(&params);
        let real = replay_corrected(
            &r.name,
            r.source.as_mut(),
            &params,
            &r.site,
            &cfg.replay,
            effect.as_mut(),
            temps,
        )?;
        let sens = run_sensitivity(
            &r.name,
            r.source.as_mut(),
            &r.site,
            &real.points,
            temps,
            setup,
        )?;
        let gap = sens
            .times
            .times_s
            .iter()
            .map(|&t| {
                let a = track_at(&real.points, t);
                let b = r.twin_mean.as_deref().map_or([0.0; 2], |m| track_at(m, t));
                [a[0] - b[0], a[1] - b[1]]
            })
            .collect();
        Ok((gap, sens))
    })
}

/// One run corrected: its gap on the output grid (m) and the candidate's columns about it.
type CorrectedRun = (Vec<[f64; 2]>, RunSensitivity);

/// Refine candidate `l` from its linear fit `rf` on the context's fit data, sensitivity passes,
/// absorption and problem (at most `cfg.refine_steps` steps).
///
/// The refinement starts from the strongest single component of the linear fit alone: when
/// the linear model is off, the further components of its forward selection mostly absorb the
/// linearisation error (a size effect then spreads over all nine lever arms). Each step fits
/// the update of the components kept so far and adds, by forward selection, any component
/// whose chi-square drop on the corrected runs is at least `max(z_keep², ln n)`. At most
/// `max_steps` Gauss-Newton steps; a step that raises the corrected chi-square ends the
/// iteration at the previous point, and a step whose predicted residual stays above
/// `stop_above` is the last (a candidate that cannot compete with the leader;
/// `f64::INFINITY`: never).
pub(crate) fn refine(
    input: &mut DiagnosisInput,
    ctx: &Context<'_>,
    base_setup: &SensitivitySetup<'_>,
    l: Layout,
    rf: &RegressionFit,
    stop_above: f64,
) -> Result<Option<Refinement>, DiagError> {
    let (cfg, base, base_sens) = (ctx.cfg, ctx.data, ctx.sens);
    let (absorption, p0, chi0) = (ctx.absorption, ctx.problem, ctx.tests.chi0);
    let max_steps = cfg.refine_steps;
    let Some(&c0) = rf.retained.first() else {
        return Ok(None);
    };
    let si = l.kind.unit().si;
    let usable: Vec<usize> = (0..l.n)
        .filter(|&c| rf.sigma_alone[c].is_finite())
        .collect();
    let min_gain = (cfg.z_keep * cfg.z_keep).max((p0.gls.n as f64).ln());
    let mut retained = vec![c0];
    let mut theta: Vec<f64> = p0
        .gls
        .fit(&select(&p0.a, l.first, &retained))
        .theta
        .iter()
        .copied()
        .collect();
    let mut best: Option<Refinement> = None;
    for step in 1..=max_steps.max(1) {
        let mut values = vec![0.0; l.n];
        for (i, &c) in retained.iter().enumerate() {
            values[c] = theta[i] * si;
        }
        let Some(spec) = EffectSpec::zero(l.kind).with_magnitudes_si(&values) else {
            return Ok(best);
        };
        // The set the calibration would have identified without the effect.
        let params = params_without(input, absorption, base_setup, l.kind, &values)?;
        let setup = SensitivitySetup {
            params: &params,
            refine: Some((l.kind, values)),
            turn_on_taus_s: &[],
            ..*base_setup
        };
        let mut passes = corrected_pass(input, cfg, &setup, &spec)?;
        if let Some(a) = absorption {
            for ((_, s), b) in passes.iter_mut().zip(base_sens) {
                a.fold(s, Some(b));
            }
        }
        let (data, corrected_gap, out_cols) = corrected_fit_data(base, passes, &l);
        let all: Vec<&RunFitData> = data.iter().collect();
        let p = Problem::new(&all)?;
        let chi2_at_lin = p.gls.chi2();
        if let Some(b) = best.as_mut()
            && chi2_at_lin.partial_cmp(&b.chi2_at_lin) != Some(std::cmp::Ordering::Less)
        {
            // The step made things worse (or NaN): keep the previous linearisation point, whose
            // residual was evaluated, without its step.
            b.rf.fit.theta = nalgebra::DVector::from_vec(b.theta_lin.clone());
            b.rf.fit.dchi2 = (chi0 - b.chi2_at_lin).max(0.0);
            break;
        }
        let (now, delta) = forward_select(&p, l.first, &usable, retained.clone(), min_gain);
        let Some(delta) = delta else {
            return Ok(best);
        };
        let added = now.len() > retained.len();
        retained = now;
        theta.resize(retained.len(), 0.0);
        let converged = !added
            && (0..retained.len())
                .all(|i| delta.theta[i].abs() <= 0.1 * delta.cov[(i, i)].max(0.0).sqrt());
        let theta_lin = theta.clone();
        for (t, d) in theta.iter_mut().zip(delta.theta.iter()) {
            *t += d;
        }
        let residual = chi2_at_lin - delta.dchi2;
        let mut fit = delta.clone();
        fit.theta = nalgebra::DVector::from_vec(theta.clone());
        fit.dchi2 = (chi0 - residual).max(0.0);
        best = Some(Refinement {
            layout: l,
            rf: RegressionFit {
                retained: retained.clone(),
                fit,
                sigma_alone: rf.sigma_alone.clone(),
            },
            data,
            corrected_gap,
            out_cols,
            theta_lin,
            chi2_at_lin,
            steps: step,
            converged,
            uncompetitive: !converged && residual > stop_above,
        });
        if converged || residual > stop_above {
            break;
        }
    }
    Ok(best)
}

/// The parameter set the calibration would have identified without the effect of `values`
/// (the given set when no calibration run was given).
fn params_without(
    input: &mut DiagnosisInput,
    absorption: Option<&Absorption>,
    base_setup: &SensitivitySetup<'_>,
    kind: EffectKind,
    values: &[f64],
) -> Result<ImuErrorParams, DiagError> {
    let Some(a) = absorption else {
        return Ok(*base_setup.params);
    };
    let cal = CalibrationRun::among(&mut input.runs, &a.run)?;
    a.without_exact(cal, base_setup.params, base_setup.noise, kind, values)
}

/// The base fit data with each run's gap and the candidate's columns replaced by those of its
/// corrected pass; also the corrected gaps and columns on the output grid.
fn corrected_fit_data(
    base: &[RunFitData],
    passes: Vec<CorrectedRun>,
    l: &Layout,
) -> (Vec<RunFitData>, Vec<Vec<[f64; 2]>>, Vec<OutputColumns>) {
    let mut data = Vec::with_capacity(base.len());
    let mut corrected_gap = Vec::new();
    let mut out_cols = Vec::new();
    for (fd, (gap, s)) in base.iter().zip(passes) {
        let mut fd = fd.clone();
        for (j, &k) in s.times.fit_index.iter().enumerate() {
            fd.gap[2 * j] = gap[k][0];
            fd.gap[2 * j + 1] = gap[k][1];
        }
        let cols = output_columns(&s, l);
        for (c, out) in cols.iter().enumerate() {
            for (j, &k) in s.times.fit_index.iter().enumerate() {
                fd.columns[(2 * j, l.first + c)] = out[k][0];
                fd.columns[(2 * j + 1, l.first + c)] = out[k][1];
            }
        }
        data.push(fd);
        corrected_gap.push(gap);
        out_cols.push(cols);
    }
    (data, corrected_gap, out_cols)
}

/// The refine stage's value.
pub(crate) struct Refined {
    /// The ranking with each refined candidate's evaluation in place of its linear one.
    pub ranked: Vec<Evaluated>,
    /// The refinements.
    pub refinements: Vec<Refinement>,
}

/// Nonlinear refinement of the leading deterministic candidates whose linear fit leaves an
/// inconsistent residual, and of a leading kind listed in `cfg.refine`; each refined candidate's
/// entry in `ranked` is replaced by its refined evaluation, and the ranking finished again.
pub(crate) fn refine_leaders(
    input: &mut DiagnosisInput,
    st: &Context<'_>,
    mut ranked: Vec<Evaluated>,
    notes: &mut Vec<Note>,
) -> Refined {
    let (cfg, ctx) = (st.cfg, &st.tests);
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
        let stop_above = cfg.refine_competitive * best_residual;
        match refine(input, st, &setup, l, &rf, stop_above) {
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
    finish_ranking(&mut ranked, ctx.n, cfg);
    Refined {
        ranked,
        refinements,
    }
}
