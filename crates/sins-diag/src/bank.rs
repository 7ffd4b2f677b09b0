//! The bank of sensitivity columns of one run: each column's perturbation is rotated to NED with
//! the sample's attitude and accumulated into the current bin's moments; at each bin end every
//! column's linear error state is propagated, and at each output time its position error is
//! recorded. Memory is per column and per output time, never per sample.
//!
//! Turn-on columns (see [`ColumnBank::with_turn_on`]) are propagated from the first sample,
//! through the alignment, to the first output time only: their state there is all the time-local
//! scan needs of an effect that starts at turn-on (see `crate::events`).

use crate::align::{AlignmentReplica, CoarseJacobian};
use crate::columns::{ColumnEval, Perturbation, SampleInputs, Triad};
use crate::model::{ErrorModel, Mat7, Moments, R_E, R_N, Vec7};
use sins_nav::{Mat3, Vec3};

/// Columns, their states and their recorded responses.
pub struct ColumnBank {
    evals: Vec<ColumnEval>,
    x: Vec<Vec7>,
    mom: Vec<Moments>,
    coarse: Vec<(Vec3, Vec3)>,
    /// North position response of each column at each output time (m per SI unit).
    pub north_m: Vec<Vec<f64>>,
    /// East position response (m per SI unit).
    pub east_m: Vec<Vec<f64>>,
    /// Columns whose full error state is kept at every output time.
    keep_full: Vec<usize>,
    /// Full states of the `keep_full` columns at each output time.
    pub full: Vec<Vec<Vec7>>,
    /// Full states of the `keep_full` columns at the start of navigation.
    pub full_at_nav_start: Vec<Vec7>,
    /// Columns propagated for the whole run (the turn-on columns follow them).
    n_main: usize,
    /// True once the turn-on columns have been recorded (they are no longer propagated).
    turn_on_recorded: bool,
    /// Full states of the turn-on columns at the first output time.
    pub turn_on_at_first_output: Vec<Vec7>,
}

impl ColumnBank {
    /// A bank of `evals`; the full state of the columns listed in `keep_full` is recorded too.
    pub fn new(evals: Vec<ColumnEval>, keep_full: Vec<usize>) -> Self {
        let n = evals.len();
        Self {
            x: vec![Vec7::zeros(); n],
            mom: vec![Moments::default(); n],
            coarse: vec![(Vec3::zeros(), Vec3::zeros()); n],
            north_m: vec![Vec::new(); n],
            east_m: vec![Vec::new(); n],
            full: vec![Vec::new(); keep_full.len()],
            full_at_nav_start: vec![Vec7::zeros(); keep_full.len()],
            keep_full,
            evals,
            n_main: n,
            turn_on_recorded: false,
            turn_on_at_first_output: Vec::new(),
        }
    }

    /// Add columns propagated only until the first output time, where their full state is
    /// kept in [`Self::turn_on_at_first_output`] (in the order of `evals`).
    pub fn with_turn_on(mut self, evals: Vec<ColumnEval>) -> Self {
        let n = evals.len();
        self.x.extend(std::iter::repeat_n(Vec7::zeros(), n));
        self.mom.extend(std::iter::repeat_n(Moments::default(), n));
        self.coarse
            .extend(std::iter::repeat_n((Vec3::zeros(), Vec3::zeros()), n));
        self.evals.extend(evals);
        self
    }

    /// Columns still propagated: all of them until the turn-on columns are recorded.
    fn active(&self) -> usize {
        if self.turn_on_recorded {
            self.n_main
        } else {
            self.evals.len()
        }
    }

    /// Coarse-alignment stage: sum each column's body-frame perturbation.
    #[inline]
    pub fn add_coarse(&mut self, s: &SampleInputs) {
        for (e, acc) in self.evals.iter_mut().zip(&mut self.coarse) {
            match e.perturbation(s) {
                Perturbation::Axis { triad, row, value } => match triad {
                    Triad::Gyro => acc.0[row] += value,
                    Triad::Accel => acc.1[row] += value,
                },
                Perturbation::Full { dtheta_rad, dv_mps } => {
                    acc.0 += dtheta_rad;
                    acc.1 += dv_mps;
                }
            }
        }
    }

    /// End of the coarse stage of `duration_s`: each column's attitude error is the coarse
    /// Jacobian applied to its mean specific force and rate perturbations.
    pub fn end_coarse(&mut self, j: &CoarseJacobian, duration_s: f64) {
        for (x, (dth, dv)) in self.x.iter_mut().zip(&self.coarse) {
            let mut input = nalgebra::SVector::<f64, 6>::zeros();
            input.fixed_rows_mut::<3>(0).copy_from(&(dv / duration_s));
            input.fixed_rows_mut::<3>(3).copy_from(&(dth / duration_s));
            let phi = j * input;
            *x = Vec7::zeros();
            x.fixed_rows_mut::<3>(0).copy_from(&phi);
        }
    }

    /// Add this sample's forcing, resolved in NED with `c_nb`, applied `w_s` before the bin end.
    /// Only the forcing's non-zero parts are added (see [`Moments::add_part`]): an axis column
    /// forces three or two components, and most effects act on one triad only.
    #[inline]
    pub fn add(&mut self, s: &SampleInputs, c_nb: &Mat3, w_s: f64) {
        let n = self.active();
        let half_w2 = 0.5 * w_s * w_s;
        for (e, m) in self.evals[..n].iter_mut().zip(&mut self.mom) {
            match e.perturbation(s) {
                Perturbation::Axis { triad, row, value } => {
                    let c = c_nb.column(row) * value;
                    match triad {
                        Triad::Gyro => m.add_part(0, [c.x, c.y, c.z], w_s, half_w2),
                        Triad::Accel => m.add_part(3, [c.x, c.y], w_s, half_w2),
                    }
                }
                Perturbation::Full { dtheta_rad, dv_mps } => {
                    if dtheta_rad != Vec3::zeros() {
                        let g = c_nb * dtheta_rad;
                        m.add_part(0, [g.x, g.y, g.z], w_s, half_w2);
                    }
                    if dv_mps != Vec3::zeros() {
                        let a = c_nb * dv_mps;
                        m.add_part(3, [a.x, a.y], w_s, half_w2);
                    }
                }
            }
        }
    }

    /// End of a bin: propagate every column with the bin's transition `phi`.
    pub fn end_bin(&mut self, model: &ErrorModel, phi: &Mat7) {
        let n = self.active();
        for (x, m) in self.x[..n].iter_mut().zip(&mut self.mom) {
            *x = phi * *x + model.input(m);
            *m = Moments::default();
        }
    }

    /// A fine-alignment update `k` (closed-loop feedback, position reset).
    pub fn align_update(&mut self, replica: &AlignmentReplica, k: usize) {
        for x in &mut self.x {
            replica.update_state(k, x);
        }
    }

    /// Start of navigation: the alignment result has zero velocity and the site position.
    pub fn nav_start(&mut self) {
        for x in &mut self.x {
            for i in 3..7 {
                x[i] = 0.0;
            }
        }
        for (f, &i) in self.full_at_nav_start.iter_mut().zip(&self.keep_full) {
            *f = self.x[i];
        }
    }

    /// Record every column's position error at an output time.
    pub fn record(&mut self) {
        if !self.turn_on_recorded {
            self.turn_on_at_first_output = self.x[self.n_main..].to_vec();
            self.turn_on_recorded = true;
        }
        for (i, x) in self.x[..self.n_main].iter().enumerate() {
            self.north_m[i].push(x[R_N]);
            self.east_m[i].push(x[R_E]);
        }
        for (f, &i) in self.full.iter_mut().zip(&self.keep_full) {
            f.push(self.x[i]);
        }
    }
}
