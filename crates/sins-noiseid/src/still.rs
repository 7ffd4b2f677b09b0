//! Still stretches found in the data, and motion named: a generalised likelihood-ratio
//! stillness detector on the gyros and accelerometers against the sensor's own white noise.
//!
//! The run is cut into windows of [`StillnessConfig::window_s`] (1 s). Under stillness each
//! channel's rate is a constant (the Earth rate, gravity, the biases) plus white noise of
//! variance σ²_c per sample, and two statistics are chi-square distributed:
//! - the within-window scatter `T1 = Σ_c S_c / σ²_c` (S_c the sum of squared deviations from
//!   the window mean), χ² with 6 (n − 1) degrees of freedom: vibration, shocks;
//! - the change of the window means from the previous window, `T2 = Σ_c (m_c − m'_c)² / v_c`,
//!   χ² with 6 degrees of freedom (`v_c = 2σ²_c / n` for white noise): a rotation or an
//!   acceleration that starts, stops or changes.
//!
//! Real sensors are not white: a MEMS gyro's bias wanders between windows and a coarse output
//! quantum scatters the window variances more than χ² says. Both tests are therefore
//! calibrated on the run itself: `v_c` is the 10 % quantile of the squared differences over
//! that of χ²_1 (at least the white value), and T1's threshold excess over its median is
//! widened by the ratio of the observed spread (median − 10 % quantile) to χ²'s.
//!
//! These are the generalised likelihood-ratio tests of "still" against "the rates move" for a
//! Gaussian white sensor (the zero-velocity detectors of foot-mounted navigation, Skog et al.
//! 2010, test the same hypothesis against known gravity; here the Earth rate and the biases
//! are unknown, so the window's own mean stands in for them). σ²_c is the sensor's own: the
//! 10 % quantile of the windows' sample variances, divided by that quantile of χ²_{n−1}/(n−1),
//! so that a run which moves most of the time still gives its quiet floor. Each test's
//! threshold is the χ² quantile at the per-window false-alarm probability
//! `false_alarms_per_hour / (2 × windows per hour)`: on still data with white noise the
//! detector flags that many windows per hour of data (the test suite measures it). A flagged
//! window and [`StillnessConfig::guard_windows`] on each side are motion; the rest, in runs of
//! at least the identification's shortest stretch, are still.
//!
//! Limitation: a motion whose rates stay constant for many seconds without vibration (a steady
//! turn on a smooth road) changes the window means only where it starts and ends; those
//! windows and their guards are motion, its steady middle is not seen.

use serde::{Deserialize, Serialize};

use crate::accumulate::{CHANNEL_NAMES, CHANNELS};
pub use crate::result::MotionReport;

/// Settings of the stillness detector.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct StillnessConfig {
    /// Window length (s; default 1).
    pub window_s: f64,
    /// Expected false alarms per hour of still, white-noise data (default 0.01).
    pub false_alarms_per_hour: f64,
    /// Windows either side of a flagged one also counted as motion (default 2).
    pub guard_windows: usize,
    /// Quantile of the windows' variances taken as the quiet floor (default 0.1).
    pub floor_quantile: f64,
}

impl Default for StillnessConfig {
    fn default() -> Self {
        Self {
            window_s: 1.0,
            false_alarms_per_hour: 0.01,
            guard_windows: 2,
            floor_quantile: 0.1,
        }
    }
}

/// A sample's six rates (gyro rad/s, accelerometer m/s²): its increments over `h_s`.
pub fn rates(s: &sins_imu::ImuSample, h_s: f64) -> [f64; CHANNELS] {
    [
        s.dtheta_rad.x / h_s,
        s.dtheta_rad.y / h_s,
        s.dtheta_rad.z / h_s,
        s.dv_mps.x / h_s,
        s.dv_mps.y / h_s,
        s.dv_mps.z / h_s,
    ]
}

/// One window's per-channel sums (rates: rad/s, m/s²).
#[derive(Clone, Debug, PartialEq)]
pub struct Window {
    /// Index of its first sample in the run.
    pub first_sample: u64,
    /// Samples in it.
    pub n: u64,
    /// Start time (s).
    pub start_s: f64,
    /// Whether its samples are candidates (labelled still, or the run has no labels).
    pub candidate: bool,
    /// Per-channel mean rate.
    pub mean: [f64; CHANNELS],
    /// Per-channel sum of squared deviations from the mean.
    pub ss: [f64; CHANNELS],
    /// Per-channel smallest non-zero difference of a sample's rate from the window's first
    /// (rad/s, m/s²; infinite when every sample equals the first): the output's resolution
    /// where the output is quantised.
    pub resolution: [f64; CHANNELS],
}

/// Builds the windows of one run in one pass (a window never straddles a change of the
/// candidate flag).
#[derive(Clone, Debug)]
pub struct WindowBuilder {
    h_s: f64,
    per_window: u64,
    sample: u64,
    open: Option<(Window, [f64; CHANNELS], [f64; CHANNELS])>,
    /// The windows closed so far.
    pub windows: Vec<Window>,
}

impl WindowBuilder {
    /// A builder for samples `h_s` apart.
    pub fn new(h_s: f64, cfg: &StillnessConfig) -> Self {
        Self {
            h_s,
            per_window: ((cfg.window_s / h_s).round() as u64).max(4),
            sample: 0,
            open: None,
            windows: Vec::new(),
        }
    }

    /// Add the next sample's rates (gyro rad/s, accel m/s²) at time `t_s` (its interval's end).
    pub fn push(&mut self, t_s: f64, rates: [f64; CHANNELS], candidate: bool) {
        let full = self
            .open
            .as_ref()
            .is_some_and(|(w, _, _)| w.n >= self.per_window || w.candidate != candidate);
        if full {
            self.close();
        }
        // Lazy on purpose: the window is built once per window, not on every sample.
        #[allow(clippy::unnecessary_lazy_evaluations)]
        let (w, shift, sum) = self.open.get_or_insert_with(|| {
            (
                Window {
                    first_sample: self.sample,
                    n: 0,
                    start_s: t_s - self.h_s,
                    candidate,
                    mean: [0.0; CHANNELS],
                    ss: [0.0; CHANNELS],
                    resolution: [f64::INFINITY; CHANNELS],
                },
                rates,
                [0.0; CHANNELS],
            )
        });
        // Shifted sums (by the window's first sample) for numerical conditioning.
        for c in 0..CHANNELS {
            let d = rates[c] - shift[c];
            sum[c] += d;
            w.ss[c] += d * d;
            if d != 0.0 {
                w.resolution[c] = w.resolution[c].min(d.abs());
            }
        }
        w.n += 1;
        self.sample += 1;
    }

    /// Close the open window (call at the end of the run).
    pub fn close(&mut self) {
        if let Some((mut w, shift, sum)) = self.open.take() {
            let n = w.n as f64;
            for c in 0..CHANNELS {
                let m = sum[c] / n;
                w.ss[c] = (w.ss[c] - n * m * m).max(0.0);
                w.mean[c] = shift[c] + m;
            }
            self.windows.push(w);
        }
    }
}

/// The detector's result for one run.
#[derive(Clone, Debug, PartialEq)]
pub struct Stillness {
    /// Whether each window is still (a candidate, not flagged, not in a guard).
    pub still: Vec<bool>,
    /// The motion found among the candidate windows.
    pub motion: Vec<MotionReport>,
    /// Per-channel white-noise variance per sample (rad²/s², m²/s⁴).
    pub sigma2: [f64; CHANNELS],
    /// Whether the detector had enough candidate windows to judge (else every candidate
    /// window is taken as still).
    pub judged: bool,
}

/// The χ² quantile with `dof` degrees of freedom at upper-tail probability `p`.
fn chi2_upper(p: f64, dof: f64) -> f64 {
    sins_diag::chi2_isf(p, dof)
}

/// The `q` quantile of χ²_k / k.
fn chi2_over_k_quantile(q: f64, k: f64) -> f64 {
    (chi2_upper(1.0 - q, k) / k).max(1e-6)
}

/// Classify the windows of run `run`.
pub fn detect(run: &str, windows: &[Window], cfg: &StillnessConfig) -> Stillness {
    let full: Vec<&Window> = windows.iter().filter(|w| w.candidate && w.n >= 4).collect();
    let nw = windows.len();
    let mut out = Stillness {
        still: windows.iter().map(|w| w.candidate).collect(),
        motion: Vec::new(),
        sigma2: [0.0; CHANNELS],
        judged: false,
    };
    if full.len() < 20 {
        return out;
    }
    let n_typ = full.iter().map(|w| w.n).max().unwrap_or(4) as f64;
    let corr = chi2_over_k_quantile(cfg.floor_quantile, n_typ - 1.0);
    for c in 0..CHANNELS {
        let mut v: Vec<f64> = full.iter().map(|w| w.ss[c] / (w.n as f64 - 1.0)).collect();
        v.sort_by(f64::total_cmp);
        let k = ((v.len() as f64 - 1.0) * cfg.floor_quantile).round() as usize;
        // A quantised output cannot be quieter than its quantisation, a uniform error of one
        // resolution step (variance step²/12 per sample): without this floor a gyro at rest
        // whose rate is below one quantum per sample (increments mostly 0) has a quiet floor of
        // zero and every pulse reads as motion. A channel without any scatter gets a floor of
        // one part in 1e12 of its level, so that the statistics stay finite.
        let level = full.iter().map(|w| w.mean[c].abs()).fold(0.0, f64::max);
        out.sigma2[c] = (v[k] / corr)
            .max(resolution(&full, c).powi(2) / 12.0)
            .max((1e-12 * level).powi(2))
            .max(f64::MIN_POSITIVE);
    }
    out.judged = true;
    let windows_per_hour = 3600.0 / cfg.window_s;
    let p = cfg.false_alarms_per_hour / (2.0 * windows_per_hour);
    let thr2 = chi2_upper(p, CHANNELS as f64);
    let q = cfg.floor_quantile;
    // The scatter test on the empirical spread: real sensors (flicker, a coarse output
    // quantum) scatter their window variances more than white noise; the threshold's excess
    // over the median is widened by the ratio of the observed to the chi-square spread.
    let dof1 = CHANNELS as f64 * (n_typ - 1.0);
    let r: Vec<f64> = full
        .iter()
        .map(|w| {
            (0..CHANNELS).map(|c| w.ss[c] / out.sigma2[c]).sum::<f64>()
                / (CHANNELS as f64 * (w.n as f64 - 1.0))
        })
        .collect();
    let (r_lo, r_mid) = (quantile(&r, q), quantile(&r, 0.5));
    let (x_lo, x_mid) = (
        chi2_over_k_quantile(q, dof1),
        chi2_over_k_quantile(0.5, dof1),
    );
    let spread = ((r_mid - r_lo) / (x_mid - x_lo)).max(1.0);
    let thr1_ratio = r_mid.max(x_mid) + (chi2_upper(p, dof1) / dof1 - x_mid) * spread;
    // The change test on the empirical variance of the window-mean differences (at least the
    // white noise's): bias wander between windows raises it for a MEMS sensor.
    let diffs: Vec<[f64; CHANNELS]> = (1..nw)
        .filter(|&i| pair_ok(windows, i))
        .map(|i| std::array::from_fn(|c| windows[i].mean[c] - windows[i - 1].mean[c]))
        .collect();
    let chi1_lo = chi2_upper(1.0 - q, 1.0);
    let var_d: [f64; CHANNELS] = std::array::from_fn(|c| {
        let d2: Vec<f64> = diffs.iter().map(|d| d[c] * d[c]).collect();
        (quantile(&d2, q) / chi1_lo).max(2.0 * out.sigma2[c] / n_typ)
    });
    let mut flagged = vec![false; nw];
    let mut score = vec![(0.0f64, [0.0f64; CHANNELS]); nw];
    for i in 0..nw {
        let w = &windows[i];
        if !w.candidate || w.n < 4 {
            continue;
        }
        let dof = CHANNELS as f64 * (w.n as f64 - 1.0);
        let per1: [f64; CHANNELS] = std::array::from_fn(|c| w.ss[c] / out.sigma2[c]);
        let t1: f64 = per1.iter().sum::<f64>() / dof;
        let mut best = (t1 / thr1_ratio, per1);
        if pair_ok(windows, i) {
            let u = &windows[i - 1];
            let per2: [f64; CHANNELS] =
                std::array::from_fn(|c| (w.mean[c] - u.mean[c]).powi(2) / var_d[c]);
            let t2: f64 = per2.iter().sum();
            if t2 / thr2 > best.0 {
                best = (t2 / thr2, per2);
            }
            if t2 > thr2 {
                flagged[i - 1] = true;
            }
        }
        if best.0 > 1.0 {
            flagged[i] = true;
        }
        score[i] = best;
    }
    for i in (0..nw).filter(|&i| flagged[i]) {
        let lo = i.saturating_sub(cfg.guard_windows);
        let hi = (i + cfg.guard_windows).min(nw - 1);
        for s in &mut out.still[lo..=hi] {
            *s = false;
        }
    }
    out.motion = motion_reports(
        run,
        windows,
        &flagged,
        &score,
        &out.still,
        cfg.guard_windows,
        &out.sigma2,
    );
    out
}

/// The output resolution of channel `c` (rad/s or m/s²): the median over the windows of their
/// smallest non-zero sample difference, 0 when no window has one. On a quantised output this is
/// one quantum over the sample interval (a scale or bias correction applied in floating point
/// keeps the steps at one corrected quantum); on a continuous one it is a small fraction of the
/// noise, and the floor it sets is negligible.
fn resolution(full: &[&Window], c: usize) -> f64 {
    let steps: Vec<f64> = full
        .iter()
        .map(|w| w.resolution[c])
        .filter(|r| r.is_finite())
        .collect();
    quantile(&steps, 0.5)
}

/// Whether windows `i - 1` and `i` are both full candidates (a change between them is tested).
fn pair_ok(windows: &[Window], i: usize) -> bool {
    i > 0
        && windows[i].candidate
        && windows[i].n >= 4
        && windows[i - 1].candidate
        && windows[i - 1].n >= 4
}

/// The `q` quantile of `v` (nearest rank; 0 for an empty slice).
fn quantile(v: &[f64], q: f64) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s.get(((s.len() as f64 - 1.0) * q).round().max(0.0) as usize)
        .copied()
        .unwrap_or(0.0)
}

/// Merge flagged windows (and their guards) into motion stretches.
fn motion_reports(
    run: &str,
    windows: &[Window],
    flagged: &[bool],
    score: &[(f64, [f64; CHANNELS])],
    still: &[bool],
    guard: usize,
    sigma2: &[f64; CHANNELS],
) -> Vec<MotionReport> {
    let median_still: [f64; CHANNELS] = std::array::from_fn(|c| {
        let mut v: Vec<f64> = windows
            .iter()
            .zip(still)
            .filter(|(_, s)| **s)
            .map(|(w, _)| w.mean[c])
            .collect();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(0.0)
    });
    let flagged_at: Vec<usize> = (0..windows.len()).filter(|&i| flagged[i]).collect();
    let mut out: Vec<MotionReport> = Vec::new();
    let mut k = 0;
    while k < flagged_at.len() {
        // Flags closer than two guards belong to one stretch of motion.
        let start = flagged_at[k];
        let mut end = start;
        while k + 1 < flagged_at.len() && flagged_at[k + 1] <= end + 2 * guard + 1 {
            k += 1;
            end = flagged_at[k];
        }
        k += 1;
        let mut per = [0.0; CHANNELS];
        let mut excess: f64 = 0.0;
        for s in &score[start..=end] {
            excess = excess.max(s.0);
            for c in 0..CHANNELS {
                per[c] += s.1[c];
            }
        }
        let c = (0..CHANNELS).fold(0, |b, c| if per[c] > per[b] { c } else { b });
        let size = windows[start..=end]
            .iter()
            .fold(0.0f64, |m, w| m.max((w.mean[c] - median_still[c]).abs()));
        let dt = window_step(windows);
        let (mut cum, mut excursion) = (0.0f64, 0.0f64);
        for w in &windows[start..=end] {
            cum += (w.mean[c] - median_still[c]) * w.n as f64 * dt;
            excursion = excursion.max(cum.abs());
        }
        let vibration = windows[start..=end].iter().fold(0.0f64, |m, w| {
            let var = w.ss[c] / (w.n as f64 - 1.0).max(1.0);
            m.max((var - sigma2[c]).max(0.0).sqrt())
        });
        let last = &windows[end];
        out.push(MotionReport {
            run: run.to_string(),
            start_s: windows[start].start_s,
            end_s: last.start_s + last.n as f64 * window_step(windows),
            channel: CHANNEL_NAMES[c].to_string(),
            size,
            vibration,
            excursion,
            excess,
        });
    }
    out
}

/// The sample interval implied by the windows (s).
fn window_step(windows: &[Window]) -> f64 {
    windows
        .windows(2)
        .find(|p| p[0].n > 0 && p[1].start_s > p[0].start_s)
        .map_or(0.0, |p| (p[1].start_s - p[0].start_s) / p[0].n as f64)
}
