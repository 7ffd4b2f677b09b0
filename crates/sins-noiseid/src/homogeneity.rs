//! Do the still stretches agree? A test of the Allan variances of every hour of still data
//! against each other, at the white-noise level and at the bias-instability level.
//!
//! The pooled fit assumes one noise process throughout. Motion the detector missed, a bias
//! that drifts for the first hour after turn-on, a sensor that is noisier in one run: each
//! leaves some stretches with an Allan variance the others do not share, and the pooled fit
//! then reports a mixture as the sensor's noise. Each still stretch is cut into chunks of about
//! [`CHUNK_S`] (the last piece, if shorter than half a chunk, joins the one before); each
//! chunk's Allan variance is taken from its bin points (the cumulative output about every
//! second, [`crate::accumulate`]), inside the pieces the bias-change scan left
//! ([`crate::steps`]). Per channel, Bartlett's test of equal variances (a likelihood ratio of
//! chi-square variables, each with the estimator's equivalent degrees of freedom) is made at
//! the first bin octave (`τ` about 1 s: the white terms) and at the octave where the pooled
//! Allan deviation is lowest (the bias instability). The degrees of freedom are the smallest
//! the plausible noise types give, so the test errs towards silence. Family-wise false-alarm
//! probability: [`FALSE_ALARM`] over the six channels and two levels (Bonferroni).
//! A significant difference is a finding only when the most discrepant chunk's Allan deviation
//! is more than [`FACTOR`] from that of the other chunks: hours of data resolve a few percent, which a
//! real sensor's temperature alone can make, and a twin within that is still a fair model.
//!
//! Measured reach for a gyro turn-on transient (two 3 h paper-noise runs, the transient in both;
//! `tests/it/identify.rs`): time constants of 5-20 min at 0.2-1 deg/h are named here and their
//! first hour left out. Shorter (2.5 min) and slower (40-90 min) ones are not: the first are
//! diluted in their hour, the second lift the first chunks together. The direct test of a
//! decay from each run's first sample ([`crate::turnon`]) names those.

use crate::allan::{NoiseType, edf};
use crate::channels::{CHANNEL_NAMES, CHANNELS};
use sins_diag::{chi2_isf, chi2_sf};
use std::ops::Range;

/// Still stretches are cut into chunks of about this length (s) for the test.
pub const CHUNK_S: f64 = 3600.0;

/// Family-wise probability of a finding on stationary, homogeneous noise.
pub const FALSE_ALARM: f64 = 1e-3;

/// A chunk's Allan deviation must be more than this factor away from that of the other chunks
/// (above or below) for a significant difference to count against the model.
pub const FACTOR: f64 = 1.3;

/// What a finding whose discrepant chunks all open their runs says.
pub const TURN_ON_TEXT: &str = "the chunks that stand out are each at the start of a run: a \
     turn-on transient or warm-up, taken for noise unless that time is left out";

/// A chunk enters the test at an octave only with at least this many degrees of freedom there.
const MIN_EDF: f64 = 4.0;

/// The noise types whose degrees of freedom bound each level's from below.
const WHITE_TYPES: [NoiseType; 2] = [NoiseType::WhitePhase, NoiseType::WhiteFrequency];
const BIAS_TYPES: [NoiseType; 3] = [
    NoiseType::WhiteFrequency,
    NoiseType::FlickerFrequency,
    NoiseType::RandomWalkFrequency,
];

/// One channel's second differences at one octave inside one chunk.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ChunkSums {
    /// Sum of squared second differences of the bin points (unit² of the cumulative output).
    pub sum_sq: f64,
    /// Their count.
    pub count: u64,
    /// Degrees of freedom: the smallest of the white types, then of the bias types.
    pub edf: [f64; 2],
}

/// A chunk of a still stretch and its sums at every bin octave (`τ = 2^j τ₀`).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Chunk {
    /// Index of the run.
    pub run: usize,
    /// Time of its first sample (s).
    pub start_s: f64,
    /// Length (s).
    pub duration_s: f64,
    /// Per octave `j`, per channel.
    pub sums: Vec<[ChunkSums; CHANNELS]>,
}

/// The chunks of one stretch: `bins` are its bin points (`tau0_s` apart, the first at
/// `start_s`), `pieces[c]` the ranges of bin points channel `c` may use.
pub(crate) fn chunks(
    run: usize,
    start_s: f64,
    tau0_s: f64,
    bins: &[[f64; CHANNELS]],
    pieces: &[Vec<Range<usize>>],
) -> Vec<Chunk> {
    let n = bins.len();
    let len = ((CHUNK_S / tau0_s).round() as usize).max(8);
    let mut bounds = Vec::new();
    let mut a = 0;
    while a + 1 < n {
        let mut b = (a + len).min(n);
        if n - b < len / 2 {
            b = n;
        }
        bounds.push(a..b);
        a = b.saturating_sub(1).max(a + 1);
    }
    bounds
        .into_iter()
        .map(|r| {
            let mut sums = Vec::new();
            let mut mb = 1usize;
            while 2 * mb < r.len() {
                let mut at = [ChunkSums::default(); CHANNELS];
                for (c, s) in at.iter_mut().enumerate() {
                    for p in pieces.get(c).map_or(&[][..], Vec::as_slice) {
                        let sub = p.start.max(r.start)..p.end.min(r.end).min(n);
                        if let Some(b) = bins.get(sub) {
                            add_sums(s, b, c, mb);
                        }
                    }
                }
                sums.push(at);
                mb *= 2;
            }
            Chunk {
                run,
                start_s: start_s + r.start as f64 * tau0_s,
                duration_s: (r.len() - 1) as f64 * tau0_s,
                sums,
            }
        })
        .collect()
}

fn add_sums(s: &mut ChunkSums, bins: &[[f64; CHANNELS]], c: usize, mb: usize) {
    if bins.len() <= 2 * mb {
        return;
    }
    for k in 0..bins.len() - 2 * mb {
        let d = bins[k + 2 * mb][c] - 2.0 * bins[k + mb][c] + bins[k][c];
        s.sum_sq += d * d;
    }
    s.count += (bins.len() - 2 * mb) as u64;
    let (n, m) = (bins.len() as u64, mb as u64);
    let least = |types: &[NoiseType]| {
        types
            .iter()
            .map(|&t| edf(t, n, m))
            .fold(f64::INFINITY, f64::min)
    };
    s.edf[0] += least(&WHITE_TYPES);
    s.edf[1] += least(&BIAS_TYPES);
}

/// The outcome of one channel's test at one level.
#[derive(Clone, Debug, PartialEq)]
pub struct Heterogeneity {
    /// Channel name (`gyro_x` … `accel_z`).
    pub channel: String,
    /// The level: "white" (τ of the first bin octave) or "bias" (the lowest pooled point).
    pub level: &'static str,
    /// Averaging time (s).
    pub tau_s: f64,
    /// Chunks compared.
    pub chunks: usize,
    /// Bartlett's statistic (chi-square with `chunks − 1` degrees of freedom under agreement).
    pub statistic: f64,
    /// Its tail probability.
    pub p: f64,
    /// The most discrepant chunk: run index, start (s), length (s), and its Allan deviation
    /// over that of the other chunks pooled.
    pub worst: (usize, f64, f64, f64),
    /// Whether every chunk well above the pooled level is the first of its run (a turn-on
    /// transient, or a warm-up).
    pub at_turn_on: bool,
    /// Significant (Bonferroni over channels and levels) and beyond [`FACTOR`].
    pub finding: bool,
}

/// A level is not tested on a channel where the quantisation makes up more than this share of
/// the pooled Allan variance (see [`test`]).
pub const MAX_QUANTISATION_SHARE: f64 = 0.5;

/// Test every channel at both levels; `tau0_s` is the bin interval, `quanta` the output quantum
/// of each channel where its increments lie on a lattice (unit of the cumulative output: rad for
/// a gyro). Returns the significant differences only (findings and the small ones).
///
/// A quantised output's rounding error is not a stationary noise: at rest it follows the
/// rate's fraction of a quantum per sample, so its Allan variance (q²/4τ² on average, the
/// textbook quantisation noise) differs from one orientation to the next by a factor of two
/// or more. Where it makes up more than [`MAX_QUANTISATION_SHARE`] of the pooled Allan
/// variance, chunks at different orientations would differ through the rounding alone (a
/// navigation-grade gyro with a 1 arcsec quantum at τ ≈ 1 s), so that level is not tested on
/// that channel: even a doubled quantisation term then moves a chunk's Allan deviation by
/// less than [`FACTOR`].
pub(crate) fn test(
    chunks: &[Chunk],
    tau0_s: f64,
    quanta: &[Option<f64>; CHANNELS],
) -> Vec<Heterogeneity> {
    let alpha = FALSE_ALARM / (2 * CHANNELS) as f64;
    let mut out = Vec::new();
    let octaves = chunks.iter().map(|c| c.sums.len()).max().unwrap_or(0);
    for c in 0..CHANNELS {
        let usable = |j: usize, level: usize| -> Vec<(usize, f64, f64)> {
            let tau = (1u64 << j) as f64 * tau0_s;
            chunks
                .iter()
                .enumerate()
                .filter_map(|(i, ch)| {
                    let s = ch.sums.get(j)?[c];
                    (s.count > 0 && s.edf[level] >= MIN_EDF).then(|| {
                        let avar = s.sum_sq / (2.0 * tau * tau * s.count as f64);
                        (i, avar, s.edf[level])
                    })
                })
                .collect()
        };
        // The bias level: the lowest pooled Allan variance among the octaves above the first
        // that at least two chunks resolve.
        let bias_j = (1..octaves)
            .filter_map(|j| {
                let u = usable(j, 1);
                (u.len() >= 2).then(|| (j, pooled(&u)))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|x| x.0);
        for (level, j) in [(0usize, Some(0usize)), (1, bias_j)] {
            let Some(j) = j else { continue };
            let u = usable(j, level);
            if u.len() < 2 {
                continue;
            }
            let tau = (1u64 << j) as f64 * tau0_s;
            if let Some(q) = quanta[c]
                && q * q / (4.0 * tau * tau) > MAX_QUANTISATION_SHARE * pooled(&u)
            {
                continue;
            }
            let Some(h) = bartlett(&u, chunks, alpha) else {
                continue;
            };
            out.push(Heterogeneity {
                channel: CHANNEL_NAMES[c].to_string(),
                level: if level == 0 { "white" } else { "bias" },
                tau_s: (1u64 << j) as f64 * tau0_s,
                ..h
            });
        }
    }
    out
}

/// Degrees-of-freedom-weighted pooled variance of `(chunk, variance, edf)`.
fn pooled(u: &[(usize, f64, f64)]) -> f64 {
    let nu: f64 = u.iter().map(|x| x.2).sum();
    u.iter().map(|x| x.1 * x.2).sum::<f64>() / nu
}

/// Bartlett's test on `(chunk, variance, edf)`; `None` when not significant at `alpha`.
fn bartlett(u: &[(usize, f64, f64)], chunks: &[Chunk], alpha: f64) -> Option<Heterogeneity> {
    let k = u.len() as f64;
    let nu: f64 = u.iter().map(|x| x.2).sum();
    let sp = pooled(u);
    if !(sp > 0.0) || u.iter().any(|x| !(x.1 > 0.0)) {
        return None;
    }
    let m = nu * sp.ln() - u.iter().map(|x| x.2 * x.1.ln()).sum::<f64>();
    let corr = 1.0 + (u.iter().map(|x| 1.0 / x.2).sum::<f64>() - 1.0 / nu) / (3.0 * (k - 1.0));
    let statistic = m / corr;
    if statistic <= chi2_isf(alpha, k - 1.0) {
        return None;
    }
    // Each chunk against the pool of the others (Wilson-Hilferty: ν s²/σ² ~ χ²(ν) to a normal
    // deviate; the others' pool stands in for σ²).
    let others = |&(i, _, _): &(usize, f64, f64)| {
        let rest: Vec<(usize, f64, f64)> = u.iter().filter(|x| x.0 != i).copied().collect();
        pooled(&rest)
    };
    let z = |x: &(usize, f64, f64)| {
        let r = x.1 / others(x);
        let a = 2.0 / (9.0 * x.2);
        (r.cbrt() - (1.0 - a)) / a.sqrt()
    };
    let worst = u
        .iter()
        .max_by(|a, b| z(a).abs().total_cmp(&z(b).abs()))
        .copied()?;
    let ratio = (worst.1 / others(&worst)).sqrt();
    let first_of_run = |i: usize| {
        let ch = &chunks[i];
        chunks
            .iter()
            .filter(|o| o.run == ch.run)
            .all(|o| o.start_s >= ch.start_s)
    };
    let high: Vec<usize> = u.iter().filter(|x| z(x) > 3.0).map(|x| x.0).collect();
    let w = &chunks[worst.0];
    Some(Heterogeneity {
        channel: String::new(),
        level: "",
        tau_s: 0.0,
        chunks: u.len(),
        statistic,
        p: chi2_sf(statistic, k - 1.0),
        worst: (w.run, w.start_s, w.duration_s, ratio),
        at_turn_on: !high.is_empty() && high.iter().all(|&i| first_of_run(i)),
        // Not `!(1/F..=F).contains(&ratio)`: a NaN ratio is not a finding.
        #[allow(clippy::manual_range_contains)]
        finding: ratio > FACTOR || ratio < 1.0 / FACTOR,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bin points of white rate noise of scale `sigma` per bin, `n` of them.
    fn white_bins(n: usize, sigma: f64, seed: u64) -> Vec<[f64; CHANNELS]> {
        let mut g = sins_sim::GaussianStream::new(seed, 3);
        let mut x = [0.0; CHANNELS];
        (0..n)
            .map(|_| {
                for v in &mut x {
                    *v += sigma * g.next_standard();
                }
                x
            })
            .collect()
    }

    #[test]
    fn chunks_cover_the_stretch_and_the_short_tail_joins_the_last() {
        let bins = white_bins(8900, 1.0, 1);
        let all = vec![vec![0..8900]; CHANNELS];
        let c = chunks(0, 0.0, 1.0, &bins, &all);
        // 8900 bin points: 0..3600, 3599..7199, then 1701 left: less than half, joined.
        assert_eq!(c.len(), 2);
        assert_eq!(c[1].start_s, 3599.0);
        assert_eq!(c[1].start_s + c[1].duration_s, 8899.0);
        // White rate noise: the Allan variance at τ₀ is σ²/τ₀ (per bin) in every chunk.
        for ch in &c {
            let s = ch.sums[0][0];
            let avar = s.sum_sq / (2.0 * s.count as f64);
            assert!((avar - 1.0).abs() < 0.1, "{avar}");
        }
    }

    #[test]
    fn a_quantised_gyro_at_four_orientations_is_not_a_finding() {
        // Four hours, each at another rate (the Earth rate on the axis at another turntable
        // position), of a 1-unit quantum output with white noise of 0.03 units per bin: the
        // rounding, which dominates at every octave, has another Allan variance in each hour.
        let rates = [0.12, 0.5, 0.013, 0.333];
        let mut g = sins_sim::GaussianStream::new(3, 3);
        let mut angle = 0.0f64;
        let bins: Vec<[f64; CHANNELS]> = (0..4 * 3600)
            .map(|k| {
                angle += rates[k / 3600] + 0.03 * g.next_standard();
                let mut b = [0.0; CHANNELS];
                b[0] = angle.round();
                b
            })
            .collect();
        let all = vec![vec![0..bins.len()]; CHANNELS];
        let c = chunks(0, 0.0, 1.0, &bins, &all);
        // Taken as noise, the hours disagree by far more than FACTOR.
        let blind = test(&c, 1.0, &[None; CHANNELS]);
        let white = blind
            .iter()
            .find(|h| h.channel == "gyro_x" && h.level == "white")
            .expect("the rounding differs between hours");
        assert!(white.finding, "{white:?}");
        // Known as quantisation, no level of gyro_x is tested.
        let mut quanta = [None; CHANNELS];
        quanta[0] = Some(1.0);
        let h = test(&c, 1.0, &quanta);
        assert!(h.iter().all(|h| h.channel != "gyro_x"), "{h:?}");
    }

    #[test]
    fn equal_noise_passes_and_a_noisier_hour_is_named() {
        let mut flagged = 0;
        for seed in 0..100 {
            let bins = white_bins(4 * 3600, 1.0, 100 + seed);
            let all = vec![vec![0..bins.len()]; CHANNELS];
            flagged += usize::from(
                !test(&chunks(0, 0.0, 1.0, &bins, &all), 1.0, &[None; CHANNELS]).is_empty(),
            );
        }
        // Family-wise 1e-3 per test: 100 tests give 0.1 expected; 2 would be p ≈ 0.005.
        assert!(flagged <= 1, "{flagged} of 100 homogeneous sets flagged");
        // The third hour 1.5x noisier (Allan deviation) on channel 4.
        let mut bins = white_bins(4 * 3600, 1.0, 7);
        let mut g = sins_sim::GaussianStream::new(8, 3);
        let mut extra = 0.0;
        for (k, b) in bins.iter_mut().enumerate() {
            if (7200..10800).contains(&k) {
                extra += 1.118 * g.next_standard();
            }
            b[4] += extra;
        }
        let all = vec![vec![0..bins.len()]; CHANNELS];
        let h = test(&chunks(0, 0.0, 1.0, &bins, &all), 1.0, &[None; CHANNELS]);
        let w = h
            .iter()
            .find(|h| h.channel == "accel_y" && h.level == "white")
            .expect("found");
        // 3 sigma of the ratio: each hour's estimate has about 2N/3 = 2400 degrees of freedom,
        // the other three pooled 7200, so the deviation ratio scatters by
        // 1.5 x 0.5 x sqrt(2/2400 + 2/7200) = 0.025.
        assert!(w.finding && (w.worst.3 - 1.5).abs() < 0.075, "{w:?}");
        assert!((w.worst.1 - 7199.0).abs() < 2.0, "{w:?}");
        assert!(h.iter().all(|h| h.channel == "accel_y"), "{h:?}");
    }
}
