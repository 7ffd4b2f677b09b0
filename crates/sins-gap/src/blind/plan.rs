//! Drawing the blind cases.

use rand_chacha::ChaCha8Rng;
use rand_core::{Rng, SeedableRng};
use serde::{Deserialize, Serialize};
use sins_imu::{EffectKind, EffectSpec};

/// The answer of one case (what the sealed manifest holds).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseAnswer {
    /// Case identifier (`case01` ...).
    pub case: String,
    /// Seed of the case's simulations (noise, chamber history as in the experiment files).
    pub seed: u64,
    /// The hidden effect, if any.
    pub hidden: Option<HiddenEffect>,
    /// The navigation experiment whose runs this case records, by its `name`, when it is not
    /// the suite's own (the "different histories" cases: [`SuiteShape::histories_experiment`]);
    /// `None`: the suite's navigation experiment.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub navigation_experiment: Option<String>,
}

/// Name of each case's calibration run among its datasets.
pub const CALIBRATION_RUN: &str = "cal";

/// The value of [`HiddenEffect::run`] for an effect in the calibration run only.
pub const CALIBRATION_SCOPE: &str = "calibration";

/// True for the name of the calibration run ([`CALIBRATION_RUN`] or [`CALIBRATION_SCOPE`]).
pub fn is_calibration_run(name: &str) -> bool {
    name == CALIBRATION_RUN || name == CALIBRATION_SCOPE
}

/// Where a time-local effect of the widened draw acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EventScope {
    /// One navigation run ([`HiddenEffect::run`] names it).
    OneRun,
    /// Every navigation run, at the same time on each run's axis (a common time course); not
    /// the calibration run.
    AllNavigationRuns,
    /// The calibration run only ([`HiddenEffect::run`] is [`CALIBRATION_SCOPE`]).
    CalibrationOnly,
}

impl EventScope {
    /// Short label for reports.
    pub fn label(self) -> &'static str {
        match self {
            EventScope::OneRun => "one run",
            EventScope::AllNavigationRuns => "every navigation run",
            EventScope::CalibrationOnly => "calibration only",
        }
    }
}

/// A hidden effect.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HiddenEffect {
    /// Effect kind name (`sins_imu::EffectKind::name`).
    pub kind: String,
    /// Whether the kind is in the diagnosis catalogue.
    pub in_catalogue: bool,
    /// The component carrying the magnitude (index into the kind's component labels).
    pub component: usize,
    /// Its label (`x`, `y`, `z`, `ax.y` ...).
    pub component_label: String,
    /// Magnitude in the kind's paper unit.
    pub magnitude: f64,
    /// That unit.
    pub unit: String,
    /// Magnitude over the kind's typical navigation-grade magnitude.
    pub times_typical: f64,
    /// Onset of a time-local effect (s on each run's time axis; 0: at turn-on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub onset_s: Option<f64>,
    /// Time constant of a transient (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_constant_s: Option<f64>,
    /// The one navigation run that carries a time-local effect, or [`CALIBRATION_SCOPE`] for
    /// the calibration run only (`None`: every run, the calibration run included, as an effect
    /// of turn-on is; with [`EventScope::AllNavigationRuns`] every navigation run only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<String>,
    /// Rise time of a ramp to a plateau, duration of a pulse, period of a decaying oscillation
    /// (s; the widened time-local draw).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// Where a time-local effect of the widened draw acts (`None`: the original draws, whose
    /// scope [`Self::run`] alone says).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scope: Option<EventScope>,
}

impl HiddenEffect {
    /// True when the hidden effect is local in time (a step, ramp or transient).
    pub fn is_time_local(&self) -> bool {
        EffectKind::from_name(&self.kind).is_some_and(|k| k.is_time_local())
    }

    /// The onset of a time-local effect (s): drawn, or the kind's default
    /// ([`sins_imu::effects::spec::DEFAULT_STEP_TIME_S`] for the original suite's accelerometer
    /// steps, which act in every run).
    pub fn onset_time_s(&self) -> f64 {
        self.onset_s
            .unwrap_or(sins_imu::effects::spec::DEFAULT_STEP_TIME_S)
    }

    /// True for a case drawn in the time-local section (not an original out-of-catalogue case).
    pub fn drawn_time_local(&self) -> bool {
        self.onset_s.is_some()
    }

    /// Whether the effect is injected into run `name` (the calibration run is `cal` or
    /// `calibration`; `all runs` is a time course on every navigation run).
    pub fn acts_on(&self, name: &str) -> bool {
        match self.run.as_deref() {
            Some(CALIBRATION_SCOPE) => is_calibration_run(name),
            Some(r) => r == name,
            None => {
                !(self.scope == Some(EventScope::AllNavigationRuns) && is_calibration_run(name))
            }
        }
    }

    /// True for a case of the widened time-local draw ([`SuiteShape::wide_time_local`]).
    pub fn drawn_wide(&self) -> bool {
        self.scope.is_some()
    }

    /// True when the effect acts in the calibration run only.
    pub fn calibration_only(&self) -> bool {
        self.run.as_deref() == Some(CALIBRATION_SCOPE)
    }
}

impl CaseAnswer {
    /// The effect as a forward-model term (SI), if any.
    pub fn spec(&self) -> Option<EffectSpec> {
        let h = self.hidden.as_ref()?;
        let kind = EffectKind::from_name(&h.kind)?;
        let mut spec = EffectSpec::unit(kind, h.component).scaled(kind.unit().to_si(h.magnitude));
        if let EffectSpec::GyroBiasRandomWalk { seed, .. }
        | EffectSpec::AccelBiasRandomWalk { seed, .. } = &mut spec
        {
            *seed = self.seed ^ 0x005e_ed0f_b11d;
        }
        if let EffectSpec::AccelBiasStep { time_s, .. } = &mut spec {
            *time_s = h.onset_s.unwrap_or(*time_s);
        }
        if let EffectSpec::BiasEvent {
            onset_s,
            time_constant_s,
            ..
        } = &mut spec
        {
            *onset_s = h.onset_s.unwrap_or(*onset_s);
            *time_constant_s = h.time_constant_s.unwrap_or(*time_constant_s);
        }
        if let EffectSpec::BiasProfile {
            onset_s,
            duration_s,
            time_constant_s,
            ..
        } = &mut spec
        {
            *onset_s = h.onset_s.unwrap_or(*onset_s);
            *duration_s = h.duration_s.unwrap_or(*duration_s);
            *time_constant_s = h.time_constant_s.unwrap_or(*time_constant_s);
        }
        Some(spec)
    }

    /// The section of the suite the case belongs to: `null`, `in-catalogue`,
    /// `out-of-catalogue`, `time-local`, `wide time-local` or `different histories`.
    pub fn section(&self) -> &'static str {
        match &self.hidden {
            None => "null",
            Some(_) if self.navigation_experiment.is_some() => "different histories",
            Some(h) if h.drawn_wide() => "wide time-local",
            Some(h) if h.drawn_time_local() => "time-local",
            Some(h) if h.in_catalogue => "in-catalogue",
            Some(_) => "out-of-catalogue",
        }
    }
}

/// How many cases of each sort.
#[derive(Clone, PartialEq, Serialize, Deserialize)]
pub struct SuiteShape {
    /// All cases.
    pub cases: usize,
    /// Cases without a hidden effect.
    pub null_cases: usize,
    /// Cases whose effect is outside the catalogue.
    pub out_of_catalogue: usize,
    /// Magnitudes are drawn log-uniformly between these multiples of the typical magnitude.
    pub times_typical: (f64, f64),
    /// The same for the effects outside the catalogue: large enough to leave a gap, since
    /// "which effect explains it" arises only when there is a gap (a 2× typical accelerometer
    /// bias step hides in the twin's noise and is rightly reported as no gap).
    #[serde(default = "default_outside_times_typical")]
    pub outside_times_typical: (f64, f64),
    /// Cases with an effect local in time (steps, ramps, transients), drawn after the others
    /// from a stream of their own, so that the first `cases` are those of a suite without them.
    #[serde(default)]
    pub time_local: usize,
    /// Their magnitudes, log-uniform between these multiples of the typical magnitude.
    #[serde(default = "default_time_local_times_typical")]
    pub time_local_times_typical: (f64, f64),
    /// The navigation runs a time-local effect may fall in (one of them at random).
    #[serde(default = "default_time_local_runs")]
    pub time_local_runs: Vec<String>,
    /// Onsets of steps, ramps and mid-run transients are drawn uniformly in this window (s).
    #[serde(default = "default_onset_window_s")]
    pub onset_window_s: (f64, f64),
    /// Cases of the widened time-local draw, after the `time_local` ones, from a stream of
    /// their own: shapes in turn (step, ramp, ramp to a plateau, pulse, transient, decaying
    /// oscillation), gyro or accelerometer, in one navigation run, in every navigation run at
    /// the same time, or in the calibration run only (see [`draw_cases`]).
    #[serde(default)]
    pub wide_time_local: usize,
    /// Onsets of the widened draw's events in the calibration run, uniform in this window (s;
    /// the calibration run lasts 4.2 h, its first 20 min are the alignment).
    #[serde(default = "default_calibration_onset_window_s")]
    pub calibration_onset_window_s: (f64, f64),
    /// Cases with an in-catalogue temperature-driven effect whose navigation runs have markedly
    /// different chamber histories ([`Self::histories_experiment`]), after the widened ones,
    /// from a stream of their own.
    #[serde(default)]
    pub different_histories: usize,
    /// The `name` of the navigation experiment of those cases (the file is the suite's
    /// configuration's: `SuiteConfig::histories_experiment`).
    #[serde(default = "default_histories_experiment")]
    pub histories_experiment: String,
}

impl std::fmt::Debug for SuiteShape {
    /// The fields of the original suites always; the widened draw's only when it draws cases
    /// (campaign fingerprints hold the shape's `Debug`: those planned before these fields
    /// existed keep theirs).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("SuiteShape");
        d.field("cases", &self.cases)
            .field("null_cases", &self.null_cases)
            .field("out_of_catalogue", &self.out_of_catalogue)
            .field("times_typical", &self.times_typical)
            .field("outside_times_typical", &self.outside_times_typical)
            .field("time_local", &self.time_local)
            .field("time_local_times_typical", &self.time_local_times_typical)
            .field("time_local_runs", &self.time_local_runs)
            .field("onset_window_s", &self.onset_window_s);
        if self.wide_time_local > 0 {
            d.field("wide_time_local", &self.wide_time_local).field(
                "calibration_onset_window_s",
                &self.calibration_onset_window_s,
            );
        }
        if self.different_histories > 0 {
            d.field("different_histories", &self.different_histories)
                .field("histories_experiment", &self.histories_experiment);
        }
        d.finish()
    }
}

fn default_calibration_onset_window_s() -> (f64, f64) {
    (1800.0, 9000.0)
}

fn default_histories_experiment() -> String {
    "navigation_varied_histories".into()
}

fn default_time_local_times_typical() -> (f64, f64) {
    (3.0, 30.0)
}

fn default_time_local_runs() -> Vec<String> {
    vec!["nav1".into(), "nav2".into()]
}

fn default_onset_window_s() -> (f64, f64) {
    (3600.0, 11.0 * 3600.0)
}

fn default_outside_times_typical() -> (f64, f64) {
    (10.0, 50.0)
}

impl Default for SuiteShape {
    /// 30 cases: 5 null, 3 out of the catalogue at 10-50 times typical, 22 from the
    /// catalogue at 2-20 times typical.
    fn default() -> Self {
        Self {
            cases: 30,
            null_cases: 5,
            out_of_catalogue: 3,
            times_typical: (2.0, 20.0),
            outside_times_typical: default_outside_times_typical(),
            time_local: 0,
            time_local_times_typical: default_time_local_times_typical(),
            time_local_runs: default_time_local_runs(),
            onset_window_s: default_onset_window_s(),
            wide_time_local: 0,
            calibration_onset_window_s: default_calibration_onset_window_s(),
            different_histories: 0,
            histories_experiment: default_histories_experiment(),
        }
    }
}

/// `x` rounded to `digits` significant digits.
fn round_sig(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let e = digits - 1 - x.abs().log10().floor() as i32;
    let f = 10f64.powi(e.abs());
    if e >= 0 {
        (x * f).round() / f
    } else {
        (x / f).round() * f
    }
}

/// Draw the cases of a suite from `suite_seed`: the in-catalogue kinds in turn (so that every
/// kind is covered), components and magnitudes at random, then the order shuffled.
pub fn draw_cases(shape: &SuiteShape, suite_seed: u64) -> Vec<CaseAnswer> {
    let mut rng = ChaCha8Rng::seed_from_u64(suite_seed);
    let mut uniform = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let catalogue = EffectKind::catalogue();
    // The suite's original out-of-catalogue kinds (a suite seed draws the same cases as before
    // the time-local kinds existed; those have a section of their own).
    let outside = [
        EffectKind::GyroBiasOscillation,
        EffectKind::AccelBiasStep,
        EffectKind::AccelCrossCoupling,
    ];
    let n_in = shape
        .cases
        .saturating_sub(shape.null_cases + shape.out_of_catalogue);
    let mut kinds: Vec<Option<EffectKind>> = vec![None; shape.null_cases];
    kinds.extend((0..n_in).map(|i| Some(catalogue[i % catalogue.len()])));
    kinds.extend((0..shape.out_of_catalogue).map(|i| Some(outside[i % outside.len()])));
    // Fisher-Yates with the same stream.
    for i in (1..kinds.len()).rev() {
        let j = ((uniform() * (i + 1) as f64) as usize).min(i);
        kinds.swap(i, j);
    }
    kinds
        .into_iter()
        .enumerate()
        .map(|(i, kind)| {
            let seed = suite_seed.wrapping_mul(1000).wrapping_add(i as u64 + 1);
            let hidden = kind.map(|k| {
                let component =
                    ((uniform() * k.n_components() as f64) as usize).min(k.n_components() - 1);
                let (lo, hi) = if k.in_catalogue() {
                    shape.times_typical
                } else {
                    shape.outside_times_typical
                };
                // Six significant digits: the manifests (JSON) then read back exactly.
                let times = round_sig(lo * (hi / lo).powf(uniform()), 6);
                let sign = if uniform() < 0.5 { -1.0 } else { 1.0 };
                // Random-walk intensities and time constants are positive.
                let sign = match k.linearity() {
                    sins_imu::Linearity::Linear => sign,
                    _ => 1.0,
                };
                HiddenEffect {
                    kind: k.name().to_string(),
                    in_catalogue: k.in_catalogue(),
                    component,
                    component_label: k.component_labels()[component].to_string(),
                    magnitude: round_sig(sign * times * k.typical_magnitude(), 6),
                    unit: k.unit().label.to_string(),
                    times_typical: times,
                    onset_s: None,
                    time_constant_s: None,
                    run: None,
                    duration_s: None,
                    scope: None,
                }
            });
            CaseAnswer {
                case: format!("case{:02}", i + 1),
                seed,
                hidden,
                navigation_experiment: None,
            }
        })
        .chain(draw_time_local(shape, suite_seed))
        .chain(draw_wide_time_local(shape, suite_seed))
        .chain(draw_different_histories(shape, suite_seed))
        .collect()
}

/// The time-local cases (numbered after the others): the six time-local kinds in turn,
/// channel, sign, size, onset and time constant at random. Steps, ramps and half the
/// transients act in one navigation run from an onset inside the window; the other transients
/// start at turn-on in every run.
fn draw_time_local(shape: &SuiteShape, suite_seed: u64) -> Vec<CaseAnswer> {
    let mut rng = ChaCha8Rng::seed_from_u64(suite_seed ^ 0x7133_10ca_1000);
    let mut uniform = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    // The six kinds of the original draw, explicitly: the kinds added since (plateaus, pulses,
    // decaying oscillations) have a draw of their own, so that a seed draws the same cases.
    let kinds = EffectKind::ORIGINAL_TIME_LOCAL;
    (0..shape.time_local)
        .map(|j| {
            let i = shape.cases + j;
            let k = kinds[j % kinds.len()];
            // The vertical accelerometer of the level IMU does not reach the horizontal error
            // (the vertical channel is not navigated): its events are not drawn, its detectable
            // level is reported instead.
            let axes = match k.sensor() {
                sins_imu::effects::Sensor::Gyro => 3.0,
                sins_imu::effects::Sensor::Accel => 2.0,
            };
            let component = ((uniform() * axes) as usize).min(2);
            let (lo, hi) = shape.time_local_times_typical;
            let times = round_sig(lo * (hi / lo).powf(uniform()), 6);
            let sign = if uniform() < 0.5 { -1.0 } else { 1.0 };
            let transient = matches!(
                k,
                EffectKind::GyroBiasTransient | EffectKind::AccelBiasTransient
            );
            let turn_on = transient && uniform() < 0.5;
            let (w0, w1) = shape.onset_window_s;
            let onset = if turn_on {
                0.0
            } else {
                round_sig(w0 + (w1 - w0) * uniform(), 6)
            };
            let tau = transient.then(|| round_sig(600.0 * 9f64.powf(uniform()), 4));
            let runs = &shape.time_local_runs;
            let run = (!turn_on && !runs.is_empty()).then(|| {
                runs[((uniform() * runs.len() as f64) as usize).min(runs.len() - 1)].clone()
            });
            CaseAnswer {
                case: format!("case{:02}", i + 1),
                seed: suite_seed.wrapping_mul(1000).wrapping_add(i as u64 + 1),
                hidden: Some(HiddenEffect {
                    kind: k.name().to_string(),
                    in_catalogue: false,
                    component,
                    component_label: k.component_labels()[component].to_string(),
                    magnitude: round_sig(sign * times * k.typical_magnitude(), 6),
                    unit: k.unit().label.to_string(),
                    times_typical: times,
                    onset_s: Some(onset),
                    time_constant_s: tau,
                    run,
                    duration_s: None,
                    scope: None,
                }),
                navigation_experiment: None,
            }
        })
        .collect()
}

/// The shapes of the widened time-local draw, in turn.
#[derive(Clone, Copy, Debug, PartialEq)]
enum WideShape {
    Step,
    Ramp,
    Plateau,
    Pulse,
    Transient,
    DecayingOscillation,
}

const WIDE_SHAPES: [WideShape; 6] = [
    WideShape::Step,
    WideShape::Ramp,
    WideShape::Plateau,
    WideShape::Pulse,
    WideShape::Transient,
    WideShape::DecayingOscillation,
];

/// Rise time of a ramp to a plateau: uniform in this range (h).
pub const WIDE_RISE_H: (f64, f64) = (0.5, 3.0);
/// Duration of a pulse: uniform in this range (h).
pub const WIDE_PULSE_H: (f64, f64) = (0.25, 2.0);
/// Period of a decaying oscillation: uniform in this range (h).
pub const WIDE_PERIOD_H: (f64, f64) = (1.0, 4.0);
/// Decay time constant of a decaying oscillation: uniform in this range (h).
pub const WIDE_DECAY_H: (f64, f64) = (1.0, 6.0);
/// Time constant of a transient: log-uniform in this range (s; as the original draw).
pub const WIDE_TRANSIENT_S: (f64, f64) = (600.0, 5400.0);

fn wide_kind(shape: WideShape, gyro: bool) -> EffectKind {
    use EffectKind as K;
    match (shape, gyro) {
        (WideShape::Step, true) => K::GyroBiasStep,
        (WideShape::Step, false) => K::AccelBiasStep,
        (WideShape::Ramp, true) => K::GyroBiasRamp,
        (WideShape::Ramp, false) => K::AccelBiasRamp,
        (WideShape::Plateau, true) => K::GyroBiasPlateau,
        (WideShape::Plateau, false) => K::AccelBiasPlateau,
        (WideShape::Pulse, true) => K::GyroBiasPulse,
        (WideShape::Pulse, false) => K::AccelBiasPulse,
        (WideShape::Transient, true) => K::GyroBiasTransient,
        (WideShape::Transient, false) => K::AccelBiasTransient,
        (WideShape::DecayingOscillation, true) => K::GyroBiasDecayingOscillation,
        (WideShape::DecayingOscillation, false) => K::AccelBiasDecayingOscillation,
    }
}

/// The widened time-local cases (numbered after the `time_local` ones), from a stream of their
/// own. Case `j` has the shape `j mod 6` (step, ramp, ramp to a plateau, pulse, transient,
/// decaying oscillation); with `v = j + ⌊j/6⌋`, the gyros when `v` is even (the accelerometers
/// otherwise) and the scope `v mod 3` (one navigation run, every navigation run at the same
/// time, the calibration run only): over 36 cases every shape meets every sensor and scope.
/// At random: the channel (gyro x, y, z; accelerometer x, y, as in the original draw), sign,
/// size (log-uniform in [`SuiteShape::time_local_times_typical`] times typical), onset
/// (uniform in [`SuiteShape::onset_window_s`] for the navigation runs,
/// [`SuiteShape::calibration_onset_window_s`] for the calibration run), the shape's times
/// ([`WIDE_RISE_H`], [`WIDE_PULSE_H`], [`WIDE_PERIOD_H`] with [`WIDE_DECAY_H`],
/// [`WIDE_TRANSIENT_S`]) and, for one run, which of [`SuiteShape::time_local_runs`].
fn draw_wide_time_local(shape: &SuiteShape, suite_seed: u64) -> Vec<CaseAnswer> {
    let mut rng = ChaCha8Rng::seed_from_u64(suite_seed ^ 0x0001_d0e7_10ca_1e00);
    let mut uniform = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let first = shape.cases + shape.time_local;
    (0..shape.wide_time_local)
        .map(|j| {
            let i = first + j;
            let v = j + j / 6;
            let form = WIDE_SHAPES[j % 6];
            let gyro = v % 2 == 0;
            let scope = [
                EventScope::OneRun,
                EventScope::AllNavigationRuns,
                EventScope::CalibrationOnly,
            ][v % 3];
            let k = wide_kind(form, gyro);
            let axes = if gyro { 3.0 } else { 2.0 };
            let component = ((uniform() * axes) as usize).min(2);
            let (lo, hi) = shape.time_local_times_typical;
            let times = round_sig(lo * (hi / lo).powf(uniform()), 6);
            let sign = if uniform() < 0.5 { -1.0 } else { 1.0 };
            let (w0, w1) = match scope {
                EventScope::CalibrationOnly => shape.calibration_onset_window_s,
                _ => shape.onset_window_s,
            };
            let onset = round_sig(w0 + (w1 - w0) * uniform(), 6);
            let hours = |(a, b): (f64, f64), u: f64| round_sig(3600.0 * (a + (b - a) * u), 4);
            let (duration, tau) = match form {
                WideShape::Step | WideShape::Ramp => (None, None),
                WideShape::Plateau => (Some(hours(WIDE_RISE_H, uniform())), None),
                WideShape::Pulse => (Some(hours(WIDE_PULSE_H, uniform())), None),
                WideShape::Transient => {
                    let (a, b) = WIDE_TRANSIENT_S;
                    (None, Some(round_sig(a * (b / a).powf(uniform()), 4)))
                }
                WideShape::DecayingOscillation => {
                    let period = hours(WIDE_PERIOD_H, uniform());
                    (Some(period), Some(hours(WIDE_DECAY_H, uniform())))
                }
            };
            let runs = &shape.time_local_runs;
            let run = match scope {
                EventScope::OneRun => (!runs.is_empty()).then(|| {
                    runs[((uniform() * runs.len() as f64) as usize).min(runs.len() - 1)].clone()
                }),
                EventScope::AllNavigationRuns => None,
                EventScope::CalibrationOnly => Some(CALIBRATION_SCOPE.to_string()),
            };
            CaseAnswer {
                case: format!("case{:02}", i + 1),
                seed: suite_seed.wrapping_mul(1000).wrapping_add(i as u64 + 1),
                hidden: Some(HiddenEffect {
                    kind: k.name().to_string(),
                    in_catalogue: false,
                    component,
                    component_label: k.component_labels()[component].to_string(),
                    magnitude: round_sig(sign * times * k.typical_magnitude(), 6),
                    unit: k.unit().label.to_string(),
                    times_typical: times,
                    onset_s: Some(onset),
                    time_constant_s: tau,
                    run,
                    duration_s: duration,
                    scope: Some(scope),
                }),
                navigation_experiment: None,
            }
        })
        .collect()
}

/// The temperature-driven kinds of the catalogue, in the order the "different histories"
/// cases take them.
pub const TEMPERATURE_DRIVEN: [EffectKind; 5] = [
    EffectKind::GyroBiasTemp,
    EffectKind::AccelBiasQuadraticTemp,
    EffectKind::GyroBiasTempRate,
    EffectKind::AccelBiasTempRate,
    EffectKind::ThermalLag,
];

/// The "different histories" cases (numbered after the widened ones), from a stream of their
/// own: the [`TEMPERATURE_DRIVEN`] kinds in turn, component, sign and size (log-uniform in
/// [`SuiteShape::times_typical`]) at random, recorded on the runs of
/// [`SuiteShape::histories_experiment`].
fn draw_different_histories(shape: &SuiteShape, suite_seed: u64) -> Vec<CaseAnswer> {
    let mut rng = ChaCha8Rng::seed_from_u64(suite_seed ^ 0xd1ff_4157_0e1e);
    let mut uniform = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let first = shape.cases + shape.time_local + shape.wide_time_local;
    (0..shape.different_histories)
        .map(|j| {
            let i = first + j;
            let k = TEMPERATURE_DRIVEN[j % TEMPERATURE_DRIVEN.len()];
            let n = k.n_components();
            let component = ((uniform() * n as f64) as usize).min(n - 1);
            let (lo, hi) = shape.times_typical;
            let times = round_sig(lo * (hi / lo).powf(uniform()), 6);
            let sign = if uniform() < 0.5 { -1.0 } else { 1.0 };
            let sign = if k.is_linear() { sign } else { 1.0 };
            CaseAnswer {
                case: format!("case{:02}", i + 1),
                seed: suite_seed.wrapping_mul(1000).wrapping_add(i as u64 + 1),
                hidden: Some(HiddenEffect {
                    kind: k.name().to_string(),
                    in_catalogue: true,
                    component,
                    component_label: k.component_labels()[component].to_string(),
                    magnitude: round_sig(sign * times * k.typical_magnitude(), 6),
                    unit: k.unit().label.to_string(),
                    times_typical: times,
                    onset_s: None,
                    time_constant_s: None,
                    run: None,
                    duration_s: None,
                    scope: None,
                }),
                navigation_experiment: Some(shape.histories_experiment.clone()),
            }
        })
        .collect()
}

#[cfg(test)]
#[path = "plan_tests.rs"]
mod tests;
