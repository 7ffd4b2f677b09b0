//! The entry point: read the runs' stationary stretches, pool their Allan variances, fit the
//! twin's noise terms.

use crate::accumulate::{Accumulator, CHANNEL_NAMES, CHANNELS, StretchStats};
use crate::allan::{PooledTau, chi2_interval};
use crate::config::NoiseIdConfig;
use crate::error::NoiseIdError;
use crate::fit::{FitData, Point, ProfiledFit, fit_profiled};
use crate::homogeneity::{self, Heterogeneity};
use crate::model::{TERMS, Term};
use crate::quant::ramp_quantization_avar;
use crate::result::{
    AllanCurve, Estimate, IdentifiedNoise, RunUsage, SensorNoise, StretchReport, instability_of,
};
use crate::turnon::{self, ChannelNoise, FittedNoise};
use sins_diag::chi2_sf;
use sins_diag::source::SampleSource;
use sins_imu::{Compensator, ImuErrorParams};
use sins_nav::alignment::coarse_align;
use sins_nav::earth::{earth_rate_ned_radps, normal_gravity_mps2};
use sins_nav::{Geodetic, Vec3};

/// One run's input: its samples, segment labels and site.
pub struct RunStationary<'a> {
    /// Run name (for messages and the per-run figures).
    pub name: String,
    /// The raw samples (read once, in batches).
    pub source: &'a mut dyn SampleSource,
    /// The run's segment labels (the source's segment indices point into this list).
    pub segment_labels: Vec<String>,
    /// The turntable site (for the Earth-rate and gravity check of each stretch).
    pub site: Geodetic,
    /// The calibrated parameter set, if known: the accelerometer increments are compensated
    /// with it (bias, scale, misalignment and the temperature terms of a 42-state set) before
    /// the Allan variance, so that the chamber's temperature drift does not pass for bias
    /// instability. The gyro increments stay raw: their model has no temperature term, its
    /// constant terms cancel in the second differences, and the quantum is read from the raw
    /// count lattice.
    pub compensation: Option<ImuErrorParams>,
}

/// The Gauss-Markov correlation-time grid ends at this multiple of the longest `τ` fitted.
pub const CORRELATION_CAP: f64 = 4.0;

/// Identify the sensor noise from the stationary stretches of `runs` (one pass over each run).
///
/// Stationary stretches are the contiguous samples whose segment label is in
/// [`NoiseIdConfig::labels`]. The Allan variance needs no removal of the Earth rate and
/// gravity: a constant rate cancels exactly in its second differences (each stretch's first
/// sample is subtracted only for numerical conditioning). Each stretch's mean is instead
/// compared with the Earth rate and gravity at the site in the stretch's own TRIAD attitude
/// ([`StretchReport`]). Results are bit-identical for the same input.
///
/// When the still stretches disagree and the chunks that stand out are each the first of their
/// run (a turn-on transient, [`crate::homogeneity`]), and [`NoiseIdConfig::leave_out_turn_on`]
/// is set, the identification is made again with that time at the start of every run left out,
/// and says so ([`IdentifiedNoise::turn_on_left_out_s`]).
pub fn identify_noise(
    runs: &mut [RunStationary<'_>],
    cfg: &NoiseIdConfig,
) -> Result<IdentifiedNoise, NoiseIdError> {
    let (first, mut turn_on_s) = identify_pass(runs, cfg, 0.0)?;
    if !cfg.leave_out_turn_on {
        return Ok(first);
    }
    let found: Vec<String> = first
        .inconsistent
        .iter()
        .filter(|r| r.contains(homogeneity::TURN_ON_TEXT) || r.contains(turnon::TRANSIENT_TEXT))
        .cloned()
        .collect();
    // Leave out the chunk that stood out and test again: a transient longer than a chunk shows
    // in the next one (at most MAX_TURN_ON_PASSES passes in all).
    let mut best: Option<(IdentifiedNoise, f64)> = None;
    for _ in 1..MAX_TURN_ON_PASSES {
        let Some(skip_s) = turn_on_s else { break };
        // Too little still data after it: keep what the last pass found.
        let Ok((again, next)) = identify_pass(runs, cfg, skip_s) else {
            break;
        };
        best = Some((again, skip_s));
        turn_on_s = next.filter(|&n| n > skip_s);
    }
    let Some((mut id, skip_s)) = best else {
        return Ok(first);
    };
    id.notes.insert(
        0,
        format!(
            "turn-on transient: the first {skip_s:.0} s of every run are left out of the \
             identification (a first pass over all the data found: {})",
            found.join("; ")
        ),
    );
    id.turn_on_left_out_s = skip_s;
    Ok(id)
}

/// Passes over the data at most when a turn-on transient is left out step by step.
const MAX_TURN_ON_PASSES: usize = 4;

/// One identification, with the first `skip_s` of every run left out; also the time to leave
/// out for a turn-on transient, when the still stretches show one.
fn identify_pass(
    runs: &mut [RunStationary<'_>],
    cfg: &NoiseIdConfig,
    skip_s: f64,
) -> Result<(IdentifiedNoise, Option<f64>), NoiseIdError> {
    cfg.validate()?;
    let Some(first) = runs.first() else {
        return Err(NoiseIdError::NotEnoughData("no run given".into()));
    };
    let h_s = first.source.sample_interval_s();
    for r in runs.iter() {
        let h = r.source.sample_interval_s();
        if !(h > 0.0 && h.is_finite()) || (h / h_s - 1.0).abs() > 1e-9 {
            return Err(NoiseIdError::Run {
                run: r.name.clone(),
                reason: format!(
                    "sample interval {h} s differs from the first run's {h_s} s (pooled Allan variances need one rate)"
                ),
            });
        }
    }
    let mut acc = Accumulator::new(h_s, cfg.min_stretch_s);
    let mut motion = Vec::new();
    let mut unjudged = Vec::new();
    let mut first_t_s = Vec::new();
    for (i, r) in runs.iter_mut().enumerate() {
        // A run without labels is searched whole; a labelled run only in its still labels.
        let unlabelled = r.segment_labels.is_empty();
        let keep: Vec<bool> = r
            .segment_labels
            .iter()
            .map(|l| cfg.labels.iter().any(|k| k == l))
            .collect();
        let candidate = |g: u16| unlabelled || keep.get(usize::from(g)).copied().unwrap_or(false);
        let found = find_still(r, h_s, &candidate, &cfg.stillness)?;
        if !found.judged {
            unjudged.push(r.name.clone());
        }
        let comp = match &r.compensation {
            Some(p) => Some(Compensator::new(*p).ok_or_else(|| NoiseIdError::Run {
                run: r.name.clone(),
                reason: "the compensation parameter set is singular".into(),
            })?),
            None => None,
        };
        let mut cursor = WindowCursor::default();
        let mut t0 = None;
        r.source.visit(&mut |samples, segs| {
            for (s, g) in samples.iter().zip(segs) {
                let started = *t0.get_or_insert(s.t_s);
                let stationary = candidate(*g) && cursor.still(&found) && s.t_s - started >= skip_s;
                match &comp {
                    Some(c) if stationary => {
                        let mut compensated = *s;
                        compensated.dv_mps = c.dv_mps(&s.dv_mps, h_s, &s.temp_degc);
                        acc.push(i, &compensated, s, true);
                    }
                    _ => acc.push(i, s, s, stationary),
                }
            }
            Ok(())
        })?;
        acc.close();
        first_t_s.push(t0.unwrap_or(0.0));
        motion.extend(found.stillness.motion);
    }
    if acc.stretches.is_empty() {
        return Err(NoiseIdError::NotEnoughData(format!(
            "no still stretch of at least {} s in any run (searched: the segments labelled {}, \
             or the whole run where it has no labels; {} stretch(es) of motion found)",
            cfg.min_stretch_s,
            cfg.labels.join(" or "),
            motion.len()
        )));
    }
    let longest_s = acc
        .stretches
        .iter()
        .map(|s| s.samples as f64 * h_s)
        .fold(0.0, f64::max);
    let max_tau_s = cfg.max_tau_fraction * longest_s;
    let taus: Vec<&[PooledTau; CHANNELS]> = acc
        .pooled
        .values()
        .filter(|p| p[0].tau_s <= max_tau_s * (1.0 + 1e-9) && p[0].count > 0)
        .collect();
    if taus.len() < 4 {
        return Err(NoiseIdError::NotEnoughData(format!(
            "only {} averaging times up to {max_tau_s:.1} s (longest stretch {longest_s:.1} s)",
            taus.len()
        )));
    }
    // A correlation time beyond a few times the longest averaging time cannot be told from a
    // rate random walk (σ² and T then trade along K² = 2σ²/T): the profile stops there.
    let tau_top = taus.last().map_or(0.0, |p| p[0].tau_s);
    let t_cap = CORRELATION_CAP * tau_top;
    let mut grid: Vec<f64> = cfg
        .correlation_grid()
        .into_iter()
        .filter(|&t| t < t_cap)
        .collect();
    if cfg.correlation_grid_s[1] >= t_cap {
        grid.push(t_cap);
    }
    let ctx = FitContext {
        taus: &taus,
        stretches: &acc.stretches,
        grid,
        rrw: cfg.fit_rate_random_walk,
        h_s,
    };
    // A partial lattice still gives the quantization's size (and is reported as inconsistent).
    let lattice = |channel0: usize| -> Option<[f64; 3]> {
        let q: [Option<f64>; 3] = std::array::from_fn(|a| {
            let l = &acc.lattice[channel0 + a];
            l.quantum().or_else(|| l.partial_quantum())
        });
        match q {
            [Some(a), Some(b), Some(c)] => Some([a, b, c]),
            _ => None,
        }
    };
    let (gyro_q, accel_q) = (lattice(0), lattice(3));
    let gyro = ctx.fit_quantised(0, gyro_q);
    // An accelerometer's quantum is not an offset: a pulse-counting one carries the remainder
    // (white phase, the ramp model), one that rounds each sample does not (white rate, part of
    // the random walk); its free white-phase term holds whichever the data show.
    let accel = ctx.fit_quantised(3, None);
    let mut notes = Vec::new();
    let compensated: Vec<&str> = runs
        .iter()
        .filter(|r| r.compensation.is_some())
        .map(|r| r.name.as_str())
        .collect();
    notes.push(if compensated.is_empty() {
        "accelerometer increments raw (no calibrated set given): a temperature drift of the bias \
         during a stretch adds to the bias instability"
            .to_string()
    } else {
        format!(
            "accelerometer increments compensated with the calibrated set (temperature terms \
             included) in {}",
            compensated.join(", ")
        )
    });
    let axes = |fits: &TriadFits, q: Option<[f64; 3]>, gyro: bool| -> Vec<SensorNoise> {
        (0..3)
            .map(|a| fits.axes[a].summary(q.map(|q| q[a]), gyro))
            .collect()
    };
    let mean = |q: Option<[f64; 3]>| q.map(|q| (q[0] + q[1] + q[2]) / 3.0);
    let mut gyro_axes = axes(&gyro, gyro_q, true);
    let mut accel_axes = axes(&accel, accel_q, false);
    let mut gyro_sum = gyro.triad.summary(mean(gyro_q), true);
    let mut accel_sum = accel.triad.summary(mean(accel_q), false);
    if ctx.rrw {
        // The rate random walk from an extended fit (the twin's terms plus K): at the lengths of
        // these runs it is nearly degenerate with a Gauss-Markov bias of long correlation, so
        // the twin's terms come from the fit without it.
        let offsets =
            |f: &TriadFits| -> [Vec<f64>; 3] { std::array::from_fn(|a| f.axes[a].offsets.clone()) };
        let gyro_offsets = offsets(&gyro);
        let with = |on: [bool; 4]| [on[0], true, true, true];
        let g = ctx.fit_triad(0, gyro_q.map(|_| &gyro_offsets), with(gyro.triad.enabled));
        let a = ctx.fit_triad(3, None, with(accel.triad.enabled));
        for (fits, sum, axes) in [
            (&g, &mut gyro_sum, &mut gyro_axes),
            (&a, &mut accel_sum, &mut accel_axes),
        ] {
            sum.rate_random_walk_per_sqrt_s = fits.triad.rate_random_walk();
            for (k, ax) in axes.iter_mut().enumerate() {
                ax.rate_random_walk_per_sqrt_s = fits.axes[k].rate_random_walk();
            }
        }
    }
    for (name, s) in [("gyro", &gyro_sum), ("accelerometer", &accel_sum)] {
        if s.bias_sigma.value > 0.0 && !s.bias_correlation_s.sigma.is_finite() {
            notes.push(format!(
                "{name} Gauss-Markov correlation time not identified: the profile has no interior minimum between {:.0} s and {:.0} s ({CORRELATION_CAP} x the longest tau); {:.0} s is used, and only K^2 = 2 sigma^2/T is determined (a longer true correlation time gives a larger sigma)",
                cfg.correlation_grid_s[0], t_cap.min(cfg.correlation_grid_s[1]), s.bias_correlation_s.value
            ));
        }
        if s.bias_sigma.value == 0.0 {
            notes.push(format!(
                "{name} Gauss-Markov bias not above zero; 95 % upper bound of sigma given"
            ));
        }
    }
    let mut inconsistent = lattice_findings(&acc, &mut notes);
    let mut curves = Vec::new();
    for c in 0..CHANNELS {
        let (set, a) = if c < 3 { (&gyro, c) } else { (&accel, c - 3) };
        curves.push(ctx.curve(c, &set.axes[a], &set.triad, a, cfg.coverage));
    }
    inconsistent.extend(curves.iter().filter_map(model_check));
    let mut turn_on_s: Option<f64> = None;
    let quanta: [Option<f64>; CHANNELS] = std::array::from_fn(|c| {
        let q = if c < 3 { gyro_q } else { accel_q };
        q.map(|q| q[c % 3])
    });
    for h in homogeneity::test(&acc.chunks, acc.tau0_s(), &quanta) {
        let text = heterogeneity_text(&h, runs);
        if h.finding {
            inconsistent.push(text.clone());
            if h.at_turn_on {
                let (run, start_s, len_s, _) = h.worst;
                let end_s = start_s + len_s - first_t_s.get(run).copied().unwrap_or(0.0);
                turn_on_s = Some(turn_on_s.map_or(end_s, |t| t.max(end_s)).ceil());
            }
        }
        notes.push(text);
    }
    // The turn-on test's null: the channel's own fit, its triad's pooled fit, and what their
    // uncertainties allow.
    let nulls: [Vec<ChannelNoise>; CHANNELS] = std::array::from_fn(|c| {
        let (axis, triad) = if c < 3 {
            (&gyro.axes[c], &gyro.triad)
        } else {
            (&accel.axes[c - 3], &accel.triad)
        };
        turnon::plausible_nulls(&[fitted_noise(axis), fitted_noise(triad)])
    });
    let mut openings = std::mem::take(&mut acc.openings);
    for o in &mut openings {
        o.offset_s -= first_t_s.get(o.run).copied().unwrap_or(0.0) - h_s;
    }
    for t in turnon::test(&openings, &nulls) {
        let name = |r: usize| runs.get(r).map_or_else(|| "?".into(), |x| x.name.clone());
        let text = turnon::text(&t, &name);
        inconsistent.push(text.clone());
        notes.push(text);
        let end_s = t.leave_out_s.ceil();
        turn_on_s = Some(turn_on_s.map_or(end_s, |s| s.max(end_s)));
    }
    let runs_out = runs
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let used: Vec<&StretchStats> = acc.stretches.iter().filter(|s| s.run == i).collect();
            RunUsage {
                name: r.name.clone(),
                stationary_s: used.iter().map(|s| s.samples as f64 * h_s).sum(),
                stretches: used.len(),
                skipped: acc.skipped.iter().filter(|s| s.0 == i).count(),
            }
        })
        .collect();
    let stretches = acc
        .stretches
        .iter()
        .map(|s| stretch_report(s, &runs[s.run], h_s))
        .collect();
    for m in &motion {
        notes.push(format!(
            "motion in {} at {:.1}-{:.1} s: {} left its still level by {}, vibration {} RMS \
             (detector statistic {:.1} x its threshold); left out",
            m.run,
            m.start_s,
            m.end_s,
            m.channel,
            motion_size_text(&m.channel, m.size),
            motion_size_text(&m.channel, m.vibration),
            m.excess
        ));
    }
    if !unjudged.is_empty() {
        notes.push(format!(
            "stillness not checked in {}: fewer than 20 one-second windows to estimate the \
             white noise from",
            unjudged.join(", ")
        ));
    }
    let mut id = IdentifiedNoise {
        gyro: gyro_sum,
        accel: accel_sum,
        gyro_axes,
        accel_axes,
        curves,
        runs: runs_out,
        stretches,
        motion,
        inconsistent,
        sample_interval_s: h_s,
        turn_on_left_out_s: skip_s,
        notes,
    };
    id.notes.extend(id.change_notes());
    Ok((id, turn_on_s))
}

/// A fit's white noise and Gauss-Markov bias with their uncertainty, for the turn-on test.
fn fitted_noise(f: &Fitted) -> FittedNoise {
    let (th, sd) = (f.fit.fit.theta, f.fit.fit.sigma);
    FittedNoise {
        noise: ChannelNoise {
            white: th[1].max(0.0).sqrt(),
            gm_sigma: th[2].max(0.0).sqrt(),
            gm_correlation_s: f.fit.correlation_s,
        },
        gm_var_sigma: sd[2],
        gm_var_upper95: f.fit.fit.upper95[2],
        ln_t_sigma: f.fit.ln_correlation_sigma,
    }
}

fn stretch_report(s: &StretchStats, run: &RunStationary<'_>, h_s: f64) -> StretchReport {
    let w = Vec3::new(s.mean_rate[0], s.mean_rate[1], s.mean_rate[2]);
    let f = Vec3::new(s.mean_rate[3], s.mean_rate[4], s.mean_rate[5]);
    let (gyro, accel) = match coarse_align(&f, &w) {
        Ok(q) => {
            let inv = q.inverse();
            let lat = run.site.lat_rad;
            let wp = inv * earth_rate_ned_radps(lat);
            let fp = inv * Vec3::new(0.0, 0.0, -normal_gravity_mps2(lat, run.site.height_m));
            let d = |a: Vec3, b: Vec3| [a.x - b.x, a.y - b.y, a.z - b.z];
            (Some(d(w, wp)), Some(d(f, fp)))
        }
        Err(_) => (None, None),
    };
    StretchReport {
        run: run.name.clone(),
        start_s: s.start_s,
        duration_s: s.samples as f64 * h_s,
        gyro_residual_radps: gyro,
        accel_residual_mps2: accel,
        changes: s.changes.clone(),
    }
}

/// A fit of one axis or a triad, with the offsets it used.
struct Fitted {
    fit: ProfiledFit,
    offsets: Vec<f64>,
    enabled: [bool; 4],
}

struct TriadFits {
    triad: Fitted,
    axes: Vec<Fitted>,
}

struct FitContext<'a> {
    taus: &'a [&'a [PooledTau; CHANNELS]],
    stretches: &'a [StretchStats],
    grid: Vec<f64>,
    rrw: bool,
    h_s: f64,
}

impl FitContext<'_> {
    fn points(&self, channel: usize, offsets: &[f64], block: usize) -> Vec<Point<'_>> {
        self.taus
            .iter()
            .zip(offsets)
            .filter_map(|(p, &off)| {
                let pt = &p[channel];
                pt.avar().map(|avar| Point {
                    tau_s: pt.tau_s,
                    avar,
                    offset: off,
                    block,
                    pooled: pt,
                })
            })
            .collect()
    }

    /// Fit the triad starting at `channel0` jointly and each axis alone; `quantum_offsets`
    /// computes a known offset per axis and `τ` from the current triad fit.
    fn fit_triad(
        &self,
        channel0: usize,
        offsets: Option<&[Vec<f64>; 3]>,
        enabled: [bool; 4],
    ) -> TriadFits {
        let zero = vec![0.0; self.taus.len()];
        let off = |a: usize| offsets.map_or(zero.clone(), |o| o[a].clone());
        let axes = (0..3)
            .map(|a| {
                let o = off(a);
                let data = FitData::new(self.points(channel0 + a, &o, 0), self.h_s);
                Fitted {
                    fit: fit_profiled(&data, enabled, &self.grid),
                    offsets: o,
                    enabled,
                }
            })
            .collect();
        let mut all = Vec::new();
        let mut stacked = Vec::new();
        for a in 0..3 {
            let o = off(a);
            all.extend(self.points(channel0 + a, &o, a));
            stacked.extend(o);
        }
        let data = FitData::new(all, self.h_s);
        TriadFits {
            triad: Fitted {
                fit: fit_profiled(&data, enabled, &self.grid),
                offsets: stacked,
                enabled,
            },
            axes,
        }
    }

    /// The triad starting at `channel0`, with a free `3Q²/τ²` term (white angle or velocity
    /// noise: quantization, vibration, dither). With a detected lattice the quantization of a
    /// sensor at rest is also a known offset (the ramp model), refined twice with the fitted
    /// white noise and bias wander, and the free term is what the data hold beyond it.
    fn fit_quantised(&self, channel0: usize, lattice: Option<[f64; 3]>) -> TriadFits {
        let enabled = [true, true, true, false];
        let Some(q) = lattice else {
            return self.fit_triad(channel0, None, enabled);
        };
        let o = self.ramp_offsets(channel0, &q, 0.0, 0.0, 0.0);
        let mut fits = self.fit_triad(channel0, Some(&o), enabled);
        for _ in 0..2 {
            let th = fits.triad.fit.fit.theta;
            let o = self.ramp_offsets(channel0, &q, th[1].sqrt(), th[2].sqrt(), th[3].sqrt());
            fits = self.fit_triad(channel0, Some(&o), enabled);
        }
        fits
    }

    /// Each axis' expected quantization Allan variance at every `τ` (weighted over the stretches
    /// by their second differences), for quanta `q` of the triad at `channel0`.
    fn ramp_offsets(
        &self,
        channel0: usize,
        q: &[f64; 3],
        arw: f64,
        bias_sigma: f64,
        rrw: f64,
    ) -> [Vec<f64>; 3] {
        std::array::from_fn(|a| {
            self.taus
                .iter()
                .map(|p| {
                    let pt = &p[channel0 + a];
                    let (mut num, mut den) = (0.0, 0.0);
                    for &(idx, n, m) in &pt.stretches {
                        let Some(s) = self.stretches.get(idx) else {
                            continue;
                        };
                        let t_s = (s.samples as f64 * self.h_s).max(pt.tau_s);
                        let du = (bias_sigma.powi(2)
                            + rrw.powi(2) * t_s / 3.0
                            + q[a].powi(2) / (6.0 * t_s * t_s))
                            .sqrt();
                        let w = (n - 2 * m) as f64;
                        let rate = s.mean_rate[channel0 + a];
                        num += w * ramp_quantization_avar(q[a], rate, pt.tau_s, arw, du);
                        den += w;
                    }
                    if den > 0.0 { num / den } else { 0.0 }
                })
                .collect()
        })
    }

    fn curve(
        &self,
        channel: usize,
        axis: &Fitted,
        triad: &Fitted,
        a: usize,
        coverage: f64,
    ) -> AllanCurve {
        let n = self.taus.len();
        let pts = self.points(channel, &axis.offsets, 0);
        let mut c = AllanCurve {
            channel: CHANNEL_NAMES[channel].to_string(),
            tau_s: Vec::with_capacity(n),
            adev: Vec::with_capacity(n),
            lo: Vec::with_capacity(n),
            hi: Vec::with_capacity(n),
            edf: Vec::with_capacity(n),
            fit_axis: Vec::with_capacity(n),
            fit_triad: Vec::with_capacity(n),
        };
        let t = axis.fit.correlation_s;
        for (i, p) in pts.iter().enumerate() {
            let dom = dominant_term(&axis.fit.fit.theta, p.tau_s, t, p.offset);
            let nu = p.pooled.edf(dom.noise_type());
            let (lo, hi) = chi2_interval(p.avar, nu, coverage);
            c.tau_s.push(p.tau_s);
            c.adev.push(p.avar.sqrt());
            c.lo.push(lo.sqrt());
            c.hi.push(hi.sqrt());
            c.edf.push(nu);
            c.fit_axis.push(
                axis.fit
                    .fit
                    .model
                    .get(i)
                    .copied()
                    .unwrap_or(f64::NAN)
                    .sqrt(),
            );
            c.fit_triad.push(
                triad
                    .fit
                    .fit
                    .model
                    .get(a * n + i)
                    .copied()
                    .unwrap_or(f64::NAN)
                    .sqrt(),
            );
        }
        c
    }
}

fn dominant_term(theta: &[f64; 4], tau_s: f64, corr_s: f64, offset: f64) -> Term {
    let mut best = (Term::Quantization, offset);
    for (j, t) in TERMS.iter().enumerate() {
        let v = theta[j] * t.basis(tau_s, corr_s);
        if v > best.1 {
            best = (*t, v);
        }
    }
    best.0
}

impl Fitted {
    /// Physical term `j` (square root of `θ_j` times `scale`, 1-sigma by the delta method; a
    /// 95 % upper bound where it is zero).
    fn root(&self, j: usize, scale: f64) -> Estimate {
        let f = &self.fit.fit;
        let th = f.theta[j];
        if th > 0.0 {
            let v = th.sqrt();
            Estimate {
                value: scale * v,
                sigma: scale * f.sigma[j] / (2.0 * v),
                upper_95: None,
            }
        } else {
            Estimate {
                value: 0.0,
                sigma: 0.0,
                upper_95: f.upper95[j].map(|u| scale * u.max(0.0).sqrt()),
            }
        }
    }

    /// The fitted rate random walk (0 where the fit left it out).
    fn rate_random_walk(&self) -> Estimate {
        if self.enabled[3] {
            self.root(3, 1.0)
        } else {
            Estimate::exact(0.0)
        }
    }

    /// Physical terms; `lattice_quantum` the quantum read off the increments. The free
    /// `3Q²/τ²` term is a gyro's quantum when its increments are on no lattice (`gyro`), else
    /// [`SensorNoise::white_phase`].
    fn summary(&self, lattice_quantum: Option<f64>, gyro: bool) -> SensorNoise {
        let f = &self.fit.fit;
        let free = self.root(0, 12f64.sqrt());
        let (quantum, excess) = match lattice_quantum {
            Some(q) => (Estimate::exact(q), free),
            None if gyro => (free, Estimate::exact(0.0)),
            None => (Estimate::exact(0.0), free),
        };
        let root = |j: usize, scale: f64| self.root(j, scale);
        let bias_sigma = root(2, 1.0);
        let corr = if bias_sigma.value > 0.0 {
            Estimate {
                value: self.fit.correlation_s,
                sigma: self.fit.correlation_s * self.fit.ln_correlation_sigma,
                upper_95: None,
            }
        } else {
            Estimate::exact(f64::INFINITY)
        };
        let active = (0..4).filter(|&j| f.theta[j] > 0.0).count();
        SensorNoise {
            white_per_sqrt_s: root(1, 1.0),
            quantum,
            quantum_from_lattice: lattice_quantum.is_some(),
            white_phase: excess,
            bias_sigma,
            bias_instability: instability_of(bias_sigma),
            bias_correlation_s: corr,
            rate_random_walk_per_sqrt_s: self.rate_random_walk(),
            chi2: f.chi2,
            points: f.model.len(),
            parameters: active + usize::from(bias_sigma.value > 0.0),
        }
    }
}

/// A run's stillness: its windows and the detector's verdict.
struct FoundStill {
    windows: Vec<crate::still::Window>,
    stillness: crate::still::Stillness,
    judged: bool,
}

/// First pass over a run: the windows of its candidate samples and the detector's verdict.
fn find_still(
    r: &mut RunStationary<'_>,
    h_s: f64,
    candidate: &dyn Fn(u16) -> bool,
    cfg: &crate::still::StillnessConfig,
) -> Result<FoundStill, NoiseIdError> {
    let mut b = crate::still::WindowBuilder::new(h_s, cfg);
    r.source.visit(&mut |samples, segs| {
        for (s, g) in samples.iter().zip(segs) {
            b.push(s.t_s, crate::still::rates(s, h_s), candidate(*g));
        }
        Ok(())
    })?;
    b.close();
    let stillness = crate::still::detect(&r.name, &b.windows, cfg);
    Ok(FoundStill {
        judged: stillness.judged,
        windows: b.windows,
        stillness,
    })
}

/// Walks the windows of a run sample by sample in the second pass.
#[derive(Default)]
struct WindowCursor {
    sample: u64,
    window: usize,
}

impl WindowCursor {
    /// Whether the next sample lies in a still window (advances by one sample).
    fn still(&mut self, f: &FoundStill) -> bool {
        while self.window + 1 < f.windows.len()
            && f.windows[self.window + 1].first_sample <= self.sample
        {
            self.window += 1;
        }
        self.sample += 1;
        f.stillness.still.get(self.window).copied().unwrap_or(false)
    }
}

/// A motion size in the channel's reading unit (deg/h or deg/s for a gyro, ug or mg for an
/// accelerometer).
fn motion_size_text(channel: &str, size: f64) -> String {
    if channel.starts_with("gyro") {
        let deg_h = size.to_degrees() * 3600.0;
        if deg_h < 3600.0 {
            format!("{deg_h:.1} deg/h")
        } else {
            format!("{:.2} deg/s", deg_h / 3600.0)
        }
    } else {
        let ug = size / sins_nav::UG;
        if ug < 1e4 {
            format!("{ug:.0} ug")
        } else {
            format!("{:.1} mg", ug / 1e3)
        }
    }
}

/// How far the fitted model's Allan deviation may lie from the data's (a factor, either way)
/// before a significant difference counts against it. The residual chi-square of the fit is no
/// guide: with hours of data the points are resolved to a percent at short averaging times, and
/// a real sensor's flicker, which no term of the twin has, is significant there while the twin
/// is still a fair model.
pub const MODEL_CHECK_FACTOR: f64 = 1.5;

/// Family-wise probability that the model check fails a correct model (Bonferroni over the
/// six channels and each channel's averaging times).
pub const MODEL_CHECK_FALSE_ALARM: f64 = 1e-3;

/// A channel's fitted model against its own Allan deviation: `Some(reason)` when at some
/// averaging time the model and the data differ by more than [`MODEL_CHECK_FACTOR`] and
/// significantly: `ν σ²_data / σ²_model` is chi-square with the point's `ν` degrees of freedom
/// when the model is right, and its two-sided tail must be below the Bonferroni level. At the
/// longest averaging times (a few degrees of freedom) a factor of 2-3 is chance: 1.5 beyond a
/// one-sigma interval there flagged 7 of 100 quiet runs.
fn model_check(c: &AllanCurve) -> Option<String> {
    let level = MODEL_CHECK_FALSE_ALARM / (CHANNELS * c.tau_s.len().max(1)) as f64;
    let worst = c
        .tau_s
        .iter()
        .enumerate()
        .filter_map(|(k, &tau)| {
            let fit = *c.fit_axis.get(k)?;
            let (data, nu) = (*c.adev.get(k)?, *c.edf.get(k)?);
            if !(fit > 0.0 && data > 0.0 && nu > 0.0) {
                return None;
            }
            let x = nu * (data / fit).powi(2);
            let upper = chi2_sf(x, nu);
            let p = 2.0 * upper.min(1.0 - upper);
            let factor = (fit / data).max(data / fit);
            (p < level && factor > MODEL_CHECK_FACTOR).then_some((factor, tau, fit, data, p))
        })
        .fold(
            None,
            |best: Option<(f64, f64, f64, f64, f64)>, x| match best {
                Some(b) if b.0 >= x.0 => Some(b),
                _ => Some(x),
            },
        )?;
    Some(format!(
        "the fitted {} model misses the data's Allan deviation by a factor {:.2} at tau = {:.3} s \
         (model {:.3e}, data {:.3e}; p = {:.1e}): a process the model lacks (motion, a bias \
         change, a partial quantisation, a non-white noise) is in the data",
        c.channel, worst.0, worst.1, worst.2, worst.3, worst.4
    ))
}

/// A quantum in words: gyro in arcsec, accelerometer in mm/s.
fn quantum_text(channel: usize, q: f64) -> String {
    if channel < 3 {
        format!("{:.4} arcsec", q / sins_nav::ARCSEC)
    } else {
        format!("{:.4} mm/s", q * 1e3)
    }
}

/// Notes on each channel's lattice, and the reasons a partial lattice makes the model suspect.
fn lattice_findings(acc: &Accumulator, notes: &mut Vec<String>) -> Vec<String> {
    let mut out = Vec::new();
    for (c, l) in acc.lattice.iter().enumerate() {
        let Some(cov) = l.coverage() else { continue };
        if cov.holds() {
            continue;
        }
        let name = CHANNEL_NAMES[c];
        let on = 100.0 * cov.fraction_on();
        if on >= 50.0 {
            let text = format!(
                "{name}: {on:.1} % of the {} increments lie on a {} lattice and the rest off it: \
                 the output is quantised for only part of the data (corrected in floating point \
                 from some point on?); its quantum is kept for the quantization term (a \
                 correction in floating point keeps the rounding the output was given), and the \
                 model is marked inconsistent",
                cov.checked,
                quantum_text(c, cov.quantum)
            );
            notes.push(text.clone());
            out.push(text);
        } else if cov.multiples < 2 && cov.off == 0 {
            notes.push(format!(
                "{name}: every increment is the same multiple of {}: a lattice by chance (a \
                 smooth, noise-free output), not a quantum",
                quantum_text(c, cov.quantum)
            ));
        }
    }
    out
}

/// A difference between the still stretches in words.
fn heterogeneity_text(h: &Heterogeneity, runs: &[RunStationary<'_>]) -> String {
    let (run, start_s, len_s, ratio) = h.worst;
    let name = runs.get(run).map_or("?", |r| r.name.as_str());
    let level = if h.level == "white" {
        "white-noise"
    } else {
        "bias-instability"
    };
    let mut text = format!(
        "{}: the still stretches disagree at the {level} level (tau = {:.3} s; Bartlett \
         chi-square {:.1} on {} degrees of freedom, p = {:.1e}): {name} {:.0}-{:.0} s has {:.2} \
         x the Allan deviation of the other {} chunks",
        h.channel,
        h.tau_s,
        h.statistic,
        h.chunks - 1,
        h.p,
        start_s,
        start_s + len_s,
        ratio,
        h.chunks - 1
    );
    if h.at_turn_on {
        text.push_str("; ");
        text.push_str(homogeneity::TURN_ON_TEXT);
    }
    if !h.finding {
        text.push_str(&format!(
            " (within the factor {} the model tolerates)",
            homogeneity::FACTOR
        ));
    }
    text
}
