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
    /// The one navigation run that carries a time-local effect (`None`: every run, the
    /// calibration run included, as an effect of turn-on is).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<String>,
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

    /// Whether the effect is injected into run `name` (`calibration`: the calibration run).
    pub fn acts_on(&self, name: &str) -> bool {
        self.run.as_deref().is_none_or(|r| r == name)
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
        Some(spec)
    }
}

/// How many cases of each sort.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
                }
            });
            CaseAnswer {
                case: format!("case{:02}", i + 1),
                seed,
                hidden,
            }
        })
        .chain(draw_time_local(shape, suite_seed))
        .collect()
}

/// The time-local cases (numbered after the others): the six time-local kinds in turn,
/// channel, sign, size, onset and time constant at random. Steps, ramps and half the
/// transients act in one navigation run from an onset inside the window; the other transients
/// start at turn-on in every run.
fn draw_time_local(shape: &SuiteShape, suite_seed: u64) -> Vec<CaseAnswer> {
    let mut rng = ChaCha8Rng::seed_from_u64(suite_seed ^ 0x7133_10ca_1000);
    let mut uniform = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let kinds: Vec<EffectKind> = EffectKind::ALL
        .into_iter()
        .filter(|k| k.is_time_local())
        .collect();
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
                }),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suite_has_the_requested_shape_and_is_reproducible() {
        let shape = SuiteShape::default();
        let a = draw_cases(&shape, 7);
        assert_eq!(a, draw_cases(&shape, 7));
        assert_ne!(a, draw_cases(&shape, 8));
        assert_eq!(a.len(), 30);
        assert_eq!(a.iter().filter(|c| c.hidden.is_none()).count(), 5);
        let outside = a
            .iter()
            .filter(|c| c.hidden.as_ref().is_some_and(|h| !h.in_catalogue))
            .count();
        assert_eq!(outside, 3);
        // every catalogue kind appears
        for k in EffectKind::catalogue() {
            assert!(
                a.iter()
                    .any(|c| c.hidden.as_ref().is_some_and(|h| h.kind == k.name())),
                "{k}"
            );
        }
        for c in &a {
            if let Some(h) = &c.hidden {
                let range = if h.in_catalogue {
                    1.99..=20.01
                } else {
                    9.99..=50.01
                };
                assert!(range.contains(&h.times_typical), "{h:?}");
                let spec = c.spec().unwrap();
                let m = spec.magnitudes_si();
                let kind = EffectKind::from_name(&h.kind).unwrap();
                assert!(
                    (m[h.component] - kind.unit().to_si(h.magnitude)).abs()
                        <= 1e-12 * m[h.component].abs()
                );
            }
        }
    }

    #[test]
    fn time_local_cases_follow_the_original_draw_and_cover_every_time_local_kind() {
        let base = SuiteShape::default();
        let shape = SuiteShape {
            time_local: 12,
            ..base.clone()
        };
        let with = draw_cases(&shape, 5);
        let without = draw_cases(&base, 5);
        // The first cases are those of the suite without time-local cases.
        assert_eq!(&with[..30], &without[..]);
        assert_eq!(with.len(), 42);
        assert_eq!(with, draw_cases(&shape, 5));
        let tl: Vec<&HiddenEffect> = with[30..]
            .iter()
            .filter_map(|c| c.hidden.as_ref())
            .collect();
        assert_eq!(tl.len(), 12);
        for k in EffectKind::ALL.into_iter().filter(|k| k.is_time_local()) {
            assert!(tl.iter().any(|h| h.kind == k.name()), "{k}");
        }
        for (c, h) in with[30..].iter().zip(&tl) {
            assert!(h.is_time_local() && h.drawn_time_local() && !h.in_catalogue);
            let kind = EffectKind::from_name(&h.kind).unwrap();
            if kind.sensor() == sins_imu::effects::Sensor::Accel {
                assert!(h.component < 2, "{h:?}");
            }
            let onset = h.onset_time_s();
            // Turn-on transients act in every run; the others in one navigation run, inside
            // the onset window.
            match &h.run {
                None => assert_eq!(onset, 0.0, "{h:?}"),
                Some(r) => {
                    assert!(shape.time_local_runs.contains(r));
                    assert!((3600.0..=11.0 * 3600.0).contains(&onset), "{h:?}");
                }
            }
            // The spec carries the onset and the magnitude.
            let spec = c.spec().unwrap();
            let m = spec.magnitudes_si();
            assert!(
                (m[h.component] - kind.unit().to_si(h.magnitude)).abs()
                    <= 1e-12 * m[h.component].abs()
            );
            if let EffectSpec::BiasEvent {
                onset_s,
                time_constant_s,
                ..
            } = spec
            {
                assert_eq!(onset_s, onset);
                if let Some(t) = h.time_constant_s {
                    assert_eq!(time_constant_s, t);
                }
            }
        }
    }
}
