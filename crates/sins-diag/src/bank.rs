//! The bank of sensitivity columns of one run: each column's perturbation is rotated to NED with
//! the sample's attitude and accumulated into the current bin's moments; at each bin end every
//! column's linear error state is propagated, and at each output time its position error is
//! recorded. Memory is per column and per output time, never per sample.
//!
//! A bin's samples are buffered and the columns evaluated at the bin end, column by column
//! ([`ColumnBank::add`]): each column then sees its samples in time order with the same
//! arithmetic as sample by sample, so the moments are the same to the bit, while a column's
//! moments stay in registers over the bin and an effect column costs one dynamic call per bin.
//!
//! Turn-on columns (see [`ColumnBank::with_turn_on`]) are propagated from the first sample,
//! through the alignment, to the first output time only: their state there is all the time-local
//! scan needs of an effect that starts at turn-on (see `crate::events`).

use crate::align::{AlignmentReplica, CoarseJacobian};
use crate::columns::{ColumnEval, Perturbation, SampleInputs, Triad};
use crate::model::{ErrorModel, Mat7, Moments, R_E, R_N, Vec7};
use sins_imu::EffectContext;
use sins_nav::simd4::Token;
use sins_nav::{Mat3, Vec3};

mod lanes;

/// The samples of the open bin, waiting for its end: each one's inputs, attitude `C_nb`, time
/// before the bin end `w` and `w²/2` (s, s²).
#[derive(Default)]
struct BinSamples {
    inputs: Vec<SampleInputs>,
    ctxs: Vec<EffectContext>,
    c_nb: Vec<Mat3>,
    w_s: Vec<f64>,
    half_w2_s2: Vec<f64>,
    /// An effect column's perturbations of these samples (rad, m/s).
    perturbations: Vec<(Vec3, Vec3)>,
    /// A coefficient column's scalars of these samples (the lanes).
    values: Vec<f64>,
}

impl BinSamples {
    fn clear(&mut self) {
        self.inputs.clear();
        self.ctxs.clear();
        self.c_nb.clear();
        self.w_s.clear();
        self.half_w2_s2.clear();
    }
}

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
    /// The open bin's samples.
    bin: BinSamples,
    /// The AVX2 token where the CPU has AVX2 (the bins are then added in lanes).
    lanes: Option<Token>,
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
            bin: BinSamples::default(),
            lanes: sins_nav::simd4::token(),
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
    /// The sample waits in the bin's buffer; the columns evaluate it at [`Self::end_bin`].
    #[inline]
    pub fn add(&mut self, s: &SampleInputs, c_nb: &Mat3, w_s: f64) {
        let bin = &mut self.bin;
        bin.inputs.push(*s);
        bin.ctxs.push(s.ctx);
        bin.c_nb.push(*c_nb);
        bin.w_s.push(w_s);
        bin.half_w2_s2.push(0.5 * w_s * w_s);
    }

    /// Add the buffered samples' forcing to every active column's moments, column by column,
    /// each column's samples in time order. Only the forcing's non-zero parts are added (see
    /// [`Moments::add_part`]): an axis column forces three or two components, and most effects
    /// act on one triad only.
    fn add_bin(&mut self) {
        let n = self.active();
        if let Some(s) = self.lanes {
            lanes::add_bin(lanes::AddBin {
                evals: &mut self.evals[..n],
                mom: &mut self.mom[..n],
                bin: &mut self.bin,
                s,
            });
            self.bin.clear();
            return;
        }
        let bin = &mut self.bin;
        for (e, m) in self.evals[..n].iter_mut().zip(&mut self.mom) {
            let mut acc = *m;
            match e {
                ColumnEval::Param(p) => {
                    for (k, s) in bin.inputs.iter().enumerate() {
                        let (w, hw2) = (bin.w_s[k], bin.half_w2_s2[k]);
                        let c = bin.c_nb[k].column(p.row) * p.scalar(s);
                        match p.triad {
                            Triad::Gyro => acc.add_part(0, [c.x, c.y, c.z], w, hw2),
                            Triad::Accel => acc.add_part(3, [c.x, c.y], w, hw2),
                        }
                    }
                }
                ColumnEval::Effect(effect) => {
                    effect.perturbations(&bin.ctxs, &mut bin.perturbations);
                    for (k, (dtheta_rad, dv_mps)) in bin.perturbations.iter().enumerate() {
                        let (c_nb, w, hw2) = (&bin.c_nb[k], bin.w_s[k], bin.half_w2_s2[k]);
                        add_full(&mut acc, c_nb, dtheta_rad, dv_mps, w, hw2);
                    }
                }
            }
            *m = acc;
        }
        bin.clear();
    }

    /// End of a bin: the bin's samples into the moments, then every column propagated with the
    /// bin's transition `phi`.
    pub fn end_bin(&mut self, model: &ErrorModel, phi: &Mat7) {
        self.add_bin();
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

/// Add a both-triad forcing `(dtheta_rad, dv_mps)` (body frame) resolved in NED with `c_nb`,
/// applied `w_s` before the bin end (`half_w2_s2` = `w_s²/2`); a triad whose forcing is exactly
/// zero is skipped.
#[inline]
fn add_full(m: &mut Moments, c_nb: &Mat3, dtheta_rad: &Vec3, dv_mps: &Vec3, w_s: f64, hw2: f64) {
    if *dtheta_rad != Vec3::zeros() {
        let g = c_nb * dtheta_rad;
        m.add_part(0, [g.x, g.y, g.z], w_s, hw2);
    }
    if *dv_mps != Vec3::zeros() {
        let a = c_nb * dv_mps;
        m.add_part(3, [a.x, a.y], w_s, hw2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::columns::{PARAM_SLOTS, SampleInputs};
    use sins_imu::effects::ContextTracker;
    use sins_imu::{EffectKind, ImuErrorParams, Linearity, ParamModel};
    use sins_nav::Quat;

    /// Every coefficient column and every deterministic candidate's components, as the pass
    /// builds them.
    fn columns(params: &ImuErrorParams) -> Vec<ColumnEval> {
        let effects = EffectKind::ALL
            .into_iter()
            .filter(|k| k.linearity() != Linearity::RandomProcess)
            .flat_map(|k| (0..k.n_components()).map(move |c| (k, c)))
            .map(|(k, c)| ColumnEval::effect(k, c, params));
        effects
            .chain(PARAM_SLOTS.iter().map(|s| ColumnEval::Param(*s)))
            .collect()
    }

    /// Bins of samples under a tumbling, vibrating motion with drifting temperatures.
    fn samples(n: usize) -> Vec<(SampleInputs, Mat3)> {
        let h = 0.005;
        let mut tracker = ContextTracker::new();
        let mut q = Quat::identity();
        (0..n)
            .map(|k| {
                let t = (k + 1) as f64 * h;
                let dtheta = Vec3::new(
                    0.3 * (7.0 * t).sin() + 0.05,
                    -0.2 * (11.0 * t).cos(),
                    0.4 * (5.0 * t + 1.0).sin(),
                ) * h;
                let dv = Vec3::new(0.5 * (3.0 * t).sin(), 0.2, 9.8) * h;
                let temp = [20.0 + 0.01 * t, 25.0 - 0.02 * t, 31.0];
                let ctx = tracker.next(t, h, dtheta, dv, temp, [1e-3, -2e-3, 0.0]);
                q *= Quat::from_scaled_axis(dtheta);
                let inputs = SampleInputs {
                    h_s: h,
                    dtheta_rad: dtheta,
                    dv_mps: dv,
                    dtemp_degc: temp.map(|x| x - 20.0),
                    ctx,
                };
                // Attitudes with exact zeros (+0.0 and -0.0) now and then: a zero lane of
                // `c_j v_j` must give the full product's moments.
                let c = match k % 9 {
                    0 => Mat3::identity(),
                    4 => Mat3::new(-1.0, -0.0, 0.0, 0.0, -1.0, -0.0, -0.0, 0.0, 1.0),
                    _ => q.to_rotation_matrix().into_inner(),
                };
                (inputs, c)
            })
            .collect()
    }

    fn bits(m: &[Moments]) -> Vec<u64> {
        m.iter()
            .flat_map(|m| m.m1.iter().chain(m.m2.iter()).chain(m.m3.iter()))
            .map(|x| x.to_bits())
            .collect()
    }

    /// The lanes add every column's bin to its moments exactly as the scalar code does, over
    /// bins of uneven length (a stateful effect carries its state from bin to bin).
    #[test]
    fn the_lanes_give_the_scalar_moments_to_the_bit() {
        let Some(_) = sins_nav::simd4::token() else {
            eprintln!("this CPU has no AVX2: the scalar code is the only path");
            return;
        };
        let mut params = ImuErrorParams::ideal(ParamModel::States42);
        params.reference_temperature_degc = 20.0;
        params.temperature.bias_mps2_per_degc = Vec3::new(3e-5, -2e-5, 1e-5);
        // Temperature scale factors and installation errors: the thermal lag's columns then
        // force several axes at once, and the rotation's order of additions shows.
        params.temperature.scale_per_degc = Vec3::new(2e-5, 1e-5, 3e-5);
        params.temperature.misalignment_rad_per_degc = [1e-6, -2e-6, 3e-6, 1e-6, -1e-6, 2e-6];
        let mut lanes = ColumnBank::new(columns(&params), vec![]);
        let mut scalar = ColumnBank::new(columns(&params), vec![]);
        assert!(lanes.lanes.is_some());
        scalar.lanes = None;
        let all = samples(700);
        let mut done = 0;
        for len in [200, 1, 150, 200, 149] {
            for bank in [&mut lanes, &mut scalar] {
                for (k, (s, c)) in all[done..done + len].iter().enumerate() {
                    bank.add(s, c, (len - k) as f64 * 0.005 - 0.0025);
                }
                bank.add_bin();
            }
            done += len;
            assert_eq!(bits(&lanes.mom), bits(&scalar.mom), "after {done} samples");
        }
        // Every coefficient column forced, and the effects other than the steps, ramps and
        // events (whose onsets lie beyond these 3.5 s): the comparison covers both kinds.
        let is_forced = |m: &Moments| m.m1.iter().any(|&x| x != 0.0);
        let mut n_effects = 0;
        for (e, m) in lanes.evals.iter().zip(&lanes.mom) {
            match e {
                ColumnEval::Param(p) => assert!(is_forced(m), "{} never forced", p.name),
                ColumnEval::Effect(_) => n_effects += usize::from(is_forced(m)),
            }
        }
        assert!(n_effects >= 35, "{n_effects} effect columns forced");
    }
}
