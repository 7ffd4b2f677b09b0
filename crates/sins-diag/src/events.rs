//! Effects local in time: a generalised likelihood ratio (GLR) scan over onset time for bias
//! steps, ramps and exponential transients on each of the six sensor axes, run by run, beside
//! the global tests.
//!
//! # Signals
//! After the start of navigation the error model is time-invariant, so the position response
//! to a unit bias on axis `b` switched on at `t_m` is `S_m(t) = H (X(t) − Φ(t − t_m) X(t_m))`
//! with `X` the response to a constant bias from the first sample (the sensitivity pass's
//! bias states, alignment included) and `Φ` the model's transition. Onsets lie on a grid of
//! spacing `Δ` from the start of navigation; the other shapes are sums of steps:
//! - ramp of unit rate from `t_m`: `R_m = R_{m+1} + Δ (S_m + S_{m+1}) / 2` (trapezoid);
//! - transient `e^{−(t − t_m)/τ}` (interval means `c d^k`, `d = e^{−Δ/τ}`,
//!   `c = τ (1 − d)/Δ`): `T_m = c U_m`, `U_m = S_m − S_{m+1} + d U_{m+1}`;
//! - pulse of unit level and duration `nΔ`: `P_m = S_m − S_{m+n}`;
//! - ramp to a plateau of unit level, rising over `nΔ`: `L_m = (R_m − R_{m+n}) / (nΔ)`, kept as
//!   a running window of the trapezoid's terms (`W_m = W_{m+1} + Δ (S_m + S_{m+1})/2 −
//!   Δ (S_{m+n} + S_{m+n+1})/2`); a pulse or plateau that would end after the last fit time is
//!   the step or the ramp already tested, and is not tested again;
//! - turn-on transient (onset at the first sample, inside the alignment): the sensitivity pass
//!   propagates `e^{−(t − t_0)/τ}` through the alignment replica to the first onset `t_1`
//!   (state `Y_τ`); from there the error is carried by the model and the rest of the transient
//!   acts as one with onset `t_1`: `H Φ(t − t_1) Y_τ + c b_1 U_1`, `b_1 = e^{−(t_1 − t_0)/τ}`.
//!   A level accelerometer's transient that decays inside the alignment thereby leaves the
//!   tilt the alignment's gains give it, not the tilt of its mean.
//!
//! # Test
//! Every signal is whitened with the run's own covariance (twin noise, the floor, the
//! calibration uncertainty, and a fitted random walk when a walk won), the catalogue winner's
//! columns are projected out, and `T = (ŝᵀ r̂)² / ŝᵀŝ` is computed against the residual `r̂` of
//! the winner's fit: one degree of freedom per signal, `χ²(1)` under the null (at most: the
//! floor is a tolerance larger than the white error the data carry). The family of tests is
//! every onset, shape and axis of every run; a Bonferroni correction over that count keeps the
//! family-wise false-alarm rate below `alpha` (conservative: neighbouring onsets are strongly
//! correlated). The strongest significant signal of a run is an event; it joins the nuisance
//! columns and the run is scanned again, up to `max_events_per_run`. An event is *explained*
//! by a deterministic catalogue candidate when the gap less that candidate's fit (one magnitude
//! for every run) leaves it insignificant.
//!
//! A pulse's duration and a plateau's rise time are then refitted on the whole grid from half
//! to twice the scanned one (see `duration`), and the onset's profile is the best `T` over
//! them. The onset's three-sigma interval holds the contiguous onsets whose `T` is within 9 of
//! the maximum (profile likelihood); its one-sigma is a third of the interval's larger side, at
//! least the grid's `Δ/√12`. The detectable level of a shape
//! at an onset is the magnitude detected with 90 % probability at the corrected level:
//! `(√T_thr + 1.2816)/√(ŝᵀŝ)`.
//!
//! The scan's settings and shapes are in `config`, what it reports in `report` (both
//! re-exported here); this module and `found` and `duration` hold the numerics.

use crate::error::DiagError;
use crate::model::{Mat7, R_E, R_N, Vec7};
use crate::parallel::par_map;
use crate::problem::RunFitData;
use crate::sensitivity::RunSensitivity;
use crate::stats::chi2_isf;
use crate::whiten::{Nuisance, RunWhitener};
use nalgebra::{DMatrix, DVector};

mod config;
mod duration;
mod found;
mod report;
pub use config::{AXES, EventScanConfig, Shape};
use found::{best, detectable_curves, event};
pub use report::{ChannelAlternative, DetectableCurve, EventScan, TimeLocalEvent};

/// One run's data for the scan.
pub struct ScanRun<'a> {
    /// Sensitivities (bias states, times, model).
    pub sens: &'a RunSensitivity,
    /// Fit data (gap, covariance, calibration responses, candidate columns).
    pub fit: &'a RunFitData,
    /// The residual the scan tests: the gap less the winner's fit (fit rows).
    pub residual: DVector<f64>,
    /// Winner columns of the run (fit rows), projected out.
    pub nuisance: DMatrix<f64>,
    /// Extra covariance (a fitted random walk), if any.
    pub extra_cov: Option<DMatrix<f64>>,
    /// Deterministic catalogue candidates: name and their fitted contribution to the run's gap
    /// (fit rows; one magnitude fitted to every run, as the catalogue's fit does).
    pub candidates: Vec<(String, DVector<f64>)>,
}

/// The step signals of one bias axis at every onset of the grid (fit rows × onsets).
fn step_signals(s: &RunSensitivity, axis: usize, onsets: &[usize], phis: &[Mat7]) -> DMatrix<f64> {
    let fit = &s.times.fit_index;
    let x = &s.bias_states[axis];
    let rows = 2 * fit.len();
    let every = phis.len() - 1;
    let mut out = DMatrix::zeros(rows, onsets.len());
    for (j, &m) in onsets.iter().enumerate() {
        let first = fit.partition_point(|&k| k <= m);
        let Some(&k0) = fit.get(first) else { continue };
        let mut carry: Vec7 = phis[(k0 - m).min(every)] * x[m];
        let mut prev = k0;
        for (i, &k) in fit.iter().enumerate().skip(first) {
            if k != prev {
                carry = phis[(k - prev).min(every)] * carry;
                prev = k;
            }
            let d = x[k] - carry;
            out[(2 * i, j)] = d[R_N];
            out[(2 * i + 1, j)] = d[R_E];
        }
    }
    out
}

/// `H Φ(t − t_1) y` on the fit rows: the position error carried by the model from state `y`
/// at the first output time (index 0; zero before it).
fn carried(s: &RunSensitivity, y: &Vec7, phis: &[Mat7]) -> DVector<f64> {
    let fit = &s.times.fit_index;
    let every = phis.len() - 1;
    let mut out = DVector::zeros(2 * fit.len());
    let (mut carry, mut prev) = (*y, 0);
    for (i, &k) in fit.iter().enumerate() {
        if k != prev {
            carry = phis[(k - prev).min(every)] * carry;
            prev = k;
        }
        out[2 * i] = carry[R_N];
        out[2 * i + 1] = carry[R_E];
    }
    out
}

/// One axis of a run: whitened step signals at every onset and the whitened constant-bias
/// signal; the other shapes are generated from them on the fly (see [`AxisSignals::visit`]).
pub(crate) struct AxisSignals {
    pub(crate) axis: usize,
    pub(crate) steps: DMatrix<f64>,
    /// Whitened `H Φ(t − t_1) Y_τ` of each turn-on time constant.
    turn_on: Vec<DVector<f64>>,
}

/// One signal handed to a visitor: its shape, onset index into the grid (0 for turn-on) and
/// the whitened vector.
pub(crate) type Visitor<'a> = dyn FnMut(Shape, usize, &DVector<f64>) + 'a;

impl AxisSignals {
    /// Every signal of the axis: steps, ramps, transients, pulses and plateaus at each onset
    /// (last onset first), then the turn-on transients.
    pub(crate) fn visit(
        &self,
        onset_s: &[f64],
        start_s: f64,
        cfg: &EventScanConfig,
        f: &mut Visitor<'_>,
    ) {
        let (rows, k) = (self.steps.nrows(), self.steps.ncols());
        let dt = cfg.onset_every_s as f64;
        let zero = DVector::zeros(rows);
        let col = |m: usize| {
            if m < k {
                self.steps.column(m).into_owned()
            } else {
                zero.clone()
            }
        };
        let taus = &cfg.time_constants_s;
        let decay: Vec<(f64, f64)> = taus
            .iter()
            .map(|&tau| {
                let d = (-dt / tau).exp();
                (d, tau * (1.0 - d) / dt)
            })
            .collect();
        let mut ramp = zero.clone();
        let mut u: Vec<DVector<f64>> = vec![zero.clone(); taus.len()];
        let mut next = zero.clone();
        let pulses = cfg.pulse_steps();
        let rises = cfg.plateau_steps();
        let mut window: Vec<DVector<f64>> = vec![zero.clone(); rises.len()];
        for m in (0..k).rev() {
            let here = col(m);
            f(Shape::Step, m, &here);
            ramp += (&here + &next) * (0.5 * dt);
            f(Shape::Ramp, m, &ramp);
            for (i, &(d, c)) in decay.iter().enumerate() {
                u[i] = &here - &next + &u[i] * d;
                let tau_s = taus[i];
                f(
                    Shape::Transient {
                        tau_s,
                        turn_on: false,
                    },
                    m,
                    &(&u[i] * c),
                );
            }
            for &n in &pulses {
                if m + n < k {
                    let duration_s = n as f64 * dt;
                    f(Shape::Pulse { duration_s }, m, &(&here - col(m + n)));
                }
            }
            for (w, &n) in window.iter_mut().zip(&rises) {
                *w += (&here + &next - col(m + n) - col(m + n + 1)) * (0.5 * dt);
                if m + n < k {
                    let rise_s = n as f64 * dt;
                    f(Shape::Plateau { rise_s }, m, &(&*w / rise_s));
                }
            }
            next = here;
        }
        if k == 0 {
            return;
        }
        // Turn-on: the alignment's share carried from the first onset, the rest from there.
        let t_1 = onset_s.first().map_or(0.0, |t| t - start_s).max(0.0);
        for (i, &tau_s) in taus.iter().enumerate() {
            let b_1 = (-t_1 / tau_s).exp();
            let on = &self.turn_on[i] + &u[i] * (decay[i].1 * b_1);
            f(
                Shape::Transient {
                    tau_s,
                    turn_on: true,
                },
                0,
                &on,
            );
        }
    }
}

/// Everything prepared for one run.
pub(crate) struct Prepared {
    /// A fingerprint of the covariance the run was whitened with.
    cov_key: [f64; 2],
    pub(crate) run: String,
    pub(crate) whitener: RunWhitener,
    pub(crate) start_s: f64,
    pub(crate) onset_s: Vec<f64>,
    pub(crate) axes: Vec<AxisSignals>,
    pub(crate) residual: DVector<f64>,
    nuisance: Vec<DVector<f64>>,
    candidates: Vec<(String, DVector<f64>)>,
}

impl Prepared {
    fn onset_of(&self, shape: Shape, m: usize) -> f64 {
        match shape {
            Shape::Transient { turn_on: true, .. } => self.start_s,
            _ => self.onset_s[m],
        }
    }
}

/// The run's covariance on its fit rows: twin noise and floor, calibration uncertainty, the
/// run's extra term (a fitted walk) and `extra`.
fn run_covariance(r: &ScanRun<'_>, extra: Option<&DMatrix<f64>>) -> DMatrix<f64> {
    let mut cov = &r.fit.cov + &r.fit.params * r.fit.params.transpose();
    for e in r.extra_cov.iter().chain(extra) {
        cov += e;
    }
    cov
}

/// The onset grid of a run: output interval (s), grid step in output points, and the onsets
/// (output indices from the start of navigation to the last fit time).
fn onset_grid(
    s: &RunSensitivity,
    cfg: &EventScanConfig,
) -> Result<(f64, usize, Vec<usize>), DiagError> {
    let out_dt = match s.times.times_s.as_slice() {
        [a, b, ..] => b - a,
        _ => return Err(DiagError::input(&s.run, "fewer than two output times")),
    };
    let every = ((cfg.onset_every_s as f64 / out_dt).round() as usize).max(1);
    let first = s
        .times
        .times_s
        .partition_point(|&t| t < s.times.nav_start_s - 1e-9);
    let last_fit = s.times.fit_index.last().copied().unwrap_or(0);
    Ok((out_dt, every, (first..last_fit).step_by(every).collect()))
}

pub(crate) fn prepare(r: &ScanRun<'_>, cfg: &EventScanConfig) -> Result<Prepared, DiagError> {
    let s = r.sens;
    let cov = run_covariance(r, None);
    let cov_key = fingerprint(&cov);
    let w = RunWhitener::new(&cov)?;
    let (out_dt, every, onsets) = onset_grid(s, cfg)?;
    let fit_every = match s.times.fit_index.as_slice() {
        [a, b, ..] => b - a,
        _ => return Err(DiagError::input(&s.run, "fewer than two fit times")),
    };
    let phis: Vec<Mat7> = (0..=fit_every.max(every))
        .map(|g| s.model.transition(g as f64 * out_dt))
        .collect();
    let onset_s: Vec<f64> = onsets.iter().map(|&m| s.times.times_s[m]).collect();
    if s.turn_on_taus_s != cfg.time_constants_s || onsets.first().is_some_and(|&m| m != 0) {
        return Err(DiagError::input(
            &s.run,
            "the sensitivity pass did not propagate the scan's turn-on transients",
        ));
    }
    let axes = (0..6)
        .map(|axis| AxisSignals {
            axis,
            steps: w.whiten(&step_signals(s, axis, &onsets, &phis)),
            turn_on: s.turn_on_states[axis]
                .iter()
                .map(|y| w.whiten_vec(&carried(s, y, &phis)))
                .collect(),
        })
        .collect();
    let mut p = Prepared {
        cov_key,
        whitener: w,
        run: r.fit.run.clone(),
        start_s: s.times.start_s,
        onset_s,
        axes,
        residual: DVector::zeros(0),
        nuisance: Vec::new(),
        candidates: Vec::new(),
    };
    p.retarget(r);
    Ok(p)
}

/// Two weighted sums of a covariance's entries: equal for the same matrix, and different for
/// any two covariances the diagnosis builds.
fn fingerprint(cov: &DMatrix<f64>) -> [f64; 2] {
    let mut k = [0.0, 0.0];
    for (i, v) in cov.iter().enumerate() {
        k[0] += v;
        k[1] += v * (1.0 + (i % 7919) as f64);
    }
    k
}

impl Prepared {
    /// Take run `r`: its residual, nuisance and candidates when its covariance is the one this
    /// run was whitened with (a refined winner's runs may carry another), else all of it.
    pub(crate) fn take(&mut self, r: &ScanRun<'_>, cfg: &EventScanConfig) -> Result<(), DiagError> {
        if fingerprint(&run_covariance(r, None)) == self.cov_key {
            self.retarget(r);
        } else {
            *self = prepare(r, cfg)?;
        }
        Ok(())
    }

    /// Take the residual, nuisance and candidates of `r` (a run whose covariance is the one
    /// this run was whitened with), keeping the whitened signals.
    fn retarget(&mut self, r: &ScanRun<'_>) {
        let w = &self.whitener;
        self.residual = w.whiten_vec(&r.residual);
        self.nuisance = w
            .whiten(&r.nuisance)
            .column_iter()
            .map(|c| c.into_owned())
            .collect();
        self.candidates = r
            .candidates
            .iter()
            .map(|(n, c)| (n.clone(), w.whiten_vec(c)))
            .collect();
    }
}

/// An event's signal on its run's fit rows (unwhitened), scaled by its fitted size: what the
/// event adds to the gap.
#[derive(Clone, Debug)]
pub struct EventSignal {
    /// Index of the run in the scan's input.
    pub run: usize,
    /// Fitted contribution to the gap at the fit rows `[N_0, E_0, ...]` (m).
    pub contribution: DVector<f64>,
}

/// `T` of an event's signal (`contribution`, any scale) on run `r` under the run's covariance
/// plus `extra` (a fitted noise term), the winner's columns and the other events projected out
/// (`others`): is the event still significant when that noise term is in the twin?
pub fn chi2_with(
    r: &ScanRun<'_>,
    extra: &DMatrix<f64>,
    contribution: &DVector<f64>,
    others: &[&DVector<f64>],
) -> Result<f64, DiagError> {
    let w = RunWhitener::new(&run_covariance(r, Some(extra)))?;
    let mut n = Nuisance::new(w.whiten_vec(&r.residual));
    for c in w.whiten(&r.nuisance).column_iter() {
        n.add(&c.into_owned());
    }
    for o in others {
        n.add(&w.whiten_vec(o));
    }
    let (a, b) = n.stat(w.whiten_vec(contribution).as_slice());
    Ok(if b > 0.0 { a * a / b } else { 0.0 })
}

/// Scan every run (see the module documentation).
pub fn scan(runs: &[ScanRun<'_>], cfg: &EventScanConfig) -> Result<EventScan, DiagError> {
    Ok(scan_with_signals(runs, cfg)?.0)
}

/// [`scan`], with each event's fitted contribution to its run's gap (same order as the events).
pub fn scan_with_signals(
    runs: &[ScanRun<'_>],
    cfg: &EventScanConfig,
) -> Result<(EventScan, Vec<EventSignal>), DiagError> {
    if !cfg.enabled || runs.is_empty() {
        return Ok((EventScan::default(), Vec::new()));
    }
    // Runs one at a time (each holds its whitened step signals, about 20 MB for 15 h).
    let tests = family(runs, cfg)?;
    let mut acc = Accumulated::new(tests, cfg);
    for (ri, r) in runs.iter().enumerate() {
        acc.scan_run(ri, &prepare(r, cfg)?, cfg);
    }
    Ok((acc.out, acc.signals))
}

/// [`scan_with_signals`] on runs already prepared (whitened with the covariance of `runs`),
/// retargeted to the residuals, nuisances and candidates of `runs`; the runs on up to
/// `threads` threads (each run is scanned alone: the result does not depend on it).
pub(crate) fn scan_prepared(
    prepared: &mut [Prepared],
    runs: &[ScanRun<'_>],
    cfg: &EventScanConfig,
    threads: usize,
) -> Result<(EventScan, Vec<EventSignal>), DiagError> {
    if !cfg.enabled || runs.is_empty() {
        return Ok((EventScan::default(), Vec::new()));
    }
    let mut acc = Accumulated::new(family(runs, cfg)?, cfg);
    let (tests, thr) = (acc.out.tests, acc.out.threshold_chi2);
    let jobs: Vec<_> = prepared.iter_mut().zip(runs).enumerate().collect();
    let found = par_map(
        jobs,
        threads,
        |(ri, (p, r))| -> Result<RunScan, DiagError> {
            p.take(r, cfg)?;
            Ok(scan_run(ri, p, (tests, thr), cfg))
        },
    )?;
    for f in found {
        acc.add(f?);
    }
    Ok((acc.out, acc.signals))
}

/// The size of the scan's family: every onset, shape and axis of every run.
fn family(runs: &[ScanRun<'_>], cfg: &EventScanConfig) -> Result<usize, DiagError> {
    runs.iter().map(|r| planned_tests(r, cfg)).sum()
}

/// The scan's result as the runs are scanned.
struct Accumulated {
    out: EventScan,
    signals: Vec<EventSignal>,
}

/// What the scan of one run found.
struct RunScan {
    detectable: Vec<DetectableCurve>,
    events: Vec<TimeLocalEvent>,
    signals: Vec<EventSignal>,
}

impl Accumulated {
    fn new(tests: usize, cfg: &EventScanConfig) -> Self {
        Self {
            out: EventScan {
                events: Vec::new(),
                tests,
                threshold_chi2: chi2_isf(cfg.alpha / tests.max(1) as f64, 1.0),
                detectable: Vec::new(),
            },
            signals: Vec::new(),
        }
    }

    /// Scan run `ri` (see [`scan_run`]) and add what it found.
    fn scan_run(&mut self, ri: usize, p: &Prepared, cfg: &EventScanConfig) {
        let (tests, thr) = (self.out.tests, self.out.threshold_chi2);
        self.add(scan_run(ri, p, (tests, thr), cfg));
    }

    /// Add one run's findings, after those of the runs before it.
    fn add(&mut self, found: RunScan) {
        self.out.detectable.extend(found.detectable);
        self.out.events.extend(found.events);
        self.signals.extend(found.signals);
    }
}

/// Scan run `ri`: the strongest significant signal, projected out, up to
/// `max_events_per_run` times, in a family of `tests` signals with threshold `thr` on `T`.
fn scan_run(ri: usize, p: &Prepared, (tests, thr): (usize, f64), cfg: &EventScanConfig) -> RunScan {
    let mut nuis = Nuisance::new(p.residual.clone());
    for v in &p.nuisance {
        nuis.add(v);
    }
    let mut found = RunScan {
        detectable: detectable_curves(p, &nuis, thr, cfg),
        events: Vec::new(),
        signals: Vec::new(),
    };
    for _ in 0..cfg.max_events_per_run {
        let Some(b) = best(p, &nuis, cfg) else { break };
        if b.t < thr {
            break;
        }
        let (b, profile) = duration::refit(p, &nuis, b, cfg);
        found
            .events
            .push(event(p, &nuis, &b, profile, (tests, thr), cfg));
        found.signals.push(EventSignal {
            run: ri,
            contribution: p.whitener.colour(&(&b.signal * (b.a / b.b))),
        });
        nuis.add(&b.signal);
    }
    found
}

/// The number of signals [`scan`] tests on a run (what [`AxisSignals::visit`] hands out).
pub(crate) fn planned_tests(r: &ScanRun<'_>, cfg: &EventScanConfig) -> Result<usize, DiagError> {
    Ok(6 * signals_per_axis(onset_grid(r.sens, cfg)?.2.len(), cfg))
}

/// The signals [`AxisSignals::visit`] hands out on an axis with `k` onsets.
pub(crate) fn signals_per_axis(k: usize, cfg: &EventScanConfig) -> usize {
    let n = cfg.time_constants_s.len();
    let ending = |steps: Vec<usize>| steps.iter().map(|&s| k.saturating_sub(s)).sum::<usize>();
    let turn_on = if k > 0 { n } else { 0 };
    k * (2 + n) + turn_on + ending(cfg.pulse_steps()) + ending(cfg.plateau_steps())
}
