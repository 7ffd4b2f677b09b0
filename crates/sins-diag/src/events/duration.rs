//! A pulse's duration and a plateau's rise time, profiled out. The scan tests a few durations
//! (an octave apart); the strongest pulse or plateau of a run is then refitted over every
//! whole number of onset-grid steps from half to twice its duration, onset free, so that a
//! duration between two of the scan's does not move the onset to centre the nearer one on the
//! true pulse. The onset's profile likelihood is the best `T` over those durations at each
//! onset. Significance stays the coarse scan's (the refit only raises `T`), so the family-wise
//! false-alarm level is unchanged.
//!
//! A pulse of a duration far from the scan's can lose to a step at one of its edges (the
//! sharp edge of an accelerometer pulse fixes the onset to a grid step or two). So, when the
//! scan has pulses at all, the strongest step is also tried as either edge of a pulse of any whole duration; the pulse
//! replaces it when its `T` exceeds the step's by the chi-square of one degree of freedom at
//! the scan's `alpha`, Bonferroni-corrected over the durations tried: the other edge is then a
//! significant second parameter, not the best of many chances.

use super::found::Best;
use super::{AxisSignals, EventScanConfig, Prepared, Shape};
use crate::stats::chi2_isf;
use crate::whiten::Nuisance;
use nalgebra::{DMatrix, DVector};

/// The unit-rate ramps `R_m` of an axis at every onset (whitened, one column per onset, and a
/// zero column after the last): `R_m = R_{m+1} + Δ (S_m + S_{m+1}) / 2`.
fn ramps(ax: &AxisSignals, dt: f64) -> DMatrix<f64> {
    let (rows, k) = (ax.steps.nrows(), ax.steps.ncols());
    let mut r = DMatrix::zeros(rows, k + 1);
    for m in (0..k).rev() {
        let next_step = if m + 1 < k {
            ax.steps.column(m + 1).into_owned()
        } else {
            DVector::zeros(rows)
        };
        let here = r.column(m + 1) + (ax.steps.column(m) + next_step) * (0.5 * dt);
        r.set_column(m, &here);
    }
    r
}

/// The pulse or plateau of `n` grid steps at onset `m` (whitened), or `None` when it would end
/// after the last onset (then it is the step or the ramp).
fn signal(
    ax: &AxisSignals,
    ramps: Option<&DMatrix<f64>>,
    m: usize,
    n: usize,
    dt: f64,
) -> Option<DVector<f64>> {
    let k = ax.steps.ncols();
    if m + n >= k {
        return None;
    }
    Some(match ramps {
        None => ax.steps.column(m) - ax.steps.column(m + n),
        Some(r) => (r.column(m) - r.column(m + n)) / (n as f64 * dt),
    })
}

/// `b` with its duration refitted (a pulse or a plateau; any other shape as it is), and the
/// onset profile of the refit (best `T` over the durations at each onset).
pub(super) fn refit(
    p: &Prepared,
    nuis: &Nuisance,
    b: Best,
    cfg: &EventScanConfig,
) -> (Best, Option<Vec<f64>>) {
    let Some(ax) = p.axes.iter().find(|a| a.axis == b.axis) else {
        return (b, None);
    };
    let dt = cfg.onset_every_s.max(1) as f64;
    let b = match b.shape {
        Shape::Step if !cfg.pulse_steps().is_empty() => pulse_at_an_edge(ax, nuis, b, cfg),
        _ => b,
    };
    let Some(duration_s) = b.shape.duration_s() else {
        return (b, None);
    };
    let plateau = matches!(b.shape, Shape::Plateau { .. });
    let ramps = plateau.then(|| ramps(ax, dt));
    let k = ax.steps.ncols();
    let n0 = ((duration_s / dt).round() as usize).max(1);
    let mut profile = vec![0.0; k];
    let mut top = b;
    for n in (n0 / 2).max(1)..=(2 * n0) {
        for (m, best_here) in profile.iter_mut().enumerate() {
            let Some(sig) = signal(ax, ramps.as_ref(), m, n, dt) else {
                break;
            };
            let (a, bb) = nuis.stat(sig.as_slice());
            if bb <= 0.0 {
                continue;
            }
            let t = a * a / bb;
            *best_here = f64::max(*best_here, t);
            if t > top.t {
                let time_s = n as f64 * dt;
                top = Best {
                    shape: if plateau {
                        Shape::Plateau { rise_s: time_s }
                    } else {
                        Shape::Pulse { duration_s: time_s }
                    },
                    m,
                    a,
                    b: bb,
                    t,
                    signal: sig,
                    ..top
                };
            }
        }
    }
    (top, Some(profile))
}

/// The step `b` as either edge of a pulse of any whole duration, when the best such pulse
/// beats it by the Bonferroni-corrected chi-square of its other edge (module documentation).
fn pulse_at_an_edge(ax: &AxisSignals, nuis: &Nuisance, b: Best, cfg: &EventScanConfig) -> Best {
    let dt = cfg.onset_every_s.max(1) as f64;
    let k = ax.steps.ncols();
    let tried = (2 * k).max(1);
    let need = b.t + chi2_isf(cfg.alpha / tried as f64, 1.0);
    let mut top: Option<Best> = None;
    for n in 1..k {
        // The step as the pulse's start, then as its end.
        let starts = [Some(b.m), b.m.checked_sub(n)];
        for m in starts.into_iter().flatten() {
            let Some(sig) = signal(ax, None, m, n, dt) else {
                continue;
            };
            let (a, bb) = nuis.stat(sig.as_slice());
            if bb <= 0.0 {
                continue;
            }
            let t = a * a / bb;
            if t >= need && top.as_ref().is_none_or(|x| t > x.t) {
                top = Some(Best {
                    shape: Shape::Pulse {
                        duration_s: n as f64 * dt,
                    },
                    m,
                    a,
                    b: bb,
                    t,
                    signal: sig,
                    axis: b.axis,
                    per_axis: b.per_axis.clone(),
                });
            }
        }
    }
    top.unwrap_or(b)
}
