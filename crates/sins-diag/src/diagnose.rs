//! The diagnosis: sensitivities and twin covariance of every run (one pass each, runs in
//! parallel), the gap on the fit grid, the null test, the candidates, the verdict, the
//! localisation and the withheld validation.

use crate::calib::{ParamUncertainty, uncertainty};
use crate::error::DiagError;
use crate::input::{DiagnoseConfig, DiagnosisInput, RunData};
use crate::localise::{GapSeries, localise};
use crate::pass::Grid;
use crate::problem::{Problem, RunFitData, run_fit_data};
use crate::rank::{Evaluated, Layout, NullDist, evaluate, verdict};
use crate::replay::temperature_series;
use crate::report::{Diagnosis, RunSeries};
use crate::sensitivity::{ColumnId, RunSensitivity, SensitivitySetup, run_sensitivity};
use crate::validate::{OutputColumns, Winner, validate};
use sins_imu::{EffectKind, Linearity};
use sins_replay::ErrorPoint;

/// North/east of a track at `t_s`, linear between points (clamped at the ends).
pub fn track_at(points: &[ErrorPoint], t_s: f64) -> [f64; 2] {
    let k = points.partition_point(|p| p.t_s < t_s);
    match (k.checked_sub(1).and_then(|i| points.get(i)), points.get(k)) {
        (Some(a), Some(b)) if b.t_s > a.t_s => {
            let w = (t_s - a.t_s) / (b.t_s - a.t_s);
            [
                a.north_m + w * (b.north_m - a.north_m),
                a.east_m + w * (b.east_m - a.east_m),
            ]
        }
        (_, Some(b)) => [b.north_m, b.east_m],
        (Some(a), None) => [a.north_m, a.east_m],
        (None, None) => [0.0, 0.0],
    }
}

/// Sensitivities of every run, `threads` at a time (results collected by run index).
fn sensitivities(
    input: &mut DiagnosisInput,
    cfg: &DiagnoseConfig,
    kinds: &[EffectKind],
    refine: Option<(EffectKind, Vec<f64>)>,
) -> Result<Vec<RunSensitivity>, DiagError> {
    let grid = Grid {
        output_every_s: cfg.output_interval_s.max(1),
        fit_every: (cfg.fit_interval_s / cfg.output_interval_s.max(1)).max(1),
    };
    let setup = SensitivitySetup {
        params: &input.params,
        noise: &input.noise,
        replay: &cfg.replay,
        candidates: kinds,
        grid,
        refine,
    };
    let one = |r: &mut RunData| -> Result<RunSensitivity, DiagError> {
        let temps = match r.temperatures.take() {
            Some(t) => t,
            None => {
                temperature_series(r.source.as_mut(), cfg.replay.temperature_rate_half_window_s)?
            }
        };
        let out = run_sensitivity(
            &r.name,
            r.source.as_mut(),
            &r.site,
            &r.track,
            &temps,
            &setup,
        );
        r.temperatures = Some(temps);
        out
    };
    let threads = cfg.threads.max(1);
    let mut results: Vec<Option<Result<RunSensitivity, DiagError>>> =
        (0..input.runs.len()).map(|_| None).collect();
    let runs = &mut input.runs;
    for (chunk_runs, chunk_out) in runs.chunks_mut(threads).zip(results.chunks_mut(threads)) {
        std::thread::scope(|s| {
            let handles: Vec<_> = chunk_runs.iter_mut().map(|r| s.spawn(|| one(r))).collect();
            for (h, o) in handles.into_iter().zip(chunk_out.iter_mut()) {
                *o = Some(h.join().unwrap_or_else(|_| {
                    Err(DiagError::Numerical("a worker thread panicked".into()))
                }));
            }
        });
    }
    results
        .into_iter()
        .map(|r| r.unwrap_or_else(|| Err(DiagError::Numerical("run not processed".into()))))
        .collect()
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
    let sens = sensitivities(input, cfg, &kinds, None)?;
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
    let all: Vec<&RunFitData> = data.iter().collect();
    let problem = Problem::new(&all)?;
    let n = problem.gls.n;
    let floor_var = (cfg.floor_sigma_m.powi(2) - cfg.floor_expected_sigma_m.powi(2)).max(0.0);
    let (mean, var) = problem.null_moments(floor_var);
    let dist = NullDist::from_moments(mean, var);
    let null = dist.test(problem.gls.chi2(), 0, cfg.null_alpha);
    let mut ranked = evaluate(&problem, &layouts, &walks, &dist, cfg);
    // Refinement of a winner whose perturbation feeds its own inputs: recompute its columns
    // with its fitted perturbation removed from the increments, and evaluate again.
    let mut problem = problem;
    let mut refined: Option<(Layout, Vec<RunSensitivity>)> = None;
    if let Some((l, rf)) = ranked
        .first()
        .filter(|e| e.report.passes && cfg.refine_kinds().contains(&e.kind))
        .and_then(|e| e.regression.clone())
    {
        let mut values = vec![0.0; l.n];
        for (i, &c) in rf.retained.iter().enumerate() {
            values[c] = rf.fit.theta[i] * l.kind.unit().si;
        }
        let sens_r = sensitivities(input, cfg, &kinds, Some((l.kind, values)))?;
        for (fd, s) in data.iter_mut().zip(&sens_r) {
            for c in 0..l.n {
                if let Some(i) = s.column(ColumnId::Effect(l.kind, c)) {
                    let si = l.kind.unit().si;
                    for (j, &k) in s.times.fit_index.iter().enumerate() {
                        fd.columns[(2 * j, l.first + c)] = si * s.north_m[i][k];
                        fd.columns[(2 * j + 1, l.first + c)] = si * s.east_m[i][k];
                    }
                }
            }
        }
        let all: Vec<&RunFitData> = data.iter().collect();
        problem = Problem::new(&all)?;
        ranked = evaluate(&problem, &layouts, &walks, &dist, cfg);
        notes.push(format!(
            "{}: columns recomputed with the fitted effect removed from the increments",
            l.kind.name()
        ));
        refined = Some((l, sens_r));
    }
    let verdict = verdict(&problem, &ranked, &null, cfg);
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
    let out_cols: Vec<OutputColumns> = match winner.and_then(|w| w.regression.as_ref()) {
        Some((l, _)) => {
            let from = match &refined {
                Some((r, s)) if r.kind == l.kind => s,
                _ => &sens,
            };
            from.iter().map(|s| output_columns(s, l)).collect()
        }
        None => Vec::new(),
    };
    let mut validation = Vec::new();
    let mut run_series: Vec<RunSeries> = series
        .iter()
        .zip(&input.runs)
        .map(|(s, r)| to_series(s, &r.segment_labels))
        .collect();
    if let Some((l, rf)) = winner.and_then(|w| w.regression.as_ref()) {
        for (rs, cols) in run_series.iter_mut().zip(&out_cols) {
            for (i, &c) in rf.retained.iter().enumerate() {
                let fitted = rs
                    .fitted_north_m
                    .iter_mut()
                    .zip(rs.fitted_east_m.iter_mut());
                for ((n, e), col) in fitted.zip(&cols[c]) {
                    *n += rf.fit.theta[i] * col[0];
                    *e += rf.fit.theta[i] * col[1];
                }
            }
        }
        let w = Winner {
            kind: l.kind.name(),
            labels: l.kind.component_labels(),
            first: l.first,
            retained: &rf.retained,
        };
        let fit_index: Vec<Vec<usize>> = sens.iter().map(|s| s.times.fit_index.clone()).collect();
        validation = validate(&w, &data, &series, &out_cols, &fit_index)?;
    }
    Ok(Diagnosis {
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

/// A deterministic candidate's columns on a run's output grid, per candidate unit.
fn output_columns(s: &RunSensitivity, l: &Layout) -> OutputColumns {
    let si = l.kind.unit().si;
    (0..l.n)
        .map(|c| match s.column(ColumnId::Effect(l.kind, c)) {
            Some(i) => (0..s.times.times_s.len())
                .map(|k| [si * s.north_m[i][k], si * s.east_m[i][k]])
                .collect(),
            None => vec![[0.0; 2]; s.times.times_s.len()],
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
