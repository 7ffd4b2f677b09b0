//! What the scan reports: the events, the channels an event cannot be told from, the detectable
//! levels, and the scan over all runs.

use serde::{Deserialize, Serialize};

/// One time-local event.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimeLocalEvent {
    /// Run name.
    pub run: String,
    /// Channel: `gyro x` ... `accel z` (body axes).
    pub channel: String,
    /// `step`, `ramp`, `transient` or `turn-on transient`.
    pub shape: String,
    /// The effect kind it is reported as (`gyro_bias_step` ...).
    pub kind: String,
    /// Onset (s, the run's time axis).
    pub onset_s: f64,
    /// One-sigma of the onset (s): a third of the larger side of `onset_interval_s`.
    pub onset_sigma_s: f64,
    /// Three-sigma profile-likelihood interval of the onset (s): the onsets whose `T` is
    /// within 9 of the best.
    pub onset_interval_s: [f64; 2],
    /// Size in `unit` (a step's jump, a ramp's rate, a transient's value at onset).
    pub size: f64,
    /// One-sigma of the size given the onset.
    pub size_sigma: f64,
    /// Unit of the size.
    pub unit: String,
    /// Time constant of a transient (s).
    pub time_constant_s: Option<f64>,
    /// Duration of a pulse, rise time of a plateau (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// `(ŝᵀr̂)²/ŝᵀŝ`: chi-square of one degree of freedom.
    pub chi2: f64,
    /// Tail probability corrected for the number of tests (Bonferroni).
    pub p_value: f64,
    /// A catalogue candidate that explains it (its columns of the run make it insignificant).
    pub explained_by: Option<String>,
    /// Other channels whose best signal fits the run's residual within 9 (three sigma) of this
    /// event's `T`: the data do not tell them from this one (a level accelerometer's turn-on
    /// transient and a gyro's both leave the alignment with a tilt). Strongest first.
    #[serde(default)]
    pub alternatives: Vec<ChannelAlternative>,
}

/// A channel an event cannot be told from (see [`TimeLocalEvent::alternatives`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChannelAlternative {
    /// Channel (`gyro x` ...).
    pub channel: String,
    /// Shape of its best signal.
    pub shape: String,
    /// Time constant of that signal if a transient (s).
    pub time_constant_s: Option<f64>,
    /// Duration of that signal if a pulse, rise time if a plateau (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// Its `T` against the same residual.
    pub chi2: f64,
}

/// The detectable size of one shape on one channel of one run at onsets through the run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DetectableCurve {
    /// Run name.
    pub run: String,
    /// Channel (`gyro x` ...).
    pub channel: String,
    /// Shape label.
    pub shape: String,
    /// Time constant of a transient (s).
    pub time_constant_s: Option<f64>,
    /// Duration of a pulse, rise time of a plateau (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// Unit of the levels.
    pub unit: String,
    /// Onsets (s).
    pub onset_s: Vec<f64>,
    /// Size detected with 90 % probability at the scan's corrected level, at each onset.
    pub level: Vec<f64>,
}

/// The scan's result over all runs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EventScan {
    /// Events, run by run, strongest first within a run.
    pub events: Vec<TimeLocalEvent>,
    /// Tests in the family (onsets × shapes × axes × runs).
    pub tests: usize,
    /// The corrected threshold on `T`.
    pub threshold_chi2: f64,
    /// Detectable levels.
    pub detectable: Vec<DetectableCurve>,
}
