//! Deterministic draws: sample `i` of candidate slot `c` always gets ChaCha8 stream `(c, i)` of
//! the master seed, so a sample's values do not depend on the thread count, on sharding or on the
//! order in which samples run.

use crate::assumptions::{AssumptionSet, Distribution, Knob};
use rand_chacha::ChaCha8Rng;
use rand_core::{Rng, SeedableRng};
use sins_imu::EffectSpec;

/// Which study a sample belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Slot {
    /// The main Monte Carlo over every assumption.
    Main,
    /// Candidate number `c` (file order) of the gap diagnosis.
    Candidate(usize),
    /// The pick-freeze design's second matrix B: independent draws of every assumption
    /// ([`crate::sobol`]).
    Resample,
}

impl Slot {
    fn stream_base(self) -> u64 {
        match self {
            Slot::Main => 0,
            Slot::Candidate(c) => (c as u64 + 1) << 32,
            Slot::Resample => 0xffff_ffff << 32,
        }
    }
}

/// A uniform and normal source on one ChaCha8 stream.
pub struct Stream {
    rng: ChaCha8Rng,
}

impl Stream {
    /// Stream `stream` of `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(stream);
        Self { rng }
    }

    /// Uniform in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        ((self.rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal (Box-Muller, cosine branch: two uniforms per deviate).
    pub fn normal(&mut self) -> f64 {
        let u1 = self.uniform();
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }

    /// A raw 64-bit value (seeds).
    pub fn next_u64(&mut self) -> u64 {
        self.rng.next_u64()
    }
}

/// The values of one sample.
#[derive(Clone, Debug, PartialEq)]
pub struct Draw {
    /// Study slot.
    pub slot: Slot,
    /// Sample index within the slot.
    pub index: usize,
    /// One value per assumption (SI, or a choice index); NaN for per-element knobs.
    pub values: Vec<f64>,
    /// Extra effects of the candidate, with drawn magnitudes.
    pub effects: Vec<EffectSpec>,
    /// Seed of the calibration run's noise.
    pub cal_seed: u64,
    /// Seed of the separate 30-state calibration run (stable chamber).
    pub cal30_seed: u64,
    /// Seed of each navigation run's noise (up to 16 runs).
    pub nav_seeds: Vec<u64>,
    /// Seed of the per-element draws (vibration phases).
    pub element_seed: u64,
}

/// Sample `index` of `slot`: each assumption drawn from its distribution (the candidate's
/// override where it has one), then the candidate's effects, then the seeds.
pub fn draw(set: &AssumptionSet, slot: Slot, index: usize) -> Draw {
    let mut s = Stream::new(set.seed, slot.stream_base() + index as u64);
    let candidate = match slot {
        Slot::Candidate(c) => set.candidates.get(c),
        Slot::Main | Slot::Resample => None,
    };
    let values = set
        .assumptions
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let d = candidate
                .and_then(|c| c.overrides.iter().find(|(j, _)| *j == i).map(|(_, d)| d))
                .unwrap_or(&a.distribution);
            let (u, z) = (s.uniform(), s.normal());
            if a.knob.is_per_element() {
                f64::NAN
            } else {
                d.value_at(u, z)
            }
        })
        .collect();
    let effects = candidate
        .map(|c| c.effects.iter().map(|e| draw_effect(e, &mut s)).collect())
        .unwrap_or_default();
    Draw {
        slot,
        index,
        values,
        effects,
        cal_seed: s.next_u64() >> 1,
        cal30_seed: s.next_u64() >> 1,
        nav_seeds: (0..16).map(|_| s.next_u64() >> 1).collect(),
        element_seed: s.next_u64(),
    }
}

fn draw_effect(e: &crate::assumptions::CandidateEffect, s: &mut Stream) -> EffectSpec {
    let zero = EffectSpec::zero(e.kind);
    let n = e.kind.n_components();
    let magnitudes: Vec<f64> = (0..n)
        .map(|_| {
            let (u, z, sign_u) = (s.uniform(), s.normal(), s.uniform());
            let m = e.magnitude.value_at(u, z);
            if e.random_sign && sign_u < 0.5 { -m } else { m }
        })
        .collect();
    zero.with_magnitudes_si(&magnitudes).unwrap_or(zero)
}

/// The value a knob takes in `draw`, if an assumption sets it.
pub fn knob_value(set: &AssumptionSet, draw: &Draw, knob: Knob) -> Option<f64> {
    set.assumptions
        .iter()
        .position(|a| a.knob == knob)
        .map(|i| draw.values[i])
}

/// The distribution of the per-element knob `knob` in `slot`, if declared.
pub fn element_distribution(set: &AssumptionSet, slot: Slot, knob: Knob) -> Option<&Distribution> {
    let i = set.assumptions.iter().position(|a| a.knob == knob)?;
    if let Slot::Candidate(c) = slot
        && let Some((_, d)) = set
            .candidates
            .get(c)?
            .overrides
            .iter()
            .find(|(j, _)| *j == i)
    {
        return Some(d);
    }
    Some(&set.assumptions[i].distribution)
}

/// The implicit group of the sensor-noise realisation (the seeds of every simulated run).
pub const NOISE_GROUP: &str = "noise realisation";

/// The groups of the design, in file order, then [`NOISE_GROUP`]: every group with at least
/// one varying assumption.
pub fn groups(set: &AssumptionSet) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for a in &set.assumptions {
        if a.distribution.varies() && !out.contains(&a.group) {
            out.push(a.group.clone());
        }
    }
    out.push(NOISE_GROUP.to_string());
    out
}

/// Row `index` of `A_B^g` for group number `group` of [`groups`]: main sample `index` with the
/// group's inputs (values, per-element draws or noise seeds) from resample `index`.
pub fn mixed_draw(set: &AssumptionSet, group: usize, index: usize) -> Draw {
    let mut a = draw(set, Slot::Main, index);
    let b = draw(set, Slot::Resample, index);
    let names = groups(set);
    let Some(name) = names.get(group) else {
        return a;
    };
    if name == NOISE_GROUP {
        a.cal_seed = b.cal_seed;
        a.cal30_seed = b.cal30_seed;
        a.nav_seeds = b.nav_seeds;
        return a;
    }
    for (i, asm) in set.assumptions.iter().enumerate() {
        if &asm.group == name {
            a.values[i] = b.values[i];
            if asm.knob.is_per_element() {
                a.element_seed = b.element_seed;
            }
        }
    }
    a
}
