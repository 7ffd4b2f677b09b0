//! Bias changes inside a stationary stretch, found before the Allan fit.
//!
//! A bias that jumps while the IMU stands still (a shock, a mode change, a turn-on transient)
//! raises the Allan variance at every `τ` above the jump like a rate random walk does, and a
//! fit would count it as noise: the twin would then absorb, as noise, an effect the diagnosis
//! should name. The scan works on the stretch's bin points (the cumulative output about every
//! second, see [`crate::accumulate`]). At each octave `m` it takes the rate difference between
//! the means of two adjacent windows of `m` bins, `d_k = (x_{k+2m} − 2x_{k+m} + x_k)/(m τ₀)`
//! (the Allan estimator's own second difference), and compares each with the robust scale of
//! all of them (1.4826 × their median absolute deviation). Stationary noise of any colour gives
//! Gaussian `d_k` of that scale; a change of the bias by `Δ` gives one peak of `|Δ|` where it
//! happens. A peak beyond the Bonferroni threshold over the six channels, the octaves and the
//! windows (family-wise false-alarm probability [`FALSE_ALARM`] per stretch) is a change. The
//! octave where it stands out most locates it; the `2m` bins around it are left out of the
//! Allan sums, and the pieces either side are scanned again.

use sins_diag::chi2_isf;

/// Family-wise probability of reporting a change in a stretch of stationary noise.
pub const FALSE_ALARM: f64 = 1e-3;

/// An octave is scanned only where the piece holds at least this many windows of its length:
/// the robust scale then rests on at least 32 independent differences.
const MIN_WINDOWS: usize = 64;

/// At most this many changes per channel and stretch (a transient can cut a stretch several
/// times; beyond this the stretch is not stationary data at all).
const MAX_CHANGES: usize = 8;

/// The 1.4826 that turns a Gaussian's median absolute deviation into its standard deviation.
const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// A change of one channel's bias found inside a stationary stretch.
#[derive(Clone, Debug, PartialEq)]
pub struct BiasChange {
    /// Channel: gyro x, y, z then accelerometer x, y, z.
    pub channel: usize,
    /// The bin point where the rate changes (index into the stretch's bin points).
    pub at_bin: usize,
    /// Half-width of the window left out around it (bins): the octave that located it.
    pub half_width_bins: usize,
    /// Rate after minus rate before (rad/s for a gyro, m/s² for an accelerometer).
    pub size: f64,
    /// The peak against the robust scale of the other windows.
    pub z: f64,
}

impl BiasChange {
    /// The bin points left out around the change: those strictly inside the half-width of the
    /// octave that located it (the pieces either side end and start on its edges).
    pub fn left_out(&self) -> std::ops::Range<usize> {
        let m = self.half_width_bins;
        (self.at_bin + 1).saturating_sub(m)..self.at_bin + m
    }
}

/// The threshold on `z` for a stretch of `n_bins` bin points: Bonferroni over its `channels`
/// and about `2 n_bins` windows each (`n/m` per octave, summed over the octaves).
pub fn threshold(n_bins: usize, channels: usize) -> f64 {
    let tests = (channels.max(1) * 2 * n_bins.max(1)) as f64;
    chi2_isf(FALSE_ALARM / tests, 1.0).sqrt()
}

/// The changes of one channel whose bin points are `x` (bins `tau0_s` apart), sorted by time;
/// `z_crit` from [`threshold`]; `quantum` the output's lattice when it is quantised (same unit
/// as `x`), which bounds the window differences' scale from below (see [`scale_floor`]).
pub fn scan_channel(
    channel: usize,
    x: &[f64],
    tau0_s: f64,
    z_crit: f64,
    quantum: Option<f64>,
) -> Vec<BiasChange> {
    let mut found = Vec::new();
    let mut pieces = vec![(0, x.len())];
    while let Some((lo, hi)) = pieces.pop() {
        if found.len() >= MAX_CHANGES {
            break;
        }
        let Some(peak) = strongest(&x[lo..hi], tau0_s, quantum).filter(|p| p.z > z_crit) else {
            continue;
        };
        let change = BiasChange {
            channel,
            at_bin: lo + peak.at_bin,
            ..peak
        };
        let gap = change.left_out();
        pieces.push((lo, gap.start.max(lo)));
        pieces.push((gap.end.min(hi), hi));
        found.push(change);
    }
    found.sort_by_key(|c| c.at_bin);
    found
}

/// The pieces of `0..n_points` left once the windows around `changes` are taken out, as
/// half-open ranges of bin points; the whole range without a change.
pub fn pieces(n_points: usize, changes: &[BiasChange]) -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    let mut start = 0;
    for c in changes {
        let gap = c.left_out();
        let end = gap.start.max(start);
        if end > start {
            out.push(start..end);
        }
        start = start.max(gap.end).min(n_points);
    }
    if n_points > start {
        out.push(start..n_points);
    }
    out
}

/// The smallest scale of a window difference of a quantised output: each bin point carries a
/// rounding error uniform over one quantum `q`, so `x_{k+2m} − 2x_{k+m} + x_k` carries one of
/// variance `6 q²/12` (and never beyond `±2q`). Without it, a gyro at rest whose differences
/// take two or three lattice values would have a median absolute deviation of zero up to
/// rounding, and any quantum a change.
pub fn scale_floor(quantum: f64) -> f64 {
    quantum * std::f64::consts::FRAC_1_SQRT_2
}

/// The most outstanding window difference of `x` over the octaves it is long enough for.
fn strongest(x: &[f64], tau0_s: f64, quantum: Option<f64>) -> Option<BiasChange> {
    let n = x.len();
    let mut best: Option<BiasChange> = None;
    let mut m = 1;
    let mut d = Vec::new();
    let mut dev = Vec::new();
    while n >= MIN_WINDOWS * m {
        d.clear();
        d.extend((0..n - 2 * m).map(|k| x[k + 2 * m] - 2.0 * x[k + m] + x[k]));
        let centre = median(&mut dev, d.iter().copied());
        let mad = MAD_TO_SIGMA * median(&mut dev, d.iter().map(|v| (v - centre).abs()));
        let scale = match quantum {
            Some(q) => mad.max(scale_floor(q)),
            None if mostly_ties(&d, centre) => 0.0,
            None => mad,
        };
        if scale > 0.0 {
            let (k, dk) = d
                .iter()
                .enumerate()
                .max_by(|a, b| (a.1 - centre).abs().total_cmp(&(b.1 - centre).abs()))
                .map(|(k, v)| (k, *v))?;
            let z = (dk - centre).abs() / scale;
            if best.as_ref().is_none_or(|b| z > b.z) {
                best = Some(BiasChange {
                    channel: 0,
                    at_bin: k + m,
                    half_width_bins: m,
                    size: (dk - centre) / (m as f64 * tau0_s),
                    z,
                });
            }
        }
        m *= 2;
    }
    best
}

/// Whether a quarter or more of the differences equal their median (to a millionth of the
/// largest deviation): an output quantised on a lattice nobody detected, whose differences
/// take a few lattice values; their median absolute deviation is then no Gaussian scale (it
/// can be zero up to rounding), so the octave is not scanned.
fn mostly_ties(d: &[f64], centre: f64) -> bool {
    let widest = d.iter().map(|v| (v - centre).abs()).fold(0.0, f64::max);
    let tol = 1e-6 * widest;
    let ties = d.iter().filter(|v| (*v - centre).abs() <= tol).count();
    4 * ties >= d.len()
}

/// Median of `values` (the upper one of an even count), with `buf` as scratch.
fn median(buf: &mut Vec<f64>, values: impl Iterator<Item = f64>) -> f64 {
    buf.clear();
    buf.extend(values);
    if buf.is_empty() {
        return 0.0;
    }
    let mid = buf.len() / 2;
    *buf.select_nth_unstable_by(mid, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cumulative output of white rate noise (σ per bin `sigma`) plus a change of `step` at bin
    /// `at` (xorshift Gaussian pairs: deterministic).
    fn walk(n: usize, sigma: f64, step: f64, at: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        let mut uniform = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let mut x = vec![0.0];
        for k in 0..n - 1 {
            let g = (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos();
            let rate = sigma * g + if k >= at { step } else { 0.0 };
            x.push(x[k] + rate);
        }
        x
    }

    #[test]
    fn a_change_of_ten_sigma_is_found_where_it_is_and_sized() {
        let x = walk(20_000, 1.0, 1.0, 7_000, 11);
        let z = threshold(x.len(), 6);
        let found = scan_channel(2, &x, 1.0, z, None);
        assert_eq!(found.len(), 1, "{found:?}");
        let c = &found[0];
        assert_eq!(c.channel, 2);
        assert!(c.at_bin.abs_diff(7_000) <= c.half_width_bins, "{c:?}");
        // The size from windows of m bins has σ = √(2/m) per bin of white noise.
        let sigma = (2.0 / c.half_width_bins as f64).sqrt();
        assert!((c.size - 1.0).abs() < 3.0 * sigma, "{c:?}");
        let p = pieces(x.len(), &found);
        assert_eq!(p.len(), 2);
        assert!(p[0].end <= 7_000 && p[1].start >= 7_000, "{p:?}");
    }

    #[test]
    fn stationary_noise_raises_no_change_in_a_hundred_stretches() {
        // FALSE_ALARM is per stretch over six channels: one channel here, so about 2e-4 each.
        let z = threshold(20_000, 6);
        let alarms: usize = (0..100)
            .map(|seed| scan_channel(0, &walk(20_000, 1.0, 0.0, 0, 100 + seed), 1.0, z, None).len())
            .sum();
        assert_eq!(alarms, 0);
    }

    #[test]
    fn a_quantised_output_raises_no_change() {
        // The paper's gyro at rest: 19.3 quanta of Earth rate per bin and white noise of 0.02
        // quantum, quantised to 1 arcsec and offset as the accumulator's reference is: most
        // one-bin differences are 0 up to rounding, a few one quantum.
        let q = 4.848_136_811_095_36e-6;
        let x = walk(20_000, 0.02, 0.0, 0, 7);
        let lattice: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(k, v)| ((v + 19.3 * k as f64).floor() * q + 0.1) - 0.1)
            .collect();
        let z = threshold(lattice.len(), 6);
        assert!(scan_channel(0, &lattice, 1.0, z, Some(q)).is_empty());
        assert!(scan_channel(0, &lattice, 1.0, z, None).is_empty());
        // A change of 0.05 quantum per bin (the blind suite's case32, 0.05 deg/h against 1
        // arcsec and 1.28 s bins) is found on the lattice, where every one-bin difference ties.
        let stepped: Vec<f64> = lattice
            .iter()
            .enumerate()
            .map(|(k, v)| v + (0.05 * k.saturating_sub(9_000) as f64).floor() * q)
            .collect();
        let found = scan_channel(0, &stepped, 1.0, z, Some(q));
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].at_bin.abs_diff(9_000) <= found[0].half_width_bins);
        assert!((found[0].size / q - 0.05).abs() < 0.01, "{found:?}");
    }

    #[test]
    fn pieces_leave_out_each_window_and_keep_the_rest() {
        let c = |at, m| BiasChange {
            channel: 0,
            at_bin: at,
            half_width_bins: m,
            size: 1.0,
            z: 9.0,
        };
        assert_eq!(pieces(100, &[]), vec![0..100]);
        assert_eq!(pieces(100, &[c(50, 4)]), vec![0..47, 54..100]);
        assert_eq!(pieces(100, &[c(2, 4), c(98, 4)]), vec![6..95]);
    }
}
