//! The gaps: every run's gap (real track less the twin's mean) on the output grid with its 1-sigma envelope and on the fit grid with
//! the twin covariance, the calibration responses, the candidate columns and the walk factors.

use crate::calib::ParamUncertainty;
use crate::error::DiagError;
use crate::input::{DiagnoseConfig, DiagnosisInput};
use crate::localise::GapSeries;
use crate::problem::{RunFitData, run_fit_data};
use crate::report::RunSeries;
use crate::runs::track_at;
use crate::sensitivity::{ColumnId, RunSensitivity};

/// Every run's gap series (output grid) and fit data (fit grid), in the input's run order.
pub(crate) fn gaps(
    input: &DiagnosisInput,
    sens: &[RunSensitivity],
    pu: Option<&ParamUncertainty>,
    cand_cols: &[(ColumnId, f64)],
    cfg: &DiagnoseConfig,
) -> Result<(Vec<GapSeries>, Vec<RunFitData>), DiagError> {
    let walk_step = (cfg.walk_step_s / cfg.fit_interval_s).max(1);
    let mut series = Vec::new();
    let mut data = Vec::new();
    for (r, s) in input.runs.iter().zip(sens) {
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
            pu,
            cand_cols,
            walk_step,
            cfg.fit_interval_s as f64,
        )?;
        let sigma_m = envelope(s, pu, cfg.floor_sigma_m);
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
    Ok((series, data))
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

/// The run's gap series as the report holds it (fitted effect zero until a winner fills it).
pub(crate) fn to_series(s: &GapSeries, labels: &[String]) -> RunSeries {
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
