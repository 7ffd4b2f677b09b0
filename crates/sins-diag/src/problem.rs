//! The fit problem: per-run data on the fit grid (gap, twin covariance, one-sigma calibration
//! responses, candidate columns in the candidates' units, random-walk factors), and the stacked,
//! whitened form of any selection of runs.

use crate::calib::ParamUncertainty;
use crate::error::DiagError;
use crate::gls::{Gls, Whitener};
use crate::model::{R_E, R_N, Vec7};
use crate::sensitivity::{BIAS_SLOTS, ColumnId, RunSensitivity};
use nalgebra::{DMatrix, DVector};

/// One run on its fit grid; rows are `[N_0, E_0, N_1, E_1, ...]`.
#[derive(Clone, Debug)]
pub struct RunFitData {
    /// Run name.
    pub run: String,
    /// Gap real - twin mean (m).
    pub gap: DVector<f64>,
    /// Twin covariance without calibration uncertainty (m²).
    pub cov: DMatrix<f64>,
    /// Responses to a one-sigma change of each uncertain coefficient (m).
    pub params: DMatrix<f64>,
    /// Candidate columns (m per unit of the candidate).
    pub columns: DMatrix<f64>,
    /// Random-walk factors of the six bias axes (gyro x, y, z, accelerometer x, y, z): `V` with
    /// `V Vᵀ` the position covariance of a walk of unit intensity (1 SI unit²/s).
    pub walks: Vec<DMatrix<f64>>,
}

impl RunFitData {
    /// The rows of the fit points `keep` (indices into the fit grid).
    pub fn subset(&self, keep: &[usize]) -> RunFitData {
        let rows: Vec<usize> = keep.iter().flat_map(|&k| [2 * k, 2 * k + 1]).collect();
        let pick = |m: &DMatrix<f64>| m.select_rows(rows.iter());
        RunFitData {
            run: self.run.clone(),
            gap: self.gap.select_rows(rows.iter()),
            cov: self
                .cov
                .select_rows(rows.iter())
                .select_columns(rows.iter()),
            params: pick(&self.params),
            columns: pick(&self.columns),
            walks: self.walks.iter().map(pick).collect(),
        }
    }

    /// Number of fit points.
    pub fn points(&self) -> usize {
        self.gap.len() / 2
    }
}

/// Build the fit data of one run: `gap_fit` at its fit times, the calibration uncertainty
/// `pu`, `cand_cols` with their SI value of one candidate unit.
pub fn run_fit_data(
    s: &RunSensitivity,
    gap_fit: &[[f64; 2]],
    floor_sigma_m: f64,
    pu: Option<&ParamUncertainty>,
    cand_cols: &[(ColumnId, f64)],
    walk_step_points: usize,
    fit_interval_s: f64,
) -> Result<RunFitData, DiagError> {
    let n = s.times.fit_index.len();
    let rows = 2 * n;
    let gap = DVector::from_fn(rows, |r, _| gap_fit[r / 2][r % 2]);
    let mut cov = s.fit_covariance.clone();
    for i in 0..rows {
        cov[(i, i)] += floor_sigma_m * floor_sigma_m;
    }
    let col = |id: ColumnId, scale: f64| -> Result<DVector<f64>, DiagError> {
        let c = s
            .column(id)
            .ok_or_else(|| DiagError::input(&s.run, format!("column {id:?} was not computed")))?;
        Ok(DVector::from_fn(rows, |r, _| {
            let k = s.times.fit_index[r / 2];
            scale
                * if r % 2 == 0 {
                    s.north_m[c][k]
                } else {
                    s.east_m[c][k]
                }
        }))
    };
    let params = match pu {
        Some(pu) => {
            let mut raw = DMatrix::zeros(rows, pu.ids.len());
            for (j, &id) in pu.ids.iter().enumerate() {
                raw.set_column(j, &col(id, 1.0)?);
            }
            raw * &pu.factor
        }
        None => DMatrix::zeros(rows, 0),
    };
    let mut columns = DMatrix::zeros(rows, cand_cols.len());
    for (j, &(id, unit)) in cand_cols.iter().enumerate() {
        columns.set_column(j, &col(id, unit)?);
    }
    let walks = (0..BIAS_SLOTS.len())
        .map(|b| walk_factor(s, b, walk_step_points, fit_interval_s))
        .collect();
    Ok(RunFitData {
        run: s.run.clone(),
        gap,
        cov,
        params,
        columns,
        walks,
    })
}

/// Low-rank factor of the position covariance of a unit-intensity random walk on bias axis `b`:
/// the walk's value accumulated during the alignment (variance `T_a`) is split evenly into a
/// constant the alignment absorbs and a step at the start of navigation; later increments are
/// lumped every `step_points` fit points at the middle of their interval. Each lump is the
/// response to a bias step, `H (X(t) - Φ(t - t_m) X(t_m))` with `X` the bias column.
fn walk_factor(s: &RunSensitivity, b: usize, step_points: usize, fit_dt: f64) -> DMatrix<f64> {
    let n = s.times.fit_index.len();
    let fit_states: Vec<Vec7> = s
        .times
        .fit_index
        .iter()
        .map(|&k| s.bias_states[b][k])
        .collect();
    let x0 = s.bias_states_at_nav_start[b];
    let t_align = s.times.nav_start_s - s.times.start_s;
    let phi = s.model.transition(fit_dt);
    let step = step_points.max(1);
    let mut cols: Vec<(DVector<f64>, f64)> = Vec::new();
    // Aligned constant.
    cols.push((
        DVector::from_fn(2 * n, |r, _| {
            fit_states[r / 2][if r % 2 == 0 { R_N } else { R_E }]
        }),
        0.5 * t_align,
    ));
    // Step at the start of navigation, then lumps.
    let mut starts: Vec<(Option<usize>, f64)> = vec![(None, 0.5 * t_align)];
    let mut m = step / 2;
    while m < n {
        starts.push((Some(m), step as f64 * fit_dt));
        m += step;
    }
    for (start, var) in starts {
        let mut y = DVector::zeros(2 * n);
        let (first, mut carry) = match start {
            None => (0, phi * x0),
            Some(m) => (m + 1, phi * fit_states[m]),
        };
        for i in first..n {
            let d = fit_states[i] - carry;
            y[2 * i] = d[R_N];
            y[2 * i + 1] = d[R_E];
            carry = phi * carry;
        }
        cols.push((y, var));
    }
    let mut v = DMatrix::zeros(2 * n, cols.len());
    for (j, (c, var)) in cols.iter().enumerate() {
        v.set_column(j, &(c * var.max(0.0).sqrt()));
    }
    v
}

/// A selection of runs, stacked and whitened.
pub struct Problem {
    /// The metric.
    pub gls: Gls,
    /// Whitened candidate columns.
    pub a: DMatrix<f64>,
    /// Whitening of each run.
    pub whitener: Whitener,
    /// Whitened random-walk factors per bias axis (block diagonal over runs, stacked).
    pub walks: Vec<DMatrix<f64>>,
    /// Column widths of each run's block in `walks`, per bias axis.
    pub walk_blocks: Vec<Vec<usize>>,
    /// Whitened one-sigma calibration columns.
    pub u: DMatrix<f64>,
}

impl Problem {
    /// Mean and variance of `gᵀ S⁻¹ g` when the gap holds only what `S` minus a white part of
    /// variance `floor_var` describes (sensor noise, calibration errors, the floor the data are
    /// expected to carry): the rest of the metric's floor is a tolerance for what the twin does
    /// not model, not a noise the real data carry, and counting it as one would make every
    /// chi-square test blind. With `S_0 = S - f I`:
    /// `E = tr(S⁻¹S_0) = n - f tr(S⁻¹)`, `Var = 2 tr((S⁻¹S_0)²)`.
    pub fn null_moments(&self, floor_var: f64) -> (f64, f64) {
        let n = self.gls.n as f64;
        let g = self.whitener.inverse_grams();
        let w = self.gls.woodbury_w();
        let p = w.ncols();
        let mut gw = DMatrix::zeros(w.nrows(), p);
        let (mut tr_g, mut fro_g) = (0.0, 0.0);
        for (r, gr) in g.iter().enumerate() {
            let rows = self.whitener.rows(r);
            tr_g += gr.trace();
            fro_g += gr.norm_squared();
            let block = gr * w.rows(rows.start, rows.len());
            gw.rows_mut(rows.start, rows.len()).copy_from(&block);
        }
        let wgw = w.transpose() * &gw;
        let tr_inv = tr_g - wgw.trace();
        let tr_inv2 = fro_g - 2.0 * gw.norm_squared() + wgw.norm_squared();
        let mean = n - floor_var * tr_inv;
        let tr_sq = n - 2.0 * floor_var * tr_inv + floor_var * floor_var * tr_inv2;
        (mean, 2.0 * tr_sq)
    }

    /// Stack and whiten `runs`.
    pub fn new(runs: &[&RunFitData]) -> Result<Self, DiagError> {
        let covs: Vec<DMatrix<f64>> = runs.iter().map(|r| r.cov.clone()).collect();
        let whitener = Whitener::new(&covs)?;
        let n = whitener.n();
        let stack = |f: &dyn Fn(&RunFitData) -> DMatrix<f64>| {
            let parts: Vec<DMatrix<f64>> = runs.iter().map(|r| f(r)).collect();
            let m = parts.first().map_or(0, |p| p.ncols());
            let mut out = DMatrix::zeros(n, m);
            for (r, p) in parts.iter().enumerate() {
                out.rows_mut(whitener.rows(r).start, p.nrows()).copy_from(p);
            }
            whitener.whiten(&out)
        };
        let g = stack(&|r| DMatrix::from_column_slice(r.gap.len(), 1, r.gap.as_slice()));
        let u = stack(&|r| r.params.clone());
        let a = stack(&|r| r.columns.clone());
        let walks = (0..BIAS_SLOTS.len())
            .map(|b| {
                let widths: Vec<usize> = runs.iter().map(|r| r.walks[b].ncols()).collect();
                let total: usize = widths.iter().sum();
                let mut out = DMatrix::zeros(n, total);
                let mut c0 = 0;
                for (r, run) in runs.iter().enumerate() {
                    let rows = whitener.rows(r);
                    out.view_mut((rows.start, c0), (rows.len(), widths[r]))
                        .copy_from(&run.walks[b]);
                    c0 += widths[r];
                }
                whitener.whiten(&out)
            })
            .collect();
        let walk_blocks = (0..BIAS_SLOTS.len())
            .map(|b| runs.iter().map(|r| r.walks[b].ncols()).collect())
            .collect();
        let gls = Gls::new(g.column(0).into_owned(), u.clone())?;
        Ok(Self {
            gls,
            a,
            whitener,
            walks,
            walk_blocks,
            u,
        })
    }
}
