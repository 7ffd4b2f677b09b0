//! The streaming calibration: compensation with the running estimate → 20 min stationary
//! self-alignment → free-inertial navigation through the rotation scheme with the closed-loop
//! Kalman filter of section 3.1.
//!
//! Closed loop everywhere: after each measurement update the navigation errors are corrected in
//! the strapdown solution and the coefficient errors are added to the running estimate, which
//! compensates the following raw samples (eqs 3-5, exactly inverted). The error states are thus
//! zero before every propagation, the navigation errors never exceed one update interval's
//! growth, and the coefficient residuals shrink as the filter converges — so the first-order
//! model of eq (6) stays accurate although the initial errors are large and the table turns at
//! 9 deg/s. The covariance is unaffected by the resets (the estimate moves, not the error).

use crate::config::CalibrationConfig;
use crate::engine::{Engine, SharedGain};
use crate::error::CalibrationError;
use crate::report::{CalibrationResult, ObservabilityReport, Snapshot, StandardizedInnovation};
use crate::states::{NAV_STATES, params_from_vec, params_to_vec};
use sins_imu::{Compensator, ImuErrorParams, ImuSample, ParamModel};
use sins_nav::alignment::SelfAlignment;
use sins_nav::earth::EarthAt;
use sins_nav::{ConingOrder, Increment, StrapdownConfig, Vec3, VerticalChannel};

/// The calibration filter. Feed raw samples in time order with [`CalibrationFilter::push`],
/// then call [`CalibrationFilter::finish`].
pub struct CalibrationFilter {
    config: CalibrationConfig,
    h: f64,
    initial_params: ImuErrorParams,
    estimate: Vec<f64>,
    compensator: Compensator,
    initial_sigma: Vec<f64>,
    phase: Phase,
    last_t_s: Option<f64>,
    first_t_s: f64,
    history: Vec<Snapshot>,
    updates_per_snapshot: usize,
    exceeded_s: f64,
    max_innovation_mps: f64,
    max_nis: f64,
    /// Every update's standardized innovation, when kept.
    innovations: Option<Vec<StandardizedInnovation>>,
    role: Role,
    /// How many times the compensation has changed (each applied update).
    generation: u64,
    /// Scratch of [`CalibrationFilter::push_batch`]: a stretch's compensated increments.
    scratch: Vec<Increment>,
}

/// Samples that [`CalibrationFilter::push_batch`] compensates at a time before the filter runs
/// (it runs from one update to the next after that).
const STRETCH_WHILE_ALIGNING: usize = 1024;

/// Whether a filter keeps its own covariance, hands its gains on, or applies another's.
enum Role {
    Alone,
    /// The gains of the updates since the last [`CalibrationFilter::take_gains`].
    Leading(Vec<SharedGain>),
    Following,
}

enum Phase {
    Waiting,
    Aligning(Box<SelfAlignment>),
    Calibrating(Box<Engine>),
}

impl CalibrationFilter {
    /// A filter with `config`, starting from the coefficient estimate `initial_params` (its
    /// reference temperature is used for ΔT; coefficients outside `config.model` are ignored).
    pub fn new(
        config: CalibrationConfig,
        initial_params: ImuErrorParams,
    ) -> Result<Self, CalibrationError> {
        config.validate()?;
        let model = config.model;
        if !initial_params.is_finite() {
            return Err(CalibrationError::InitialParams(
                "non-finite coefficient".into(),
            ));
        }
        let estimate = params_to_vec(&initial_params, model);
        let reference = initial_params.reference_temperature_degc;
        let start = params_from_vec(&estimate, model, reference);
        let compensator = Compensator::new(start)
            .ok_or_else(|| CalibrationError::InitialParams("I + E is singular".into()))?;
        let s = &config.initial_sigma;
        let e = EarthAt::new(config.site.lat_rad, config.site.height_m);
        let mut initial_sigma = vec![
            s.level_rad,
            s.level_rad,
            s.heading_rad,
            s.velocity_mps,
            s.velocity_mps,
            s.velocity_mps,
            s.position_m / e.meridian_plus_h_m,
            s.position_m / (e.transverse_plus_h_m * e.cos_lat),
            s.position_m,
        ];
        initial_sigma.extend(params_to_vec(&s.params, model));
        let t_update = config.samples_per_update() as f64 * config.sample_interval_s;
        Ok(Self {
            h: config.sample_interval_s,
            updates_per_snapshot: ((config.snapshot_interval_s / t_update).round() as usize).max(1),
            config,
            initial_params: start,
            estimate,
            compensator,
            initial_sigma,
            phase: Phase::Waiting,
            last_t_s: None,
            first_t_s: 0.0,
            history: Vec::new(),
            exceeded_s: 0.0,
            max_innovation_mps: 0.0,
            max_nis: 0.0,
            innovations: None,
            role: Role::Alone,
            generation: 0,
            scratch: Vec::new(),
        })
    }

    /// Keep every update's standardized innovation for [`CalibrationResult::innovations`]
    /// (three numbers per update).
    pub fn keep_innovations(mut self) -> Self {
        self.innovations = Some(Vec::new());
        self
    }

    /// Hand this filter's gains on (see [`CalibrationFilter::take_gains`]) to filters that
    /// follow it over the same run with slightly different samples (the diagnosis's absorption:
    /// the run once per small perturbation). Its own results are unchanged.
    pub fn leading(mut self) -> Self {
        self.role = Role::Leading(Vec::new());
        self
    }

    /// Keep no covariance: apply, at each update, the gain of a leading filter fed with the same
    /// run (see [`CalibrationFilter::push_led`]) to this filter's own innovation; an update the
    /// leader rejected, or whose innovation exceeds the gate, is rejected. Each update then
    /// costs a product with the innovation instead of a propagation and a Joseph update, and
    /// each sample skips the transition sums (about half a filter's work). The estimate differs
    /// from that of a filter with its own covariance by the gains' difference (first order in
    /// the difference of the two filters' samples) times the innovations: small for small
    /// perturbations of a run the leader fits well, but a perturbation that changes the gains
    /// much (a time offset under rotation) needs a filter of its own.
    pub fn following(mut self) -> Self {
        self.role = Role::Following;
        self
    }

    /// A leading filter's gains since the last call, one per update, in order (empty for other
    /// filters).
    pub fn take_gains(&mut self) -> Vec<SharedGain> {
        match &mut self.role {
            Role::Leading(gains) => std::mem::take(gains),
            _ => Vec::new(),
        }
    }

    /// [`CalibrationFilter::push`] for a following filter: an update takes the next of the
    /// leader's `gains` (its [`CalibrationFilter::take_gains`] over the same samples).
    pub fn push_led(
        &mut self,
        s: &ImuSample,
        gains: &mut std::slice::Iter<'_, SharedGain>,
    ) -> Result<(), CalibrationError> {
        self.check_sample(s)?;
        let (dtheta, dv) = self.compensate(s);
        self.push_compensated(s, dtheta, dv, Some(gains))
    }

    /// Feed `samples` (time order) as [`CalibrationFilter::push`] does one by one or, with
    /// `gains`, as [`CalibrationFilter::push_led`] does; the same results to the bit, but each
    /// stretch between two updates (where the compensation stays the same) is compensated
    /// four samples at a time ([`Compensator::compensate_into`]). Stops at the first error,
    /// after the samples before it.
    pub fn push_batch(
        &mut self,
        samples: &[ImuSample],
        mut gains: Option<&mut std::slice::Iter<'_, SharedGain>>,
    ) -> Result<(), CalibrationError> {
        let mut incs = std::mem::take(&mut self.scratch);
        let result = self.push_stretches(samples, &mut gains, &mut incs);
        self.scratch = incs;
        result
    }

    /// [`CalibrationFilter::push_batch`] with its scratch of compensated increments.
    fn push_stretches(
        &mut self,
        samples: &[ImuSample],
        gains: &mut Option<&mut std::slice::Iter<'_, SharedGain>>,
        incs: &mut Vec<Increment>,
    ) -> Result<(), CalibrationError> {
        let led = gains.is_some();
        let mut rest = samples;
        while !rest.is_empty() {
            let stretch = match &self.phase {
                Phase::Calibrating(engine) => engine.samples_to_update(led),
                Phase::Waiting | Phase::Aligning(_) => STRETCH_WHILE_ALIGNING,
            };
            let (head, tail) = rest.split_at(stretch.min(rest.len()));
            let checked = head
                .iter()
                .take_while(|s| self.check_sample(s).is_ok())
                .count();
            let mut todo = &head[..checked];
            while !todo.is_empty() {
                incs.clear();
                let hs = [self.h; STRETCH_WHILE_ALIGNING];
                for part in todo.chunks(hs.len()) {
                    self.compensator.compensate_into(part, &hs, incs);
                }
                let generation = self.generation;
                let mut done = 0;
                for (s, inc) in todo.iter().zip(incs.iter()) {
                    let gains = gains.as_deref_mut();
                    self.push_compensated(s, inc.dtheta_rad, inc.dv_mps, gains)?;
                    done += 1;
                    // An update changed the compensation: compensate the rest again.
                    if self.generation != generation {
                        break;
                    }
                }
                todo = &todo[done..];
            }
            if checked < head.len() {
                // The sample that failed its check, checked again for its error.
                return self.check_sample(&head[checked]);
            }
            rest = tail;
        }
        Ok(())
    }

    /// The compensated increments of `s` with the current estimate (rad, m/s).
    #[inline]
    fn compensate(&self, s: &ImuSample) -> (Vec3, Vec3) {
        let h = self.h;
        let dtheta = self.compensator.dtheta_rad(&s.dtheta_rad, h);
        let dv = self.compensator.dv_mps(&s.dv_mps, h, &s.temp_degc);
        (dtheta, dv)
    }

    /// One checked sample's compensated increments into the alignment or the filter: a
    /// following filter's update takes the next of `gains`.
    #[inline]
    fn push_compensated(
        &mut self,
        s: &ImuSample,
        dtheta: Vec3,
        dv: Vec3,
        gains: Option<&mut std::slice::Iter<'_, SharedGain>>,
    ) -> Result<(), CalibrationError> {
        let Phase::Calibrating(engine) = &mut self.phase else {
            return self.align(s, dtheta, dv);
        };
        let Some(gains) = gains else {
            let dtemp = self
                .compensator
                .params()
                .temperature_offsets_degc(&s.temp_degc);
            if engine.push(dtheta, dv, dtemp) {
                self.update()?;
            }
            return Ok(());
        };
        if !engine.push_led(dtheta, dv) {
            return Ok(());
        }
        let t_s = engine.nav.state().t_s;
        let gain = gains.next().ok_or(CalibrationError::Diverged {
            t_s,
            reason: "the leading filter made fewer updates",
        })?;
        let gate_mps = self.config.motion_check.max_horizontal_innovation_mps;
        let out = engine
            .update_led(gain, gate_mps)
            .map_err(|reason| CalibrationError::Diverged { t_s, reason })?;
        self.apply(out)
    }

    /// The current estimate of the constant coefficients.
    pub fn estimate(&self) -> ImuErrorParams {
        let r = self.initial_params.reference_temperature_degc;
        params_from_vec(&self.estimate, self.config.model, r)
    }

    /// True once the alignment is complete and the Kalman filter runs.
    pub fn is_calibrating(&self) -> bool {
        matches!(self.phase, Phase::Calibrating(_))
    }

    /// The convergence history so far.
    pub fn history(&self) -> &[Snapshot] {
        &self.history
    }

    /// Add one raw sample (time order, evenly spaced at the configured interval).
    pub fn push(&mut self, s: &ImuSample) -> Result<(), CalibrationError> {
        self.check_sample(s)?;
        let (dtheta, dv) = self.compensate(s);
        self.push_compensated(s, dtheta, dv, None)
    }

    fn align(&mut self, s: &ImuSample, dtheta: Vec3, dv: Vec3) -> Result<(), CalibrationError> {
        if let Phase::Waiting = self.phase {
            self.first_t_s = s.t_s - self.h;
            let nav = StrapdownConfig {
                sample_interval_s: self.h,
                coning: ConingOrder::TwoSample,
                vertical: VerticalChannel::Hold {
                    height_m: self.config.site.height_m,
                },
            };
            let a =
                SelfAlignment::new(self.config.alignment, nav, self.config.site, self.first_t_s);
            self.phase = Phase::Aligning(Box::new(a));
        }
        if let Phase::Aligning(a) = &mut self.phase {
            let inc = Increment {
                dtheta_rad: dtheta,
                dv_mps: dv,
            };
            if a.push(&inc)? {
                let result = a.finish()?;
                let engine = Engine::new(&self.config, result, &self.initial_sigma);
                self.phase = Phase::Calibrating(Box::new(engine));
            }
        }
        Ok(())
    }

    fn check_sample(&mut self, s: &ImuSample) -> Result<(), CalibrationError> {
        let finite = |v: &Vec3| v.iter().all(|x| x.is_finite());
        if !(s.t_s.is_finite() && finite(&s.dtheta_rad) && finite(&s.dv_mps)) {
            return Err(CalibrationError::BadSample {
                t_s: s.t_s,
                reason: "non-finite time or increment",
            });
        }
        if self.config.model == ParamModel::States42 && !s.temp_degc.iter().all(|t| t.is_finite()) {
            return Err(CalibrationError::BadSample {
                t_s: s.t_s,
                reason: "the 42-state model needs all three accelerometer temperatures",
            });
        }
        if let Some(last) = self.last_t_s {
            let gap = s.t_s - last;
            if (gap - self.h).abs() > 1e-3 * self.h {
                return Err(CalibrationError::TimeGap {
                    t_s: s.t_s,
                    gap_s: gap,
                    expected_s: self.h,
                });
            }
        }
        self.last_t_s = Some(s.t_s);
        Ok(())
    }

    /// One measurement update of the engine, then [`CalibrationFilter::apply`].
    fn update(&mut self) -> Result<(), CalibrationError> {
        let Phase::Calibrating(engine) = &mut self.phase else {
            return Ok(());
        };
        let t_s = engine.nav.state().t_s;
        if let Role::Following = self.role {
            return Err(CalibrationError::Diverged {
                t_s,
                reason: "a following filter needs its leader's gains (push_led)",
            });
        }
        let mc = self.config.motion_check;
        let share = matches!(self.role, Role::Leading(_));
        let mut out = engine
            .update(mc.max_horizontal_innovation_mps, share)
            .map_err(|reason| CalibrationError::Diverged { t_s, reason })?;
        if let (Role::Leading(gains), Some(gain)) = (&mut self.role, out.gain.take()) {
            gains.push(gain);
        }
        self.apply(out)
    }

    /// An update's motion check, coefficient feedback into the compensation and history.
    fn apply(&mut self, out: crate::engine::UpdateOutcome) -> Result<(), CalibrationError> {
        let Phase::Calibrating(engine) = &mut self.phase else {
            return Ok(());
        };
        let mc = self.config.motion_check;
        self.max_innovation_mps = self.max_innovation_mps.max(out.horizontal_innovation_mps);
        self.max_nis = self.max_nis.max(out.horizontal_nis);
        if let Some(kept) = self.innovations.as_mut() {
            let [north, east] = out.standardized;
            kept.push(StandardizedInnovation {
                t_s: out.t_s,
                north,
                east,
            });
        }
        if out.rejected {
            self.exceeded_s += engine.interval_s();
            if self.exceeded_s > mc.max_duration_s {
                return Err(CalibrationError::NotStationary {
                    t_s: out.t_s,
                    innovation_mps: out.horizontal_innovation_mps,
                    duration_s: self.exceeded_s,
                    limit_mps: mc.max_horizontal_innovation_mps,
                });
            }
            return Ok(());
        }
        self.exceeded_s = 0.0;
        for (e, dx) in self.estimate.iter_mut().zip(&out.dparams) {
            *e += dx;
        }
        let reference = self.initial_params.reference_temperature_degc;
        let mut applied = params_from_vec(&self.estimate, self.config.model, reference);
        let (wg, wa) = engine.wander_bias();
        applied.gyro.bias_radps += wg;
        applied.accel.bias_mps2 += wa;
        self.compensator = Compensator::new(applied).ok_or(CalibrationError::Diverged {
            t_s: out.t_s,
            reason: "estimate not invertible",
        })?;
        self.generation += 1;
        let following = matches!(self.role, Role::Following);
        if !following && engine.updates % self.updates_per_snapshot == 0 {
            self.history.push(Snapshot {
                t_s: out.t_s,
                estimate: self.estimate.clone(),
                sigma: engine.sigmas(),
            });
        }
        Ok(())
    }

    /// End a following filter's run: its estimate (a following filter keeps no covariance, so
    /// no 1-sigma, history or observability report).
    pub fn finish_led(self) -> Result<ImuErrorParams, CalibrationError> {
        self.engine_with_updates()?;
        Ok(self.estimate())
    }

    /// The engine, once it has made an update.
    fn engine_with_updates(&self) -> Result<&Engine, CalibrationError> {
        let got_s = self.last_t_s.map_or(0.0, |t| t - self.first_t_s);
        let needed_s = self.config.alignment.duration_s + self.config.update_interval_s;
        match &self.phase {
            Phase::Calibrating(engine) if engine.updates > 0 => Ok(engine),
            _ => Err(CalibrationError::TooShort { got_s, needed_s }),
        }
    }

    /// End the run: the estimate, its 1-sigma, the history and the observability report (a
    /// following filter: see [`CalibrationFilter::finish_led`]).
    pub fn finish(mut self) -> Result<CalibrationResult, CalibrationError> {
        let engine = self.engine_with_updates()?;
        if let Role::Following = self.role {
            return Err(CalibrationError::Config {
                field: "following",
                reason: "a following filter keeps no covariance; take its estimate with finish_led"
                    .into(),
            });
        }
        let (sigma, t_end) = (engine.sigmas(), engine.nav.state().t_s);
        let (alignment, updates) = (engine.alignment, engine.updates);
        let param_covariance = engine.param_covariance();
        if self.history.last().is_none_or(|s| s.t_s < t_end) {
            self.history.push(Snapshot {
                t_s: t_end,
                estimate: self.estimate.clone(),
                sigma: sigma.clone(),
            });
        }
        let model = self.config.model;
        let reference = self.initial_params.reference_temperature_degc;
        Ok(CalibrationResult {
            params: self.estimate(),
            sigma: params_from_vec(&sigma[NAV_STATES..], model, reference),
            param_covariance,
            initial_params: self.initial_params,
            initial_sigma: params_from_vec(&self.initial_sigma[NAV_STATES..], model, reference),
            observability: ObservabilityReport::new(
                &self.initial_sigma,
                &sigma,
                self.config.weak_ratio,
            ),
            alignment,
            filter_start_s: alignment.state.t_s,
            filter_end_s: t_end,
            updates,
            max_innovation_mps: self.max_innovation_mps,
            max_normalized_innovation: self.max_nis,
            innovations: self.innovations.unwrap_or_default(),
            history: self.history,
        })
    }
}
