//! The verdict stage's winner: its constancy across runs, its fitted effect on every run's
//! gap series, and its prediction of withheld data.

use crate::constancy::{Winner as ConstancyWinner, constancy};
use crate::context::Context;
use crate::error::DiagError;
use crate::input::{DiagnoseConfig, RunData};
use crate::problem::{Problem, RunFitData};
use crate::rank::Evaluated;
use crate::refinement::Refinement;
use crate::report::{RunSeries, ValidationReport};
use crate::runs::output_columns;
use crate::validate::{EvalRun, OutputColumns, Winner, validate};

/// Test whether the leading passing deterministic candidate has one magnitude in every run
/// (on its refined fit data when it was refined); the result goes into its report.
pub(crate) fn winner_constancy(
    ranked: &mut [Evaluated],
    refinements: &[Refinement],
    problem: &Problem,
    names: &[String],
    cfg: &DiagnoseConfig,
) -> Result<(), DiagError> {
    let Some(best) = ranked.iter_mut().find(|e| e.report.passes) else {
        return Ok(());
    };
    let Some((l, rf)) = &best.regression else {
        return Ok(());
    };
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
        refined_problem.as_ref().unwrap_or(problem),
        &w,
        names,
        residual.chi2 / residual.dof.max(1.0),
        cfg.alpha,
    );
    Ok(())
}

/// The report's gap series, with the fitted effect of the deterministic winner (the leading
/// candidate when it passes) fitted on all runs, and the winner's withheld validation.
pub(crate) fn winner_series(
    winner: Option<&Evaluated>,
    sc: &Context<'_>,
    runs: &[RunData],
) -> Result<(Vec<RunSeries>, Vec<ValidationReport>), DiagError> {
    let mut run_series: Vec<RunSeries> = sc
        .series
        .iter()
        .zip(runs)
        .map(|(s, r)| crate::gaps::to_series(s, &r.segment_labels))
        .collect();
    let Some((l, rf)) = winner.and_then(|w| w.regression.as_ref()) else {
        return Ok((run_series, Vec::new()));
    };
    let refined = sc.refinements.iter().find(|r| r.layout.kind == l.kind);
    let linear_cols: Vec<OutputColumns>;
    let about = match refined {
        Some(r) => Linearisation {
            fit_data: &r.data,
            bases: r.corrected_gap.iter().map(|g| g.as_slice()).collect(),
            cols: &r.out_cols,
            offset: r.theta_lin.clone(),
        },
        None => {
            linear_cols = sc.sens.iter().map(|s| output_columns(s, l)).collect();
            Linearisation {
                fit_data: sc.data,
                bases: sc.series.iter().map(|s| s.gap_m.as_slice()).collect(),
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
    for (((rs, s), base), cols) in run_series.iter_mut().zip(sc.series).zip(&bases).zip(cols) {
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
    let eval: Vec<EvalRun<'_>> = sc
        .series
        .iter()
        .zip(&bases)
        .zip(cols)
        .zip(sc.sens)
        .zip(sc.data)
        .map(|((((s, b), c), se), d)| EvalRun {
            series: s,
            base: b,
            cols: c,
            fit_index: &se.times.fit_index,
            metric: d,
        })
        .collect();
    let validation = validate(&w, fit_data, &eval, sc.floor_var)?;
    Ok((run_series, validation))
}

/// The winner's fit data and columns about its linearisation point (zero, or the refined
/// estimate with the gap corrected by it).
struct Linearisation<'a> {
    fit_data: &'a [RunFitData],
    bases: Vec<&'a [[f64; 2]]>,
    cols: &'a [OutputColumns],
    offset: Vec<f64>,
}
