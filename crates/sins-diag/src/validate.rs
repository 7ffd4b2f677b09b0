//! Withheld validation: fit the winning effect without one run (leave-one-run-out; with a single
//! run, on its first half), predict the withheld run (the second half) with
//! `twin + effect(θ)`, and compare the maximum-horizontal-error gap, the RMS gap and the
//! systematic gap (the part of the chi-square beyond the twin's own spread) before and after.
//! For a refined winner `effect(θ)` is the nonlinear correction at the refined point plus the
//! columns about it times the step to the withheld fit (the withheld run enters only through
//! the linearisation point, at second order). A fit that does not determine the effect (no
//! retained component at |z| ≥ 3 on the fitting data, e.g. a vibration effect fitted on a
//! calibration run without vibration) is reported as not informative and its prediction is not
//! made.

use crate::candidates::select;
use crate::error::DiagError;
use crate::localise::GapSeries;
use crate::problem::{Problem, RunFitData};
use crate::report::{GapMetrics, ValidationReport};

/// The winner's columns on one run's output grid: `[component][output point] = [north, east]`
/// in metres per unit of the candidate.
pub type OutputColumns = Vec<Vec<[f64; 2]>>;

/// What the validation needs about the winner.
pub struct Winner<'a> {
    /// Kind name.
    pub kind: &'a str,
    /// Component labels.
    pub labels: &'a [&'static str],
    /// First column of the candidate in the fit data.
    pub first: usize,
    /// Retained components.
    pub retained: &'a [usize],
    /// Linearisation point of the fit data (candidate units, retained components): zero for a
    /// linear fit, the refined estimate for a refined one, whose fit data hold the gap with the
    /// effect at this point removed.
    pub offset: &'a [f64],
}

/// One run as the validation evaluates it.
pub struct EvalRun<'a> {
    /// The gap before (real - twin) on the output grid.
    pub series: &'a GapSeries,
    /// The gap with the winner at its linearisation point removed (equal to the gap for a
    /// linear fit).
    pub base: &'a [[f64; 2]],
    /// The winner's columns about the linearisation point.
    pub cols: &'a OutputColumns,
    /// Output index of each fit point.
    pub fit_index: &'a [usize],
    /// The run's fit data before any refinement: its covariance is the metric of the
    /// systematic gap.
    pub metric: &'a RunFitData,
}

/// Metrics of `series` points `keep` against a prediction `pred` of the gap.
fn metrics(s: &GapSeries, keep: &[usize], pred: &dyn Fn(usize) -> [f64; 2]) -> GapMetrics {
    let (mut real_max, mut pred_max, mut sum) = (0.0f64, 0.0f64, 0.0);
    for &k in keep {
        let t = s.twin_m[k];
        let g = s.gap_m[k];
        let p = pred(k);
        real_max = real_max.max((t[0] + g[0]).hypot(t[1] + g[1]));
        pred_max = pred_max.max((t[0] + p[0]).hypot(t[1] + p[1]));
        sum += (g[0] - p[0]).powi(2) + (g[1] - p[1]).powi(2);
    }
    GapMetrics {
        max_horizontal_gap_m: (real_max - pred_max).abs(),
        rms_gap_m: (sum / keep.len().max(1) as f64).sqrt(),
    }
}

fn shrink(before: f64, after: f64) -> f64 {
    if before > 0.0 {
        100.0 * (1.0 - after / before)
    } else {
        0.0
    }
}

/// The systematic gap of the residual `resid(k)` (output index `k`) on the fit points of
/// `run` inside `keep`: `√max(0, rᵀ S⁻¹ r - E₀)`, the part of the chi-square beyond what the
/// twin's noise and calibration uncertainty give on average (`E₀`, with the white floor the
/// data are expected to carry, `floor_var` less than the metric's).
fn systematic(
    run: &EvalRun<'_>,
    keep: &[usize],
    floor_var: f64,
    resid: &dyn Fn(usize) -> [f64; 2],
) -> Result<f64, DiagError> {
    let pts: Vec<usize> = (0..run.fit_index.len())
        .filter(|&j| keep.binary_search(&run.fit_index[j]).is_ok())
        .collect();
    if pts.is_empty() {
        return Ok(0.0);
    }
    let mut fd = run.metric.subset(&pts);
    for (j, &p) in pts.iter().enumerate() {
        let r = resid(run.fit_index[p]);
        fd.gap[2 * j] = r[0];
        fd.gap[2 * j + 1] = r[1];
    }
    let p = Problem::new(&[&fd])?;
    let (mean, _) = p.null_moments(floor_var);
    Ok((p.gls.chi2() - mean).max(0.0).sqrt())
}

/// Fit the winner on `fit` and report the gap on the output points `keep` of `eval`.
fn one(
    w: &Winner<'_>,
    fit: &[&RunFitData],
    fitted_on: String,
    eval: &EvalRun<'_>,
    keep: &[usize],
    evaluated_on: String,
    floor_var: f64,
) -> Result<ValidationReport, DiagError> {
    let p = Problem::new(fit)?;
    let a = select(&p.a, w.first, w.retained);
    let f = p.gls.fit(&a);
    let value = |i: usize| w.offset.get(i).copied().unwrap_or(0.0) + f.theta[i];
    let informative = (0..w.retained.len()).any(|i| {
        let s = f.cov[(i, i)].max(0.0).sqrt();
        s > 0.0 && value(i).abs() >= 3.0 * s
    });
    // After: the base (the effect at the linearisation point removed) minus the columns times
    // the step to the estimate; an uninformative fit predicts nothing (after = before).
    let resid_after = |k: usize| -> [f64; 2] {
        if !informative {
            return eval.series.gap_m[k];
        }
        let mut r = eval.base[k];
        for (i, &c) in w.retained.iter().enumerate() {
            r[0] -= f.theta[i] * eval.cols[c][k][0];
            r[1] -= f.theta[i] * eval.cols[c][k][1];
        }
        r
    };
    let gap = |k: usize| eval.series.gap_m[k];
    let pred = |k: usize| {
        let (g, r) = (gap(k), resid_after(k));
        [g[0] - r[0], g[1] - r[1]]
    };
    let before = metrics(eval.series, keep, &|_| [0.0, 0.0]);
    let after = metrics(eval.series, keep, &pred);
    let sys_before = systematic(eval, keep, floor_var, &gap)?;
    let sys_after = systematic(eval, keep, floor_var, &resid_after)?;
    Ok(ValidationReport {
        kind: w.kind.to_string(),
        informative,
        fitted_on,
        evaluated_on,
        magnitudes: w
            .retained
            .iter()
            .enumerate()
            .map(|(i, &c)| {
                (
                    w.labels.get(c).copied().unwrap_or("?").to_string(),
                    value(i),
                    f.cov[(i, i)].max(0.0).sqrt(),
                )
            })
            .collect(),
        rms_shrinkage_percent: shrink(before.rms_gap_m, after.rms_gap_m),
        max_shrinkage_percent: shrink(before.max_horizontal_gap_m, after.max_horizontal_gap_m),
        systematic_before: sys_before,
        systematic_after: sys_after,
        systematic_shrinkage_percent: shrink(sys_before, sys_after),
        before,
        after,
    })
}

/// Validate the winner: with two runs or more, leave each run out of the fit in turn and
/// evaluate on it; with one run, fit on the fit points of its first half and evaluate on the
/// output points of the second half. `fit_data` are the runs' fit data about the winner's
/// linearisation point (in run order, like `runs`).
pub fn validate(
    w: &Winner<'_>,
    fit_data: &[RunFitData],
    runs: &[EvalRun<'_>],
    floor_var: f64,
) -> Result<Vec<ValidationReport>, DiagError> {
    let mut out = Vec::new();
    if fit_data.len() >= 2 {
        for (r, ev) in runs.iter().enumerate() {
            let others: Vec<&RunFitData> = fit_data
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != r)
                .map(|(_, d)| d)
                .collect();
            let names: Vec<&str> = others.iter().map(|d| d.run.as_str()).collect();
            let keep: Vec<usize> = (0..ev.series.t_s.len()).collect();
            out.push(one(
                w,
                &others,
                names.join("+"),
                ev,
                &keep,
                ev.series.run.clone(),
                floor_var,
            )?);
        }
    } else if let (Some(fit), Some(ev)) = (fit_data.first(), runs.first()) {
        let n = ev.series.t_s.len();
        let half = n / 2;
        let fit_pts: Vec<usize> = ev
            .fit_index
            .iter()
            .enumerate()
            .filter(|(_, k)| **k < half)
            .map(|(i, _)| i)
            .collect();
        if fit_pts.len() >= 2 && half < n {
            let keep: Vec<usize> = (half..n).collect();
            let half_data = fit.subset(&fit_pts);
            out.push(one(
                w,
                &[&half_data],
                format!("{}[first half]", fit.run),
                ev,
                &keep,
                format!("{}[second half]", ev.series.run),
                floor_var,
            )?);
        }
    }
    Ok(out)
}
