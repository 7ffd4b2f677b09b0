//! One pass over the samples of a run: compensation, the attitude of every sample (the real
//! track's `ned_from_body` at each error point, carried between points by the compensated gyro
//! increments and Earth rate), the alignment replica, and the bins that feed the column bank and
//! the noise propagation.

use crate::align::{AlignmentReplica, coarse_jacobian};
use crate::bank::ColumnBank;
use crate::columns::SampleInputs;
use crate::error::DiagError;
use crate::model::{ErrorModel, Mat7};
use crate::noise::{AttitudeMoments, NoiseProp};
use crate::source::SampleSource;
use crate::temperature::TemperatureSeries;
use sins_imu::{Compensator, ContextTracker, ExtraEffect, ImuErrorParams, ImuSample};
use sins_nav::alignment::coarse_align;
use sins_nav::attitude::{quat_from_rotation_vector, skew};
use sins_nav::{Quat, Vec3};
use sins_replay::ErrorPoint;

/// Output and fit grids of a pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Output interval (whole seconds of navigation).
    pub output_every_s: usize,
    /// Output points per fit point.
    pub fit_every: usize,
}

/// What a pass produced besides the bank and the noise propagation.
#[derive(Clone, Debug, Default)]
pub struct PassTimes {
    /// Start of the first sample interval (s).
    pub start_s: f64,
    /// Time navigation starts (end of the alignment, s).
    pub nav_start_s: f64,
    /// Output times (s).
    pub times_s: Vec<f64>,
    /// Segment index of the sample ending at each output time.
    pub segments: Vec<u16>,
    /// Indices (into the output times) of the fit times.
    pub fit_index: Vec<usize>,
}

/// Inputs of one pass.
pub struct PassInput<'a> {
    /// Run name (for errors).
    pub run: &'a str,
    /// Calibrated parameter set (compensation).
    pub params: &'a ImuErrorParams,
    /// The real error track (attitude anchors).
    pub track: &'a [ErrorPoint],
    /// Temperature rates.
    pub temperatures: &'a TemperatureSeries,
    /// Alignment replica.
    pub replica: &'a AlignmentReplica,
    /// Error model at the site.
    pub model: &'a ErrorModel,
    /// Grids.
    pub grid: Grid,
}

/// Phase of a sample.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Phase {
    Coarse,
    Fine,
    Nav,
}

/// Run the pass, filling `bank` and `noise`. With a `correction` (an effect of fitted
/// magnitude), the columns see the increments with that effect's perturbation removed: the
/// context of an effect whose perturbation feeds its own inputs (the time offset differences
/// the very increments it perturbs) is then the true motion to second order.
pub fn run_pass(
    source: &mut dyn SampleSource,
    inp: &PassInput<'_>,
    bank: &mut ColumnBank,
    noise: &mut NoiseProp,
    correction: Option<&mut Box<dyn ExtraEffect>>,
) -> Result<PassTimes, DiagError> {
    let h = source.sample_interval_s();
    let t0 = source.start_time_s();
    let run = inp.run;
    let rep = inp.replica;
    let mut feed = Feed {
        comp: Compensator::new(*inp.params)
            .ok_or_else(|| DiagError::input(run, "parameter set is singular"))?,
        h,
        temperatures: inp.temperatures,
        reference_temperature_degc: inp.params.reference_temperature_degc,
        tracker: ContextTracker::new(),
        corrected: ContextTracker::new(),
        correction,
    };
    let spb = samples_per_second(h, run)?;
    let consts = Consts {
        h,
        spb,
        phi_update: rep.phi_update,
        phi_bin: inp.model.transition(spb as f64 * h),
        q_earth_sample: quat_from_rotation_vector(&(-inp.model.earth.earth_rate_ned_radps * h)),
    };
    let anchors = attitude_anchors(inp.track, t0, h);
    let mut st = State::new(rep, t0, h);
    // Each sample is processed once the next one is known (its gyro increment enters the
    // second-order quadrature of the attitude, see `effective_attitude`).
    let mut pending: Option<(SampleInputs, u16)> = None;
    let mut theta_prev = Vec3::zeros();
    let mut anchor_cursor = 0usize;
    source.visit(&mut |samples: &[ImuSample], segments: &[u16]| {
        for (s, &seg) in samples.iter().zip(segments) {
            let inputs = feed.inputs(s);
            if let Some((prev, prev_seg)) = pending.take() {
                let theta = prev.dtheta_rad;
                let next = &inputs.dtheta_rad;
                st.sample(
                    &prev,
                    prev_seg,
                    &theta_prev,
                    next,
                    inp,
                    &consts,
                    bank,
                    noise,
                )?;
                st.anchor(&anchors, &mut anchor_cursor);
                theta_prev = theta;
            }
            pending = Some((inputs, seg));
        }
        Ok(())
    })?;
    if let Some((last, seg)) = pending.take() {
        let theta = last.dtheta_rad;
        st.sample(&last, seg, &theta_prev, &theta, inp, &consts, bank, noise)?;
    }
    if st.phase != Phase::Nav || st.times.times_s.is_empty() {
        return Err(DiagError::input(
            run,
            format!(
                "the data end before the first output time ({} samples, alignment needs {})",
                st.i, rep.n_total
            ),
        ));
    }
    Ok(st.times)
}

/// Samples per second; an error unless the sample interval divides one second.
fn samples_per_second(h: f64, run: &str) -> Result<usize, DiagError> {
    let spb = (1.0 / h).round() as usize;
    if spb == 0 || ((spb as f64) * h - 1.0).abs() > 1e-9 {
        return Err(DiagError::input(
            run,
            format!("sample interval {h} s does not divide one second"),
        ));
    }
    Ok(spb)
}

/// The real track's attitudes as anchors: (index of the sample ending at the point, attitude),
/// in sample order.
fn attitude_anchors(track: &[ErrorPoint], t0: f64, h: f64) -> Vec<(usize, Quat)> {
    let mut anchors: Vec<(usize, Quat)> = track
        .iter()
        .map(|p| {
            let k = ((p.t_s - t0) / h).round() as i64 - 1;
            (k.max(0) as usize, p.ned_from_body)
        })
        .collect();
    anchors.sort_by_key(|a| a.0);
    anchors
}

/// What turns a raw sample into the columns' inputs: the compensation, the context of the
/// effects (temperature rates included) and an optional fitted effect's perturbation removed.
struct Feed<'a, 'c> {
    comp: Compensator,
    h: f64,
    temperatures: &'a TemperatureSeries,
    reference_temperature_degc: f64,
    tracker: ContextTracker,
    corrected: ContextTracker,
    correction: Option<&'c mut Box<dyn ExtraEffect>>,
}

impl Feed<'_, '_> {
    fn inputs(&mut self, s: &ImuSample) -> SampleInputs {
        let h = self.h;
        let mut dtheta = self.comp.dtheta_rad(&s.dtheta_rad, h);
        let mut dv = self.comp.dv_mps(&s.dv_mps, h, &s.temp_degc);
        let rate = self.temperatures.rate_at(s.t_s - 0.5 * h);
        let mut ctx = self.tracker.next(s.t_s, h, dtheta, dv, s.temp_degc, rate);
        if let Some(c) = self.correction.as_deref_mut() {
            let (p_theta, p_v) = c.perturbation(&ctx);
            dtheta -= p_theta;
            dv -= p_v;
            ctx = self.corrected.next(s.t_s, h, dtheta, dv, s.temp_degc, rate);
        }
        SampleInputs {
            h_s: h,
            dtheta_rad: dtheta,
            dv_mps: dv,
            dtemp_degc: s.temp_degc.map(|t| t - self.reference_temperature_degc),
            ctx,
        }
    }
}

/// Constants of a pass.
struct Consts {
    h: f64,
    spb: usize,
    phi_update: Mat7,
    phi_bin: Mat7,
    q_earth_sample: Quat,
}

/// The attitude that resolves a sample's increment perturbation `δ_j` in NED to second order:
/// `Σ_j ∫_j C(t) δf(t) dt = Σ_j C_eff,j δ_j + O(h³)` with
/// `C_eff,j = C_mid,j (I - [(θ_{j+1} - θ_{j-1})×]/12 - [θ_j×]²/24)`, where `C_mid,j` is the
/// attitude at the middle of the sample for a constant rate and `θ` the gyro increments. The
/// rate change inside the sample shifts the true mid-sample attitude, and the curvature of the
/// perturbation is moved onto the neighbouring attitudes by summation by parts, so the
/// correction is the same for every column. Without it, perturbations that correlate with the
/// vibration (size effect, time offset) rectify with the one-sample coning error of the
/// quadrature.
fn effective_attitude(
    c_mid: &sins_nav::Mat3,
    prev: &Vec3,
    cur: &Vec3,
    next: &Vec3,
) -> sins_nav::Mat3 {
    let d = skew(&(next - prev));
    let t = skew(cur);
    c_mid * (sins_nav::Mat3::identity() - d / 12.0 - t * t / 24.0)
}

/// Mutable state of the pass.
struct State {
    i: usize,
    phase: Phase,
    sum_dtheta: Vec3,
    sum_dv: Vec3,
    q: Quat,
    c_align: sins_nav::Mat3,
    bin_end: usize,
    update_k: usize,
    nav_bins: usize,
    att: AttitudeMoments,
    times: PassTimes,
    bin_start: usize,
    c_prev: Option<sins_nav::Mat3>,
}

impl State {
    /// The state before the first sample of a run starting at `t0` (s), samples `h` apart.
    fn new(rep: &AlignmentReplica, t0: f64, h: f64) -> Self {
        State {
            i: 0,
            phase: Phase::Coarse,
            sum_dtheta: Vec3::zeros(),
            sum_dv: Vec3::zeros(),
            q: Quat::identity(),
            c_align: sins_nav::Mat3::identity(),
            bin_end: rep.n_coarse,
            update_k: 0,
            nav_bins: 0,
            att: AttitudeMoments::default(),
            times: PassTimes {
                start_s: t0,
                nav_start_s: t0 + rep.n_total as f64 * h,
                ..Default::default()
            },
            bin_start: 0,
            c_prev: None,
        }
    }

    /// Process one sample with the gyro increments of its neighbours.
    #[allow(clippy::too_many_arguments)]
    fn sample(
        &mut self,
        inputs: &SampleInputs,
        seg: u16,
        theta_prev: &Vec3,
        theta_next: &Vec3,
        inp: &PassInput<'_>,
        k: &Consts,
        bank: &mut ColumnBank,
        noise: &mut NoiseProp,
    ) -> Result<(), DiagError> {
        let h = k.h;
        let dtheta = inputs.dtheta_rad;
        match self.phase {
            Phase::Coarse => {
                bank.add_coarse(inputs);
                self.sum_dtheta += dtheta;
                self.sum_dv += inputs.dv_mps;
            }
            Phase::Fine | Phase::Nav => {
                let c = if self.phase == Phase::Fine {
                    self.c_align
                } else {
                    let q_mid = self.q * quat_from_rotation_vector(&(0.5 * dtheta));
                    let c_mid = q_mid.to_rotation_matrix().into_inner();
                    effective_attitude(&c_mid, theta_prev, &dtheta, theta_next)
                };
                let w = (self.bin_end - self.i) as f64 * h - 0.5 * h;
                bank.add(inputs, &c, w);
                self.att.add(&c, h, w);
                if let Some(prev) = &self.c_prev {
                    self.att.add_change(&(c - prev));
                }
                self.c_prev = Some(c);
                if self.phase == Phase::Nav {
                    self.q = k.q_earth_sample * self.q * quat_from_rotation_vector(&dtheta);
                }
            }
        }
        self.i += 1;
        if self.i == self.bin_end {
            self.end_bin(inp, bank, noise, &k.phi_update, &k.phi_bin, k.spb, h, seg)?;
        }
        Ok(())
    }

    /// Reset the attitude to the track's estimate if a point ends at the last sample.
    fn anchor(&mut self, anchors: &[(usize, Quat)], cursor: &mut usize) {
        let last = self.i.saturating_sub(1);
        while *cursor < anchors.len() && anchors[*cursor].0 < last {
            *cursor += 1;
        }
        if *cursor < anchors.len() && anchors[*cursor].0 == last {
            self.q = anchors[*cursor].1;
            *cursor += 1;
        }
    }

    /// Close the bin that ended with sample `self.i - 1`.
    #[allow(clippy::too_many_arguments)]
    fn end_bin(
        &mut self,
        inp: &PassInput<'_>,
        bank: &mut ColumnBank,
        noise: &mut NoiseProp,
        phi_update: &Mat7,
        phi_bin: &Mat7,
        spb: usize,
        h: f64,
        seg: u16,
    ) -> Result<(), DiagError> {
        let rep = inp.replica;
        let model = inp.model;
        match self.phase {
            Phase::Coarse => {
                let dur = rep.n_coarse as f64 * h;
                let f = self.sum_dv / dur;
                let w = self.sum_dtheta / dur;
                let q = coarse_align(&f, &w)?;
                let j = coarse_jacobian(&f, &w)?;
                bank.end_coarse(&j, dur);
                noise.end_coarse(model, &j, dur);
                self.q = q;
                self.c_align = q.to_rotation_matrix().into_inner();
                self.phase = Phase::Fine;
            }
            Phase::Fine => {
                let len = self.i - self.bin_start;
                let full = len == rep.samples_per_update;
                let phi = if full {
                    *phi_update
                } else {
                    model.transition(len as f64 * h)
                };
                bank.end_bin(model, &phi);
                noise.step(model, &phi, &self.att, len as f64 * h);
                self.att = AttitudeMoments::default();
                if full {
                    bank.align_update(rep, self.update_k);
                    noise.align_update(rep, self.update_k);
                    self.update_k += 1;
                }
            }
            Phase::Nav => {
                bank.end_bin(model, phi_bin);
                noise.step(model, phi_bin, &self.att, spb as f64 * h);
                self.att = AttitudeMoments::default();
                self.nav_bins += 1;
                let g = inp.grid;
                if self.nav_bins.is_multiple_of(g.output_every_s.max(1)) {
                    let k = self.times.times_s.len();
                    let fit = (k + 1).is_multiple_of(g.fit_every.max(1));
                    bank.record();
                    noise.record(fit);
                    self.times
                        .times_s
                        .push(self.times.nav_start_s + self.nav_bins as f64 * spb as f64 * h);
                    self.times.segments.push(seg);
                    if fit {
                        self.times.fit_index.push(k);
                    }
                }
            }
        }
        // Open the next bin.
        self.bin_start = self.i;
        if self.phase == Phase::Fine && self.i >= rep.n_total {
            bank.nav_start();
            noise.nav_start();
            self.phase = Phase::Nav;
        }
        self.bin_end = match self.phase {
            Phase::Coarse => rep.n_coarse,
            Phase::Fine => (self.i + rep.samples_per_update).min(rep.n_total),
            Phase::Nav => self.i + spb,
        };
        Ok(())
    }
}
