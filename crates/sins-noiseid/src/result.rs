//! What an identification returns: the twin's noise terms with their 1-sigma, the Allan curves
//! and the data used. SI throughout (rad, m/s, s).

use serde::{Deserialize, Serialize};
use sins_diag::noise::NoiseSpec;
use sins_diag::report::{Note, NoteKind};
use sins_nav::{DEG_PER_H, UG};
use sins_sim::NoiseModel;
use sins_sim::noise::GM_ALLAN_PEAK_RATIO;

/// The standard normal's one-sided 95 % quantile.
const ONE_SIDED_95_Z: f64 = 1.644_853_626_951_472_2;

/// A rate random walk counts as resolved (a finding, not noise the twin may absorb) only above
/// this many sigma: the one-sided 1e-3 point of a normal. At 95 % (1.645 sigma) one triad in
/// ten of a sensor without a walk came out "resolved" by chance (two triads per diagnosis), and
/// its twin then carried no slow noise at all: the gap of a 0.0005 deg/h Gauss-Markov bias
/// (a walk at 1.68 sigma over 10 h of still data) was then named as a catalogue effect.
pub const WALK_RESOLVED_Z: f64 = 3.090_232_306_167_813_6;

/// An identified quantity with its 1-sigma (same unit).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// The value (0 when the term did not fit above zero).
    pub value: f64,
    /// Its 1-sigma (infinite when not identified; 0 for an exact value and for a term that
    /// fitted to zero, whose [`Estimate::upper_95`] is then given).
    pub sigma: f64,
    /// One-sided 95 % upper bound when the value is 0 (the term fitted at or below zero).
    pub upper_95: Option<f64>,
}

impl Estimate {
    /// One-sided 95 % upper bound: the given one for a term fitted at zero, else
    /// `value + 1.645 σ`; `None` when the term was not fitted or its σ is unknown.
    pub fn upper_bound_95(&self) -> Option<f64> {
        match self.upper_95 {
            Some(u) => Some(u),
            None if self.sigma.is_finite() && (self.value > 0.0 || self.sigma > 0.0) => {
                Some(self.value + ONE_SIDED_95_Z * self.sigma)
            }
            None => None,
        }
    }

    /// Exactly zero (a term an older file does not hold).
    pub fn zero() -> Self {
        Self::exact(0.0)
    }

    /// A value known exactly.
    pub fn exact(value: f64) -> Self {
        Self {
            value,
            sigma: 0.0,
            upper_95: None,
        }
    }
}

/// The noise terms of one sensor (one axis, or a triad pooled over its three axes). Units:
/// gyro in rad and rad/s, accelerometer in m/s and m/s².
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensorNoise {
    /// White rate noise density: gyro angle random walk (rad/√s), accelerometer velocity random
    /// walk (m/s/√s).
    pub white_per_sqrt_s: Estimate,
    /// Output quantum (rad for a gyro, m/s for an accelerometer): from the lattice of the
    /// increments when they are quantised (exact), else, for a gyro, from the `3Q²/τ²` term
    /// (`q = √12 Q`); 0 for an accelerometer off any lattice.
    pub quantum: Estimate,
    /// Whether the quantum was read off the increments' lattice.
    pub quantum_from_lattice: bool,
    /// The free `3Q²/τ²` Allan term as an equivalent quantum `√12 Q` (rad, m/s): white angle
    /// or velocity noise such as a vehicle's vibration or a dither in the still stretches. For a
    /// gyro on a lattice, what the data hold beyond its quantization (the ramp model's offset);
    /// for an accelerometer, all of it, its quantization included (a pulse-counting one carries
    /// the remainder and one that rounds each sample does not, so no offset is assumed); 0 for
    /// a gyro off any lattice, whose free term is its `quantum`. Bounded (it does not
    /// accumulate), so not part of the twin.
    #[serde(default = "Estimate::zero")]
    pub white_phase: Estimate,
    /// Gauss-Markov bias: stationary standard deviation (rad/s, m/s²).
    pub bias_sigma: Estimate,
    /// The same as an Allan bias-instability figure (the peak of its Allan deviation,
    /// 0.6174 σ; the experiment file's unit).
    pub bias_instability: Estimate,
    /// Gauss-Markov correlation time (s; infinite when the bias is zero).
    pub bias_correlation_s: Estimate,
    /// Rate random walk (rad/s/√s, m/s²/√s); not part of the twin, reported only.
    pub rate_random_walk_per_sqrt_s: Estimate,
    /// Weighted residual sum of squares of the fit.
    pub chi2: f64,
    /// Allan-variance points fitted.
    pub points: usize,
    /// Free parameters fitted (the correlation time included).
    pub parameters: usize,
}

/// One channel's Allan deviation for plotting (rate units: rad/s, m/s²).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AllanCurve {
    /// `gyro_x` … `accel_z`.
    pub channel: String,
    /// Averaging times (s).
    pub tau_s: Vec<f64>,
    /// Overlapping Allan deviation, pooled over stretches and runs.
    pub adev: Vec<f64>,
    /// Lower end of its chi-square interval (coverage of the configuration).
    pub lo: Vec<f64>,
    /// Upper end.
    pub hi: Vec<f64>,
    /// Equivalent degrees of freedom of each point.
    pub edf: Vec<f64>,
    /// The axis' own fitted model.
    pub fit_axis: Vec<f64>,
    /// The triad's pooled model at this axis (its quantization offset included).
    pub fit_triad: Vec<f64>,
}

/// How much stationary data a run gave.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunUsage {
    /// Run name.
    pub name: String,
    /// Stationary time used (s).
    pub stationary_s: f64,
    /// Stretches used.
    pub stretches: usize,
    /// Stretches too short to use.
    pub skipped: usize,
}

/// A stationary stretch: its mean rates against the Earth rate and gravity at the site in the
/// stretch's own TRIAD attitude (their difference is the observable part of the turn-on bias:
/// the component of the accelerometer mean along gravity, and the gyro mean's vertical and
/// north components; the level accelerometer and east gyro components are zero by
/// construction of the alignment).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StretchReport {
    /// Run name.
    pub run: String,
    /// Start (s, the run's time).
    pub start_s: f64,
    /// Length (s).
    pub duration_s: f64,
    /// Mean gyro rate minus the Earth rate in body axes (rad/s); `None` if the TRIAD failed.
    pub gyro_residual_radps: Option<[f64; 3]>,
    /// Mean specific force minus `−g` in body axes (m/s²).
    pub accel_residual_mps2: Option<[f64; 3]>,
    /// Changes of a bias found inside the stretch and left out of the Allan sums.
    #[serde(default)]
    pub changes: Vec<ChangeReport>,
}

/// A change of one channel's bias found inside a stationary stretch ([`crate::steps`]): not
/// noise, so the data around it are left out of the Allan sums; the navigation data still
/// carry it, for the diagnosis to find.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChangeReport {
    /// `gyro_x` … `accel_z`.
    pub channel: String,
    /// When (s, the run's time), to within half of `left_out_s`.
    pub at_s: f64,
    /// Length of the data left out around it (s).
    pub left_out_s: f64,
    /// Rate after minus rate before (rad/s for a gyro, m/s² for an accelerometer).
    pub size: f64,
    /// The change against the robust scale of the stretch's window differences.
    pub z: f64,
}

/// The identified noise of the IMU.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IdentifiedNoise {
    /// Gyro triad, pooled over the three axes (the twin's isotropic model).
    pub gyro: SensorNoise,
    /// Accelerometer triad, pooled.
    pub accel: SensorNoise,
    /// Gyro x, y, z fitted alone.
    pub gyro_axes: Vec<SensorNoise>,
    /// Accelerometer x, y, z fitted alone.
    pub accel_axes: Vec<SensorNoise>,
    /// Allan deviations of the six channels.
    pub curves: Vec<AllanCurve>,
    /// Data used per run.
    pub runs: Vec<RunUsage>,
    /// The stretches used.
    pub stretches: Vec<StretchReport>,
    /// Motion found inside the searched data (labelled still stretches, or whole unlabelled
    /// runs) and left out.
    #[serde(default)]
    pub motion: Vec<MotionReport>,
    /// Why the identified model is inconsistent with the data it came from (empty when it is
    /// consistent): a lattice that holds for only part of the data, a fit that does not
    /// reproduce the Allan curve. A diagnosis with such a twin says its noise cannot be trusted.
    #[serde(default)]
    pub inconsistent: Vec<String>,
    /// Sample interval of the data (s).
    pub sample_interval_s: f64,
    /// Time left out at the start of every run for a turn-on transient (s; 0 when none was
    /// found or the leaving out is off).
    #[serde(default)]
    pub turn_on_left_out_s: f64,
    /// Remarks (e.g. a term not identified).
    pub notes: Vec<String>,
}

impl IdentifiedNoise {
    /// One note per stretch of motion found and left out.
    pub fn motion_notes(&self) -> Vec<String> {
        self.motion.iter().map(motion_text).collect()
    }

    /// Whether the identified model is consistent with the data it came from.
    pub fn consistent(&self) -> bool {
        self.inconsistent.is_empty()
    }

    /// The twin's noise model (the rate random walk, which the twin lacks, is left out).
    pub fn to_noise_model(&self) -> NoiseModel {
        let corr = |s: &SensorNoise| {
            if s.bias_sigma.value > 0.0 {
                s.bias_correlation_s.value
            } else {
                f64::INFINITY
            }
        };
        NoiseModel {
            gyro_arw_rad_per_sqrt_s: self.gyro.white_per_sqrt_s.value,
            gyro_bias_instability_radps: self.gyro.bias_sigma.value,
            gyro_bias_correlation_s: corr(&self.gyro),
            gyro_quantum_rad: self.gyro.quantum.value,
            accel_vrw_mps_per_sqrt_s: self.accel.white_per_sqrt_s.value,
            accel_bias_instability_mps2: self.accel.bias_sigma.value,
            accel_bias_correlation_s: corr(&self.accel),
        }
    }

    /// The diagnosis's noise specification (quantization factor at its default,
    /// [`sins_diag::noise::DEFAULT_QUANTUM_FACTOR`]),
    /// with the 95 % upper bounds of the rate random walks as the walks the identification
    /// could not exclude ([`NoiseSpec::unresolved_walk_per_sqrt_s`]; none when the rate random
    /// walk was not fitted). A triad whose walk the identification resolved (above zero by
    /// [`WALK_RESOLVED_Z`] sigma) gets 0: that walk is a finding the diagnosis reports, not noise
    /// its twin absorbs.
    pub fn to_noise_spec(&self) -> NoiseSpec {
        let bounds = [&self.gyro, &self.accel].map(|s| {
            let k = s.rate_random_walk_per_sqrt_s;
            if k.value > WALK_RESOLVED_Z * k.sigma {
                Some(0.0)
            } else {
                k.upper_bound_95()
            }
        });
        NoiseSpec {
            unresolved_walk_per_sqrt_s: match bounds {
                [Some(g), Some(a)] => Some([g, a]),
                _ => None,
            },
            ..NoiseSpec::from(&self.to_noise_model())
        }
    }

    /// The note on a turn-on transient left out of the identification, for the notes of a
    /// diagnosis that uses it (`None` when nothing was left out; [`crate::identify_noise`]
    /// puts it first in [`IdentifiedNoise::notes`]).
    pub fn turn_on_note(&self) -> Option<String> {
        self.notes
            .first()
            .filter(|_| self.turn_on_left_out_s > 0.0)
            .cloned()
    }

    /// One line per change of a bias found inside a stationary stretch (paper units), for the
    /// notes of the identification and of a diagnosis that uses it.
    pub fn change_notes(&self) -> Vec<String> {
        self.change_findings().into_iter().map(|n| n.text).collect()
    }

    /// The changes of [`IdentifiedNoise::change_notes`] as typed notes: the run, the channel,
    /// and the figures `size` (deg/h or ug), `at_s`, `z` and `left_out_s`.
    fn change_findings(&self) -> Vec<Note> {
        let mut out = Vec::new();
        for s in &self.stretches {
            for c in &s.changes {
                let (unit, per) = if c.channel.starts_with("gyro") {
                    ("deg/h", DEG_PER_H)
                } else {
                    ("ug", UG)
                };
                let text = format!(
                    "{}: the bias changes by {:.4} {unit} at {:.0} s of run {} (z = {:.1}) inside a stationary stretch; the {:.0} s around it are left out of the noise identification (a change is not noise: the diagnosis sees it in the navigation data)",
                    c.channel,
                    c.size / per,
                    c.at_s,
                    s.run,
                    c.z,
                    c.left_out_s
                );
                out.push(
                    Note::new(NoteKind::NoiseIdentification, text)
                        .run(s.run.as_str())
                        .subject(c.channel.as_str())
                        .figure("size", c.size / per)
                        .figure("at_s", c.at_s)
                        .figure("z", c.z)
                        .figure("left_out_s", c.left_out_s),
                );
            }
        }
        out
    }

    /// What a diagnosis that uses this identification reports of it, typed at the source
    /// (kind `noise_identification`): the turn-on left out (figure `left_out_s`), every bias
    /// change inside a stationary stretch (run, channel, `size` in deg/h or ug, `at_s`, `z`,
    /// `left_out_s`) and every stretch of motion left out (run, channel, `start_s`, `end_s`).
    pub fn diagnosis_notes(&self) -> Vec<Note> {
        let mut out: Vec<Note> = self
            .turn_on_note()
            .map(|t| {
                Note::new(NoteKind::NoiseIdentification, t)
                    .figure("left_out_s", self.turn_on_left_out_s)
            })
            .into_iter()
            .collect();
        out.extend(self.change_findings());
        out.extend(self.motion.iter().map(|m| {
            Note::new(NoteKind::NoiseIdentification, motion_text(m))
                .run(m.run.as_str())
                .subject(m.channel.as_str())
                .figure("start_s", m.start_s)
                .figure("end_s", m.end_s)
        }));
        out
    }

    /// Total stationary time used over all runs (s).
    pub fn stationary_s(&self) -> f64 {
        self.runs.iter().map(|r| r.stationary_s).sum()
    }
}

/// The line on a stretch of motion left out.
fn motion_text(m: &MotionReport) -> String {
    format!(
        "noise identification: motion in {} at {:.1}-{:.1} s ({}), left out",
        m.run, m.start_s, m.end_s, m.channel
    )
}

/// Bias-instability figure (Allan peak) of a Gauss-Markov σ.
pub(crate) fn instability_of(sigma: Estimate) -> Estimate {
    Estimate {
        value: sigma.value * GM_ALLAN_PEAK_RATIO,
        sigma: sigma.sigma * GM_ALLAN_PEAK_RATIO,
        upper_95: sigma.upper_95.map(|u| u * GM_ALLAN_PEAK_RATIO),
    }
}

/// A stretch of motion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotionReport {
    /// Run name.
    pub run: String,
    /// Start (s).
    pub start_s: f64,
    /// End (s).
    pub end_s: f64,
    /// The channel that moved most (`gyro_x` … `accel_z`).
    pub channel: String,
    /// How far that channel's rate left its still level: the largest offset of a window mean
    /// from the median still mean (rad/s or m/s²): a rotation or an acceleration.
    pub size: f64,
    /// The largest RMS scatter of that channel within a window beyond its white noise (rad/s
    /// or m/s²): vibration, a shock.
    #[serde(default)]
    pub vibration: f64,
    /// The largest excursion the offsets add up to over the stretch: the angle (rad) or the
    /// velocity (m/s) the IMU moved through. A rocking vehicle goes back and forth (small);
    /// a turn or a drive-off does not.
    #[serde(default)]
    pub excursion: f64,
    /// Largest detector statistic in the stretch over its threshold (≥ 1).
    pub excess: f64,
}
