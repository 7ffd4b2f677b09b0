//! The scan's settings and its signal shapes.

use serde::{Deserialize, Serialize};
use sins_imu::EffectKind;

/// Settings of the scan.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct EventScanConfig {
    /// Scan at all (false: no events, no detectable levels).
    pub enabled: bool,
    /// Onset grid spacing (s, a whole multiple of the output interval).
    pub onset_every_s: usize,
    /// Time constants of the transients tried (s).
    pub time_constants_s: Vec<f64>,
    /// Durations of the pulses tried (s, rounded to the onset grid; 600-4800 s in octaves by
    /// default, none turns them off). With any, a step found is also tried as either edge of a
    /// pulse.
    pub pulse_durations_s: Vec<f64>,
    /// Rise times of the ramps to a plateau tried (s, rounded to the onset grid; 1200-9600 s
    /// in octaves by default, none turns them off).
    pub plateau_rises_s: Vec<f64>,
    /// Events per run at most.
    pub max_events_per_run: usize,
    /// Family-wise false-alarm level of the scan (all runs, onsets, shapes and axes).
    pub alpha: f64,
    /// Spacing of the onsets at which detectable levels are reported (s).
    pub detectable_every_s: f64,
}

impl Default for EventScanConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            onset_every_s: 120,
            time_constants_s: vec![300.0, 600.0, 1200.0, 2400.0, 4800.0, 9600.0],
            // Octaves: the widened blind draw's pulses and plateaus are located at their onset,
            // not as a step at a pulse's end or a transient at a plateau's top. A walk keeps
            // its evidence against them when its wander makes them insignificant (see
            // `timelocal::excursions`) and is not promoted by their removal when it failed its
            // shape test with them in place (`timelocal::keep_shape_refusals`).
            pulse_durations_s: vec![600.0, 1200.0, 2400.0, 4800.0],
            plateau_rises_s: vec![1200.0, 2400.0, 4800.0, 9600.0],
            max_events_per_run: 3,
            alpha: 1e-3,
            detectable_every_s: 3600.0,
        }
    }
}

/// The shape of a time-local signal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// Bias step.
    Step,
    /// Bias ramp.
    Ramp,
    /// Exponential transient with time constant `tau_s`; `turn_on`: onset at the first sample.
    Transient {
        /// Time constant (s).
        tau_s: f64,
        /// Onset at turn-on (the first sample), not on the navigation grid.
        turn_on: bool,
    },
    /// Bias pulse: a step up at the onset and back down `duration_s` later.
    Pulse {
        /// Duration (s, a whole number of onset-grid steps).
        duration_s: f64,
    },
    /// Ramp from the onset to a plateau reached `rise_s` later; the size is the plateau's level.
    Plateau {
        /// Rise time (s, a whole number of onset-grid steps).
        rise_s: f64,
    },
}

impl EventScanConfig {
    /// The scan without pulses and ramps to a plateau: steps, ramps and transients only (the
    /// scan before 2026-11-30; a smaller family, so a lower threshold).
    pub fn without_pulses_and_plateaus(self) -> Self {
        Self {
            pulse_durations_s: Vec::new(),
            plateau_rises_s: Vec::new(),
            ..self
        }
    }

    /// The distinct pulse durations in onset-grid steps, ascending.
    pub(crate) fn pulse_steps(&self) -> Vec<usize> {
        grid_steps(&self.pulse_durations_s, self.onset_every_s)
    }

    /// The distinct plateau rise times in onset-grid steps, ascending.
    pub(crate) fn plateau_steps(&self) -> Vec<usize> {
        grid_steps(&self.plateau_rises_s, self.onset_every_s)
    }
}

/// `times_s` rounded to whole steps of `every_s` (at least one), distinct and ascending.
fn grid_steps(times_s: &[f64], every_s: usize) -> Vec<usize> {
    let mut n: Vec<usize> = times_s
        .iter()
        .filter(|t| t.is_finite() && **t > 0.0)
        .map(|t| ((t / every_s.max(1) as f64).round() as usize).max(1))
        .collect();
    n.sort_unstable();
    n.dedup();
    n
}

impl Shape {
    /// The effect kind of this shape on `axis` (0-2 gyro, 3-5 accelerometer).
    pub fn kind(self, axis: usize) -> EffectKind {
        let gyro = axis < 3;
        match (self, gyro) {
            (Shape::Step, true) => EffectKind::GyroBiasStep,
            (Shape::Step, false) => EffectKind::AccelBiasStep,
            (Shape::Ramp, true) => EffectKind::GyroBiasRamp,
            (Shape::Ramp, false) => EffectKind::AccelBiasRamp,
            (Shape::Transient { .. }, true) => EffectKind::GyroBiasTransient,
            (Shape::Transient { .. }, false) => EffectKind::AccelBiasTransient,
            (Shape::Pulse { .. }, true) => EffectKind::GyroBiasPulse,
            (Shape::Pulse { .. }, false) => EffectKind::AccelBiasPulse,
            (Shape::Plateau { .. }, true) => EffectKind::GyroBiasPlateau,
            (Shape::Plateau { .. }, false) => EffectKind::AccelBiasPlateau,
        }
    }

    /// `step`, `ramp`, `transient`, `turn-on transient`, `pulse` or `plateau`.
    pub fn label(self) -> &'static str {
        match self {
            Shape::Step => "step",
            Shape::Ramp => "ramp",
            Shape::Transient { turn_on: false, .. } => "transient",
            Shape::Transient { turn_on: true, .. } => "turn-on transient",
            Shape::Pulse { .. } => "pulse",
            Shape::Plateau { .. } => "plateau",
        }
    }

    /// A pulse's duration or a plateau's rise time (s).
    pub(crate) fn duration_s(self) -> Option<f64> {
        match self {
            Shape::Pulse { duration_s } => Some(duration_s),
            Shape::Plateau { rise_s } => Some(rise_s),
            _ => None,
        }
    }

    pub(crate) fn tau_s(self) -> Option<f64> {
        match self {
            Shape::Transient { tau_s, .. } => Some(tau_s),
            _ => None,
        }
    }
}

/// Names of the six axes.
pub const AXES: [&str; 6] = [
    "gyro x", "gyro y", "gyro z", "accel x", "accel y", "accel z",
];
