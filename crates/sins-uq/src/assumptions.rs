//! The replica's assumptions as data: what the paper does not fix, each with a distribution in
//! SI and a justification; and the candidate explanations of the replica-vs-paper gap.

use crate::UqError;
use sins_imu::EffectKind;

/// A distribution of one assumption's value (SI, or a choice index for [`Self::Choice`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Distribution {
    /// Always `value` (declared, with its justification, rather than silently fixed).
    Fixed(f64),
    /// Uniform on `[low, high]`.
    Uniform {
        /// Lower bound.
        low: f64,
        /// Upper bound.
        high: f64,
    },
    /// Log-uniform on `[low, high]` (both > 0).
    LogUniform {
        /// Lower bound.
        low: f64,
        /// Upper bound.
        high: f64,
    },
    /// Normal with `mean` and standard deviation `sd`.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation (>= 0).
        sd: f64,
    },
    /// One of `labels` with probabilities proportional to `weights`; the drawn value is the
    /// index of the label.
    Choice {
        /// The labels (e.g. "ramp", "stable").
        labels: Vec<String>,
        /// Relative weights (>= 0, not all zero).
        weights: Vec<f64>,
    },
}

impl Distribution {
    /// Checks bounds and weights; `name` is used in the error.
    pub fn validate(&self, name: &str) -> Result<(), UqError> {
        let bad = |message: String| {
            Err(UqError::Assumption {
                name: name.to_string(),
                message,
            })
        };
        match self {
            Distribution::Fixed(v) if !v.is_finite() => bad(format!("fixed value {v} not finite")),
            Distribution::Uniform { low, high }
                if !(low.is_finite() && high.is_finite() && low <= high) =>
            {
                bad(format!(
                    "uniform needs finite low <= high, got [{low}, {high}]"
                ))
            }
            Distribution::LogUniform { low, high }
                if !(*low > 0.0 && high.is_finite() && low <= high) =>
            {
                bad(format!(
                    "log_uniform needs 0 < low <= high, got [{low}, {high}]"
                ))
            }
            Distribution::Normal { mean, sd }
                if !(mean.is_finite() && sd.is_finite() && *sd >= 0.0) =>
            {
                bad(format!(
                    "normal needs a finite mean and sd >= 0, got {mean}, {sd}"
                ))
            }
            Distribution::Choice { labels, weights } => {
                if labels.is_empty() || labels.len() != weights.len() {
                    return bad("choice needs as many weights as labels (at least one)".into());
                }
                if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0))
                    || weights.iter().sum::<f64>() <= 0.0
                {
                    return bad("choice weights must be >= 0 and not all zero".into());
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// The value at probability `u` in (0, 1) (inverse CDF; `z` is a standard normal deviate
    /// used by [`Self::Normal`]).
    pub fn value_at(&self, u: f64, z: f64) -> f64 {
        match self {
            Distribution::Fixed(v) => *v,
            Distribution::Uniform { low, high } => low + (high - low) * u,
            Distribution::LogUniform { low, high } => (low.ln() + (high.ln() - low.ln()) * u).exp(),
            Distribution::Normal { mean, sd } => mean + sd * z,
            Distribution::Choice { weights, .. } => {
                let total: f64 = weights.iter().sum();
                let mut acc = 0.0;
                for (i, w) in weights.iter().enumerate() {
                    acc += w / total;
                    if u < acc {
                        return i as f64;
                    }
                }
                (weights.len() - 1) as f64
            }
        }
    }

    /// True when the value varies between draws (not fixed, not a one-label choice, not a
    /// zero-width range).
    pub fn varies(&self) -> bool {
        match self {
            Distribution::Fixed(_) => false,
            Distribution::Uniform { low, high } | Distribution::LogUniform { low, high } => {
                high > low
            }
            Distribution::Normal { sd, .. } => *sd > 0.0,
            Distribution::Choice { weights, .. } => {
                weights.iter().filter(|w| **w > 0.0).count() > 1
            }
        }
    }

    /// The choice labels, for [`Self::Choice`].
    pub fn labels(&self) -> Option<&[String]> {
        match self {
            Distribution::Choice { labels, .. } => Some(labels),
            _ => None,
        }
    }
}

/// The thermal condition of the 30-state calibration run (choice labels of
/// [`Knob::Cal30Chamber`]).
pub const CAL30_LABELS: [&str; 2] = ["ramp", "stable"];
/// Mounting of the IMU on the turntable in the navigation runs (choice labels of
/// [`Knob::NavMounting`]): which body axis points up.
pub const MOUNTING_LABELS: [&str; 3] = ["z_up", "y_up", "x_up"];

/// What an assumption sets in the replica.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Knob {
    /// Thermal condition of the 30-state calibration: 0 = the 42-state run itself (chamber ramp),
    /// 1 = a separate run at a stable chamber temperature.
    Cal30Chamber,
    /// Chamber temperature of a stable 30-state calibration (degC).
    Cal30StableTemperatureDegc,
    /// Factor on every accelerometer's thermal time constant (calibration and navigation).
    AccelTimeConstantScale,
    /// Factor on every accelerometer's steady offset from the chamber.
    AccelOffsetScale,
    /// Sustained chamber drop over each navigation run (degC, positive for cooling): the trend
    /// rates of every navigation run are scaled to give it.
    NavTemperatureDropDegc,
    /// Factor on the navigation runs' fluctuation amplitudes.
    NavFluctuationAmplitudeScale,
    /// Factor on the navigation runs' fluctuation periods.
    NavFluctuationPeriodScale,
    /// Shift of the navigation runs' chamber temperatures (degC).
    NavTemperatureShiftDegc,
    /// Which body axis points up in the navigation runs (choice of [`MOUNTING_LABELS`]).
    NavMounting,
    /// Heading of the table at the start of the navigation runs, added to the file's (rad).
    NavYawOffsetRad,
    /// Phase of each sinusoid of the vibration patterns (rad): one independent draw per pattern
    /// and axis from this distribution.
    VibrationPhaseRad,
    /// A coefficient of the truth IMU, by index in the state order of eq (8) (SI).
    TruthCoefficient(usize),
    /// Gyro angle random walk (rad/sqrt(s)).
    GyroArw,
    /// Gyro Gauss-Markov bias instability (rad/s).
    GyroBiasInstability,
    /// Gyro output quantum (rad).
    GyroQuantum,
    /// Accelerometer velocity random walk (m/s/sqrt(s)).
    AccelVrw,
    /// Accelerometer Gauss-Markov bias instability (m/s^2).
    AccelBiasInstability,
    /// Correlation time of both Gauss-Markov biases (s).
    BiasCorrelationS,
    /// Thermometer white noise (degC).
    ThermometerNoiseDegc,
}

impl Knob {
    /// The choice labels this knob expects, when it is a choice.
    pub fn choice_labels(self) -> Option<&'static [&'static str]> {
        match self {
            Knob::Cal30Chamber => Some(&CAL30_LABELS),
            Knob::NavMounting => Some(&MOUNTING_LABELS),
            _ => None,
        }
    }

    /// True when each draw of this knob is independent per pattern and axis (not one value a
    /// sample): such values get no sensitivity index of their own (they stay in the residual).
    pub fn is_per_element(self) -> bool {
        matches!(self, Knob::VibrationPhaseRad)
    }
}

/// One declared assumption.
#[derive(Clone, Debug, PartialEq)]
pub struct Assumption {
    /// Unique name (the key in the assumptions file).
    pub name: String,
    /// What it sets.
    pub knob: Knob,
    /// Its distribution in SI (or choice indices).
    pub distribution: Distribution,
    /// Group for grouped sensitivity indices (e.g. "truth temperature coefficients").
    pub group: String,
    /// The unit the file and reports use.
    pub unit: String,
    /// SI value of one such unit.
    pub unit_si: f64,
    /// Why this distribution (quote of the paper's section or a literature source).
    pub justification: String,
}

/// An extra effect a candidate adds to the IMU (calibration and navigation runs alike).
#[derive(Clone, Debug, PartialEq)]
pub struct CandidateEffect {
    /// The effect kind (catalogue of `sins-imu`).
    pub kind: EffectKind,
    /// Magnitude of every component in SI (each component drawn independently).
    pub magnitude: Distribution,
    /// Give each component a random sign.
    pub random_sign: bool,
}

/// A candidate explanation of the replica-vs-paper gap: overrides of assumptions and extra
/// effects, each at a physically plausible size.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// Unique name.
    pub name: String,
    /// Why it is a candidate (quote or source).
    pub justification: String,
    /// Assumptions given another distribution: (index into the assumption list, distribution).
    pub overrides: Vec<(usize, Distribution)>,
    /// Extra effects.
    pub effects: Vec<CandidateEffect>,
    /// Monte Carlo samples of this candidate.
    pub samples: usize,
}

/// Everything a UQ study needs besides the base replica.
#[derive(Clone, Debug, PartialEq)]
pub struct AssumptionSet {
    /// The assumptions, in file order (the draw order).
    pub assumptions: Vec<Assumption>,
    /// The candidates, in file order; the first one is the baseline of the shrinkage (the
    /// replica as built).
    pub candidates: Vec<Candidate>,
    /// Main Monte Carlo samples (over all assumptions).
    pub samples: usize,
    /// Rows of the pick-freeze design for grouped first-order and total Sobol indices
    /// ([`crate::sobol`]; 0: none). Rows reuse the first main samples, so at most `samples`.
    pub pick_freeze_samples: usize,
    /// Master seed.
    pub seed: u64,
    /// Cells the gap diagnosis chooses on (the rest are withheld).
    pub choose_on: Vec<crate::cell::CellId>,
}

impl AssumptionSet {
    /// Checks every distribution, choice labels against their knobs, unique names, candidate
    /// overrides and sample counts.
    pub fn validate(&self) -> Result<(), UqError> {
        let err = |name: &str, message: String| UqError::Assumption {
            name: name.to_string(),
            message,
        };
        for (i, a) in self.assumptions.iter().enumerate() {
            a.distribution.validate(&a.name)?;
            check_choice(a.knob, &a.distribution, &a.name)?;
            if self.assumptions[..i].iter().any(|b| b.name == a.name) {
                return Err(err(&a.name, "declared twice".into()));
            }
            if self.assumptions[..i].iter().any(|b| b.knob == a.knob) {
                return Err(err(
                    &a.name,
                    "sets the same input as an earlier assumption".into(),
                ));
            }
        }
        for c in &self.candidates {
            for (idx, d) in &c.overrides {
                let a = self
                    .assumptions
                    .get(*idx)
                    .ok_or_else(|| err(&c.name, format!("override of unknown assumption {idx}")))?;
                d.validate(&format!("{} (candidate {})", a.name, c.name))?;
                check_choice(a.knob, d, &a.name)?;
            }
            for e in &c.effects {
                e.magnitude
                    .validate(&format!("{} effect {}", c.name, e.kind.name()))?;
            }
            if c.samples < 2 {
                return Err(err(
                    &c.name,
                    format!("needs at least 2 samples, got {}", c.samples),
                ));
            }
        }
        if self.samples < 4 {
            return Err(err(
                "samples",
                format!("needs at least 4 samples, got {}", self.samples),
            ));
        }
        if self.pick_freeze_samples > self.samples || self.pick_freeze_samples == 1 {
            return Err(err(
                "pick_freeze_samples",
                format!(
                    "must be 0 or 2..={} (the main samples it reuses), got {}",
                    self.samples, self.pick_freeze_samples
                ),
            ));
        }
        if self.candidates.is_empty() {
            return Err(err(
                "candidate",
                "at least one candidate (the replica as built) is needed".into(),
            ));
        }
        Ok(())
    }

    /// The index of the assumption named `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.assumptions.iter().position(|a| a.name == name)
    }
}

fn check_choice(knob: Knob, d: &Distribution, name: &str) -> Result<(), UqError> {
    let expected = knob.choice_labels();
    let ok = match (expected, d) {
        (Some(exp), Distribution::Choice { labels, .. }) => {
            labels.len() == exp.len() && labels.iter().zip(exp).all(|(a, b)| a == b)
        }
        (Some(_), Distribution::Fixed(v)) => v.fract() == 0.0 && *v >= 0.0,
        (Some(_), _) => false,
        (None, Distribution::Choice { .. }) => false,
        (None, _) => true,
    };
    if ok {
        Ok(())
    } else {
        Err(UqError::Assumption {
            name: name.to_string(),
            message: match expected {
                Some(exp) => format!("must be a choice of exactly {exp:?} in that order"),
                None => "is numeric: a choice is not allowed".into(),
            },
        })
    }
}
