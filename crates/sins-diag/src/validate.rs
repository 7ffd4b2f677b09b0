//! Withheld validation: fit the winning effect without one run (leave-one-run-out; with a single
//! run, on its first half), predict the withheld run (the second half) with
//! `twin + θ × sensitivity`, and compare the maximum-horizontal-error gap and the RMS gap before
//! and after. A fit that does not determine the effect (no retained component at |z| ≥ 3 on the
//! fitting data, e.g. a vibration effect fitted on a calibration run without vibration) is
//! reported as not informative and its prediction is not made.

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
}

/// Metrics of `series` points `keep` against a prediction `pred` (added to the twin mean).
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

/// Fit the winner on `fit` and report the gap on the output points `keep` of `eval`.
fn one(
    w: &Winner<'_>,
    fit: &[&RunFitData],
    fitted_on: String,
    eval: (&GapSeries, &OutputColumns, &[usize]),
    evaluated_on: String,
) -> Result<ValidationReport, DiagError> {
    let p = Problem::new(fit)?;
    let a = select(&p.a, w.first, w.retained);
    let f = p.gls.fit(&a);
    let (series, cols, keep) = eval;
    let informative = (0..w.retained.len()).any(|i| {
        let s = f.cov[(i, i)].max(0.0).sqrt();
        s > 0.0 && f.theta[i].abs() >= 3.0 * s
    });
    let theta: Vec<f64> = (0..w.retained.len())
        .map(|i| if informative { f.theta[i] } else { 0.0 })
        .collect();
    let pred = |k: usize| {
        let mut out = [0.0; 2];
        for (i, &c) in w.retained.iter().enumerate() {
            out[0] += theta[i] * cols[c][k][0];
            out[1] += theta[i] * cols[c][k][1];
        }
        out
    };
    let before = metrics(series, keep, &|_| [0.0, 0.0]);
    let after = metrics(series, keep, &pred);
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
                    f.theta[i],
                    f.cov[(i, i)].max(0.0).sqrt(),
                )
            })
            .collect(),
        rms_shrinkage_percent: shrink(before.rms_gap_m, after.rms_gap_m),
        max_shrinkage_percent: shrink(before.max_horizontal_gap_m, after.max_horizontal_gap_m),
        before,
        after,
    })
}

/// Validate the winner: with two runs or more, leave each run out of the fit in turn and
/// evaluate on it; with one run, fit on the fit points of its first half and evaluate on the
/// output points of the second half.
pub fn validate(
    w: &Winner<'_>,
    data: &[RunFitData],
    series: &[GapSeries],
    cols: &[OutputColumns],
    fit_index: &[Vec<usize>],
) -> Result<Vec<ValidationReport>, DiagError> {
    let mut out = Vec::new();
    if data.len() >= 2 {
        for (r, ser) in series.iter().enumerate() {
            let others: Vec<&RunFitData> = data
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != r)
                .map(|(_, d)| d)
                .collect();
            let names: Vec<&str> = others.iter().map(|d| d.run.as_str()).collect();
            let keep: Vec<usize> = (0..ser.t_s.len()).collect();
            out.push(one(
                w,
                &others,
                names.join("+"),
                (ser, &cols[r], &keep),
                ser.run.clone(),
            )?);
        }
    } else if let (Some(fit), Some(ser)) = (data.first(), series.first()) {
        let n = ser.t_s.len();
        let half = n / 2;
        let fit_pts: Vec<usize> = fit_index[0]
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
                (ser, &cols[0], &keep),
                format!("{}[second half]", ser.run),
            )?);
        }
    }
    Ok(out)
}
