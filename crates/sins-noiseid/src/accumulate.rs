//! One streaming pass over a run: the stationary stretches' second differences at every octave
//! of `τ`, in bounded memory.
//!
//! Per stretch and channel the cumulative output `x` (a constant reference rate, the stretch's
//! first sample, removed for numerical conditioning; it cancels in every second difference) is
//! kept in a ring of the last `2B + 1` points, `B` the bin length (the power of two of samples
//! nearest 1 s), which gives the exact overlapping estimator at every octave `τ = h … B h`
//! sample by sample. Every `B` samples `x` is also stored (a 5 h stretch at 200 Hz: 14 063
//! points per channel, 0.7 MB for six channels); octaves `τ ≥ 2 B h` use these bin points,
//! overlapping at a stride of one bin instead of one sample (fewer, equally valid second
//! differences; the degrees of freedom are computed for that stride). Memory is therefore
//! about 50 bytes per second of stationary data, independent of the sample rate.

use crate::allan::PooledTau;
use crate::homogeneity::{self, Chunk};
use crate::quant::LatticeDetector;
use crate::result::ChangeReport;
use crate::steps::{self, BiasChange};
use crate::turnon::Opening;
use sins_imu::ImuSample;
use std::collections::BTreeMap;

pub use crate::channels::{CHANNEL_NAMES, CHANNELS};

/// A stationary stretch that was used.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct StretchStats {
    /// Index of the run.
    pub run: usize,
    /// Time of its first sample (s).
    pub start_s: f64,
    /// Samples in it.
    pub samples: u64,
    /// Mean rate per channel: gyro rad/s, accelerometer m/s².
    pub mean_rate: [f64; CHANNELS],
    /// Changes of a bias found inside it ([`crate::steps`]), left out of the Allan sums.
    pub changes: Vec<ChangeReport>,
}

/// The pooled second differences of all runs, keyed by the averaging factor in samples.
pub(crate) struct Accumulator {
    h_s: f64,
    bin: usize,
    min_stretch_samples: u64,
    pub pooled: BTreeMap<u64, [PooledTau; CHANNELS]>,
    pub stretches: Vec<StretchStats>,
    /// Each channel's lattice (gyro rad, accelerometer m/s), read from the raw increments.
    pub lattice: [LatticeDetector; CHANNELS],
    pub skipped: Vec<(usize, f64, u64)>,
    /// The still stretches cut into hours, for the test of their agreement
    /// ([`crate::homogeneity`]).
    pub chunks: Vec<Chunk>,
    /// Each run's first still stretch up to its first bias change, for the turn-on test
    /// ([`crate::turnon`]; its `offset_s` is the stretch's start time until the identification
    /// makes it relative to the run's first sample).
    pub openings: Vec<Opening>,
    open: Option<Open>,
}

/// The stretch being read.
struct Open {
    run: usize,
    start_s: f64,
    reference: [f64; CHANNELS],
    x: [f64; CHANNELS],
    raw_sum: [f64; CHANNELS],
    points: u64,
    /// The last points of `x`, all channels of a point together (so that one point's six
    /// second differences are computed side by side).
    ring: Vec<[f64; CHANNELS]>,
    mask: usize,
    short_ss: Vec<[f64; CHANNELS]>,
    short_n: Vec<u64>,
    bins: Vec<[f64; CHANNELS]>,
}

impl Accumulator {
    /// Accumulator for samples every `h_s`, ignoring stretches shorter than `min_stretch_s`.
    pub fn new(h_s: f64, min_stretch_s: f64) -> Self {
        // Bin length: the power of two of samples nearest 1 s (at least 1).
        let per_s = (1.0 / h_s).max(1.0);
        let bin = 1usize << (per_s.log2().round().clamp(0.0, 20.0) as u32);
        Self {
            h_s,
            bin,
            min_stretch_samples: (min_stretch_s / h_s).ceil() as u64,
            pooled: BTreeMap::new(),
            stretches: Vec::new(),
            lattice: std::array::from_fn(|_| LatticeDetector::default()),
            skipped: Vec::new(),
            chunks: Vec::new(),
            openings: Vec::new(),
            open: None,
        }
    }

    /// The interval of the bin points (s): the bin length in samples times the sample interval.
    pub fn tau0_s(&self) -> f64 {
        self.bin as f64 * self.h_s
    }

    fn short_octaves(&self) -> usize {
        self.bin.trailing_zeros() as usize + 1
    }

    /// Feed one sample: `stationary` says whether its segment is one of the chosen labels;
    /// `raw` is the sample as recorded (the same as `s` unless the accelerometer increments
    /// were compensated), whose increments the lattice of each channel is read from.
    #[inline]
    pub fn push(&mut self, run: usize, s: &ImuSample, raw: &ImuSample, stationary: bool) {
        let r = [
            raw.dtheta_rad.x,
            raw.dtheta_rad.y,
            raw.dtheta_rad.z,
            raw.dv_mps.x,
            raw.dv_mps.y,
            raw.dv_mps.z,
        ];
        if !stationary {
            // The lattice is checked over every sample, its quantum read from the still ones.
            for (l, x) in self.lattice.iter_mut().zip(r) {
                l.check(x);
            }
            self.close();
            return;
        }
        for (l, x) in self.lattice.iter_mut().zip(r) {
            l.push(x);
        }
        let v = [
            s.dtheta_rad.x,
            s.dtheta_rad.y,
            s.dtheta_rad.z,
            s.dv_mps.x,
            s.dv_mps.y,
            s.dv_mps.z,
        ];
        if self.open.as_ref().is_some_and(|o| o.run != run) {
            self.close();
        }
        let octaves = self.short_octaves();
        let bin = self.bin;
        let h_s = self.h_s;
        let o = self.open.get_or_insert_with(|| {
            let len = (4 * bin).next_power_of_two();
            Open {
                run,
                start_s: s.t_s - h_s,
                reference: v,
                x: [0.0; CHANNELS],
                raw_sum: [0.0; CHANNELS],
                points: 0,
                ring: vec![[0.0; CHANNELS]; len],
                mask: len - 1,
                short_ss: vec![[0.0; CHANNELS]; octaves],
                short_n: vec![0; octaves],
                bins: vec![[0.0; CHANNELS]],
            }
        });
        o.points += 1;
        let p = o.points as usize;
        for (c, &vc) in v.iter().enumerate() {
            o.raw_sum[c] += vc;
            o.x[c] += vc - o.reference[c];
        }
        o.ring[p & o.mask] = o.x;
        for j in 0..octaves {
            let m = 1usize << j;
            if p < 2 * m {
                break;
            }
            let (a, b) = (&o.ring[(p - m) & o.mask], &o.ring[(p - 2 * m) & o.mask]);
            for (c, ss) in o.short_ss[j].iter_mut().enumerate() {
                let d = o.x[c] - 2.0 * a[c] + b[c];
                *ss += d * d;
            }
            o.short_n[j] += 1;
        }
        if p.is_multiple_of(bin) {
            o.bins.push(o.x);
        }
    }

    /// End the stretch being read (at a non-stationary sample or the end of a run).
    pub fn close(&mut self) {
        let Some(o) = self.open.take() else { return };
        if o.points < self.min_stretch_samples.max(2) {
            self.skipped.push((o.run, o.start_s, o.points));
            return;
        }
        let n_points = o.points + 1;
        let index = self.stretches.len();
        for (j, (ss, &n)) in o.short_ss.iter().zip(&o.short_n).enumerate() {
            let m = 1u64 << j;
            let entry = self.entry(m);
            for c in 0..CHANNELS {
                entry[c].add(index, ss[c], n, n_points, m);
            }
        }
        let nb = o.bins.len();
        let tau0_s = self.bin as f64 * self.h_s;
        let z_crit = steps::threshold(nb, CHANNELS);
        let changes: Vec<Vec<BiasChange>> = (0..CHANNELS)
            .map(|c| {
                let x: Vec<f64> = o.bins.iter().map(|b| b[c]).collect();
                let quantum = self.lattice.get(c).and_then(|l| l.quantum());
                steps::scan_channel(c, &x, tau0_s, z_crit, quantum)
            })
            .collect();
        let pieces: Vec<_> = changes.iter().map(|ch| steps::pieces(nb, ch)).collect();
        if !self.openings.iter().any(|op| op.run == o.run) {
            // Up to the first bias change on any channel, except those in the first
            // `OPENING_FREE_S`: a change found so early is often the transient itself.
            let early = (OPENING_FREE_S / tau0_s).ceil() as usize;
            let end = pieces
                .iter()
                .map(|p| first_gap_after(p, nb, early))
                .min()
                .unwrap_or(nb);
            self.openings.push(Opening {
                run: o.run,
                offset_s: o.start_s,
                tau0_s,
                bins: o.bins[..end.min(nb)].to_vec(),
            });
        }
        self.chunks.extend(homogeneity::chunks(
            o.run, o.start_s, tau0_s, &o.bins, &pieces,
        ));
        let mut mb = 2usize;
        while 2 * mb < nb {
            let m = (mb * self.bin) as u64;
            for (c, channel_pieces) in pieces.iter().enumerate() {
                for piece in channel_pieces {
                    let bins = &o.bins[piece.clone()];
                    let (ss, count) = bin_second_differences(bins, c, mb);
                    self.entry(m)[c].add(index, ss, count, bins.len() as u64, mb as u64);
                }
            }
            mb *= 2;
        }
        let mean_rate = std::array::from_fn(|c| o.raw_sum[c] / (o.points as f64 * self.h_s));
        self.stretches.push(StretchStats {
            run: o.run,
            start_s: o.start_s,
            samples: o.points,
            mean_rate,
            changes: changes
                .into_iter()
                .flatten()
                .map(|c| ChangeReport {
                    channel: CHANNEL_NAMES[c.channel].to_string(),
                    at_s: o.start_s + c.at_bin as f64 * tau0_s,
                    left_out_s: 2.0 * c.half_width_bins as f64 * tau0_s,
                    size: c.size,
                    z: c.z,
                })
                .collect(),
        });
    }

    fn entry(&mut self, m: u64) -> &mut [PooledTau; CHANNELS] {
        let tau_s = m as f64 * self.h_s;
        self.pooled.entry(m).or_insert_with(|| {
            std::array::from_fn(|_| PooledTau {
                tau_s,
                ..PooledTau::default()
            })
        })
    }
}

/// A bias change found within this time of a run's first still stretch (s) does not end the
/// stretch for the turn-on test.
const OPENING_FREE_S: f64 = 600.0;

/// The start of the first gap between `pieces` (of `nb` bin points) that begins after bin
/// `early`, or `nb`.
fn first_gap_after(pieces: &[std::ops::Range<usize>], nb: usize, early: usize) -> usize {
    let mut gaps = pieces
        .iter()
        .map(|r| r.end)
        .filter(|&e| e < nb)
        .chain(pieces.first().filter(|r| r.start > 0).map(|_| 0));
    gaps.find(|&g| g > early).unwrap_or(nb)
}

/// Squared second differences of channel `c` at a stride of `mb` bin points, and their count.
fn bin_second_differences(bins: &[[f64; CHANNELS]], c: usize, mb: usize) -> (f64, u64) {
    if bins.len() <= 2 * mb {
        return (0.0, 0);
    }
    let mut ss = 0.0;
    for k in 0..bins.len() - 2 * mb {
        let d = bins[k + 2 * mb][c] - 2.0 * bins[k + mb][c] + bins[k][c];
        ss += d * d;
    }
    (ss, (bins.len() - 2 * mb) as u64)
}
