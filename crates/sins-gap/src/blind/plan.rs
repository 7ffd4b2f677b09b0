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
        Some(spec)
    }
}

/// How many cases of each sort.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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
    let outside: Vec<EffectKind> = EffectKind::ALL
        .into_iter()
        .filter(|k| !k.in_catalogue())
        .collect();
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
                }
            });
            CaseAnswer {
                case: format!("case{:02}", i + 1),
                seed,
                hidden,
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
}
