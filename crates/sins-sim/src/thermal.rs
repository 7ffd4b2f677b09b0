//! Thermal chamber and accelerometer temperatures.
//!
//! The chamber temperature `T_c(t)` is piecewise: on each segment `c0 + s τ + A sin(ω τ)`
//! (τ from the segment start; hold: s = A = 0 with the set point as c0), held after the last
//! segment. Each accelerometer follows `dT_j/dt = (T_c(t) + o_j − T_j)/τ_j`, which has the exact
//! solution `T_j(t) = P_j(t) + (T_j(t_a) − P_j(t_a)) e^{−(t − t_a)/τ_j}` on a segment, with the
//! particular solution `P_j = c0 + o_j + s (τ − τ_j) + A (sin ωτ − ωτ_j cos ωτ)/(1 + ω²τ_j²)`.
//! Steps are split at segment boundaries, so the temperatures are exact for any step length.
//! Before t = 0 the chamber is at `chamber_start_degc`; accelerometers starting "in equilibrium"
//! are at `chamber_start_degc + o_j`.

use crate::error::{SimError, finite_reason, non_negative_reason, positive_reason};
use crate::noise::GaussianStream;
use crate::scenario::{ChamberSegment, ThermalModel};
use crate::trig::{reduced_phase, sin_cos};

/// One chamber segment: `T_c = c0 + s (t − start) + A sin(ω (t − start))` on `[start, end)`.
#[derive(Clone, Copy, Debug)]
struct ChamberPiece {
    start_s: f64,
    end_s: f64,
    c0_degc: f64,
    slope_degc_per_s: f64,
    amp_degc: f64,
    omega_radps: f64,
}

impl ChamberPiece {
    /// `(s τ, sin ωτ, cos ωτ)` at absolute time `t_s`.
    #[inline]
    fn terms(&self, t_s: f64) -> (f64, f64, f64) {
        let tau = t_s - self.start_s;
        let (s, c) = if self.amp_degc == 0.0 {
            (0.0, 1.0)
        } else {
            sin_cos(reduced_phase(self.omega_radps, tau, 0.0))
        };
        (self.slope_degc_per_s * tau, s, c)
    }
}

/// The chamber temperature profile.
#[derive(Clone, Debug)]
pub struct ChamberProfile {
    /// A constant piece before 0, the segments, and a constant piece after the end.
    pieces: Vec<ChamberPiece>,
}

fn chamber_error(
    index: usize,
    kind: &'static str,
    field: &'static str,
    r: Option<String>,
) -> Result<(), SimError> {
    r.map_or(Ok(()), |reason| {
        Err(SimError::ChamberSegment {
            index,
            kind,
            field,
            reason,
        })
    })
}

fn field_error(field: &'static str, r: Option<String>) -> Result<(), SimError> {
    r.map_or(Ok(()), |reason| Err(SimError::Field { field, reason }))
}

impl ChamberProfile {
    /// Validate and build the profile of `model` (errors name the chamber segment and field).
    pub fn new(model: &ThermalModel) -> Result<Self, SimError> {
        field_error(
            "thermal.chamber_start_degc",
            finite_reason(model.chamber_start_degc),
        )?;
        let constant = |start_s: f64, end_s: f64, c0_degc: f64| ChamberPiece {
            start_s,
            end_s,
            c0_degc,
            slope_degc_per_s: 0.0,
            amp_degc: 0.0,
            omega_radps: 0.0,
        };
        let mut pieces = vec![constant(-1.0, 0.0, model.chamber_start_degc)];
        let (mut t, mut temp) = (0.0, model.chamber_start_degc);
        for (i, seg) in model.chamber.iter().enumerate() {
            let kind = match seg {
                ChamberSegment::Hold { .. } => "hold",
                ChamberSegment::Ramp { .. } => "ramp",
                ChamberSegment::Fluctuating { .. } => "fluctuating",
            };
            let piece = match *seg {
                ChamberSegment::Hold {
                    duration_s,
                    temp_degc,
                } => {
                    chamber_error(i, "hold", "duration_s", positive_reason(duration_s))?;
                    chamber_error(i, "hold", "temp_degc", finite_reason(temp_degc))?;
                    constant(t, t + duration_s, temp_degc)
                }
                ChamberSegment::Ramp {
                    duration_s,
                    rate_degc_per_s,
                } => {
                    chamber_error(i, "ramp", "duration_s", positive_reason(duration_s))?;
                    chamber_error(i, "ramp", "rate_degc_per_s", finite_reason(rate_degc_per_s))?;
                    ChamberPiece {
                        slope_degc_per_s: rate_degc_per_s,
                        ..constant(t, t + duration_s, temp)
                    }
                }
                ChamberSegment::Fluctuating {
                    duration_s,
                    rate_degc_per_s,
                    fluctuation_amplitude_degc,
                    fluctuation_period_s,
                } => {
                    let k = kind;
                    chamber_error(i, k, "duration_s", positive_reason(duration_s))?;
                    chamber_error(i, k, "rate_degc_per_s", finite_reason(rate_degc_per_s))?;
                    let amp = fluctuation_amplitude_degc;
                    chamber_error(i, k, "fluctuation_amplitude_degc", finite_reason(amp))?;
                    let period = fluctuation_period_s;
                    chamber_error(i, k, "fluctuation_period_s", positive_reason(period))?;
                    ChamberPiece {
                        slope_degc_per_s: rate_degc_per_s,
                        amp_degc: amp,
                        omega_radps: std::f64::consts::TAU / period,
                        ..constant(t, t + duration_s, temp)
                    }
                }
            };
            let (lin, sin, _) = piece.terms(piece.end_s);
            temp = piece.c0_degc + lin + piece.amp_degc * sin;
            let reason = (!(piece.end_s.is_finite() && temp.is_finite()))
                .then(|| format!("makes the profile end at {} s, {temp} degC", piece.end_s));
            chamber_error(i, kind, "duration_s", reason)?;
            t = piece.end_s;
            pieces.push(piece);
        }
        pieces.push(constant(t, f64::INFINITY, temp));
        Ok(Self { pieces })
    }

    /// Chamber temperature (degC) at `t_s`.
    pub fn temperature_degc(&self, t_s: f64) -> f64 {
        let i = self.pieces.partition_point(|p| p.end_s <= t_s);
        let p = &self.pieces[i.min(self.pieces.len() - 1)];
        let (lin, s, _) = p.terms(t_s);
        p.c0_degc + lin + p.amp_degc * s
    }
}

/// Exact first-order lags of the three accelerometers behind the chamber, advanced in time order.
#[derive(Clone, Debug)]
pub struct AccelThermal {
    profile: ChamberProfile,
    tau_s: [f64; 3],
    inv_tau_per_s: [f64; 3],
    offset_degc: [f64; 3],
    /// Constant parts of the particular solution on the current piece, per accelerometer:
    /// `c0 + o_j − s τ_j`, `A/(1 + ω²τ_j²)` and `A ω τ_j/(1 + ω²τ_j²)`.
    base_degc: [f64; 3],
    sin_gain_degc: [f64; 3],
    cos_gain_degc: [f64; 3],
    piece: usize,
    time_s: f64,
    temp_degc: [f64; 3],
    /// Particular solution and chamber temperature at `time_s` for the current piece.
    particular_degc: [f64; 3],
    chamber_degc: f64,
    nominal_step_s: f64,
    nominal_decay: [f64; 3],
    /// `(sin ωτ, cos ωτ)` of the chamber fluctuation at `time_s`, `(sin, cos)` of ω times the
    /// nominal step, and whether the last evaluation advanced the phase by rotation (the next
    /// one is then computed afresh, so rotations never accumulate).
    phase_sc: (f64, f64),
    nominal_rotation: (f64, f64),
    rotated_last: bool,
}

impl AccelThermal {
    /// Validate `model` and start at t = 0. `nominal_step_s` is the usual step length (steps of
    /// that length reuse precomputed decay factors).
    pub fn new(model: &ThermalModel, nominal_step_s: f64) -> Result<Self, SimError> {
        let profile = ChamberProfile::new(model)?;
        let axes = ["x", "y", "z"];
        for j in 0..3 {
            let tau = model.accel_time_constant_s[j];
            let r = positive_reason(tau).map(|r| format!("({}) {r}", axes[j]));
            field_error("thermal.accel_time_constant_s", r)?;
            let r = finite_reason(model.accel_offset_degc[j]).map(|r| format!("({}) {r}", axes[j]));
            field_error("thermal.accel_offset_degc", r)?;
            if let Some(init) = model.accel_initial_degc {
                let r = finite_reason(init[j]).map(|r| format!("({}) {r}", axes[j]));
                field_error("thermal.accel_initial_degc", r)?;
            }
        }
        let noise = model.thermometer_noise_degc;
        field_error("thermal.thermometer_noise_degc", non_negative_reason(noise))?;
        let offset_degc = model.accel_offset_degc;
        let temp_degc = model
            .accel_initial_degc
            .unwrap_or(offset_degc.map(|o| model.chamber_start_degc + o));
        let tau_s = model.accel_time_constant_s;
        let mut state = Self {
            profile,
            tau_s,
            inv_tau_per_s: tau_s.map(|tau| 1.0 / tau),
            offset_degc,
            base_degc: [0.0; 3],
            sin_gain_degc: [0.0; 3],
            cos_gain_degc: [0.0; 3],
            piece: 0,
            time_s: 0.0,
            temp_degc,
            particular_degc: [0.0; 3],
            chamber_degc: 0.0,
            nominal_step_s,
            nominal_decay: tau_s.map(|tau| (-nominal_step_s / tau).exp()),
            phase_sc: (0.0, 1.0),
            nominal_rotation: (0.0, 1.0),
            rotated_last: false,
        };
        state.piece = state.profile.pieces.partition_point(|p| p.end_s <= 0.0);
        state.enter_piece(0.0);
        Ok(state)
    }

    /// Set the particular-solution constants for the current piece and evaluate it at `t_s`.
    fn enter_piece(&mut self, t_s: f64) {
        let p = self.profile.pieces[self.piece];
        for j in 0..3 {
            let wt = p.omega_radps * self.tau_s[j];
            let gain = p.amp_degc / (1.0 + wt * wt);
            self.base_degc[j] =
                p.c0_degc + self.offset_degc[j] - p.slope_degc_per_s * self.tau_s[j];
            self.sin_gain_degc[j] = gain;
            self.cos_gain_degc[j] = gain * wt;
        }
        self.nominal_rotation = sin_cos(p.omega_radps * self.nominal_step_s);
        // Forces a fresh evaluation (the cached phase belongs to the previous piece).
        self.rotated_last = true;
        self.evaluate(t_s);
    }

    /// Chamber temperature and particular solutions of the current piece at `t_s`. When `t_s`
    /// is one nominal step after `time_s`, every other call advances the fluctuation phase by the
    /// angle-addition formulas instead of a fresh sine and cosine.
    #[inline]
    fn evaluate(&mut self, t_s: f64) {
        let p = &self.profile.pieces[self.piece];
        let tau = t_s - p.start_s;
        let lin = p.slope_degc_per_s * tau;
        let eps = p.omega_radps * ((t_s - self.time_s) - self.nominal_step_s);
        let (s, c) = if p.amp_degc == 0.0 {
            (0.0, 1.0)
        } else if !self.rotated_last && eps.abs() <= 1e-6 {
            // sin/cos of ω (step + ε/ω) from those of ω·step: error below ε³/6.
            let (s0, c0) = self.nominal_rotation;
            let h2 = 0.5 * eps * eps;
            let (sd, cd) = (s0 - s0 * h2 + c0 * eps, c0 - c0 * h2 - s0 * eps);
            let (sa, ca) = self.phase_sc;
            self.rotated_last = true;
            (sa * cd + ca * sd, ca * cd - sa * sd)
        } else {
            self.rotated_last = false;
            sin_cos(reduced_phase(p.omega_radps, tau, 0.0))
        };
        self.phase_sc = (s, c);
        self.chamber_degc = p.c0_degc + lin + p.amp_degc * s;
        for j in 0..3 {
            self.particular_degc[j] =
                self.base_degc[j] + lin + self.sin_gain_degc[j] * s - self.cos_gain_degc[j] * c;
        }
    }

    /// Advance within the current piece from `time_s` to `t_s`.
    #[inline]
    fn advance_within(&mut self, t_s: f64) {
        let step = t_s - self.time_s;
        let mut dev = self.temp_degc;
        for (d, p) in dev.iter_mut().zip(&self.particular_degc) {
            *d -= p;
        }
        self.evaluate(t_s);
        let d = step - self.nominal_step_s;
        for (j, dev_j) in dev.into_iter().enumerate() {
            let x = d * self.inv_tau_per_s[j];
            let decay = if x.abs() <= 1e-6 {
                self.nominal_decay[j] * (1.0 - x + 0.5 * x * x)
            } else {
                (-step * self.inv_tau_per_s[j]).exp()
            };
            self.temp_degc[j] = self.particular_degc[j] + dev_j * decay;
        }
        self.time_s = t_s;
    }

    /// Advance the accelerometer temperatures to `t_s` (not before the current time) exactly,
    /// and return them (degC).
    pub fn advance_to(&mut self, t_s: f64) -> [f64; 3] {
        while t_s >= self.profile.pieces[self.piece].end_s {
            let end = self.profile.pieces[self.piece].end_s;
            if end > self.time_s {
                self.advance_within(end);
            }
            self.piece += 1;
            self.enter_piece(end);
        }
        if t_s > self.time_s {
            self.advance_within(t_s);
        }
        self.temp_degc
    }

    /// Current time of the state (s).
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// True accelerometer temperatures at the current time (degC).
    pub fn temperature_degc(&self) -> [f64; 3] {
        self.temp_degc
    }

    /// Chamber temperature at the current time (degC).
    pub fn chamber_degc(&self) -> f64 {
        self.chamber_degc
    }

    /// `dT_j/dt = (T_c + o_j − T_j)/τ_j` at the current time (degC/s).
    pub fn rate_degc_per_s(&self) -> [f64; 3] {
        std::array::from_fn(|j| {
            (self.chamber_degc + self.offset_degc[j] - self.temp_degc[j]) * self.inv_tau_per_s[j]
        })
    }
}

/// Platinum thermometers: the true temperature plus white noise of a fixed standard deviation,
/// from their own random stream.
#[derive(Clone, Debug)]
pub struct Thermometers {
    sigma_degc: f64,
    gauss: GaussianStream,
}

impl Thermometers {
    /// Thermometers with white noise `sigma_degc` (1 sigma) drawn from `gauss`.
    pub fn new(sigma_degc: f64, gauss: GaussianStream) -> Self {
        Self { sigma_degc, gauss }
    }

    /// Readings (degC) of the three thermometers for true temperatures `true_degc`.
    #[inline]
    pub fn read(&mut self, true_degc: [f64; 3]) -> [f64; 3] {
        if self.sigma_degc == 0.0 {
            return true_degc;
        }
        let mut out = true_degc;
        for t in &mut out {
            *t += self.sigma_degc * self.gauss.next_standard();
        }
        out
    }
}
