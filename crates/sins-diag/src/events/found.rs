//! What the scan reports of a run: its strongest signal ([`best`]), that signal as a
//! [`TimeLocalEvent`] (onset interval by profile likelihood, size, the channels it cannot be told
//! from, the catalogue candidate that explains it), and the detectable level of every shape and
//! axis along the run.

use super::{
    AXES, ChannelAlternative, DetectableCurve, EventScanConfig, Prepared, Shape, TimeLocalEvent,
};
use crate::stats::chi2_sf;
use crate::whiten::Nuisance;
use nalgebra::DVector;

/// The strongest signal of a run against the current nuisance, with the best `T` (and its
/// shape) of every axis.
pub(super) struct Best {
    pub(super) axis: usize,
    pub(super) shape: Shape,
    pub(super) m: usize,
    pub(super) a: f64,
    pub(super) b: f64,
    pub(super) t: f64,
    pub(super) signal: DVector<f64>,
    pub(super) per_axis: Vec<(usize, Shape, f64)>,
}

/// `T` a rival channel may fall short of the best by and still not be told from it.
const ALTERNATIVE_DT: f64 = 9.0;

pub(super) fn best(p: &Prepared, nuis: &Nuisance, cfg: &EventScanConfig) -> Option<Best> {
    let mut top: Option<Best> = None;
    let mut per_axis = Vec::with_capacity(p.axes.len());
    for ax in &p.axes {
        let mut axis_top: Option<(usize, Shape, f64)> = None;
        ax.visit(&p.onset_s, p.start_s, cfg, &mut |shape, m, sig| {
            let (a, b) = nuis.stat(sig.as_slice());
            if b <= 0.0 {
                return;
            }
            let t = a * a / b;
            if axis_top.is_none_or(|x| t > x.2) {
                axis_top = Some((ax.axis, shape, t));
            }
            if top.as_ref().is_none_or(|x| t > x.t) {
                top = Some(Best {
                    axis: ax.axis,
                    shape,
                    m,
                    a,
                    b,
                    t,
                    signal: sig.clone(),
                    per_axis: Vec::new(),
                });
            }
        });
        per_axis.extend(axis_top);
    }
    top.map(|b| Best { per_axis, ..b })
}

/// The channels `b` cannot be told from, strongest first.
fn alternatives(b: &Best) -> Vec<ChannelAlternative> {
    let mut out: Vec<ChannelAlternative> = b
        .per_axis
        .iter()
        .filter(|&&(axis, _, t)| axis != b.axis && t >= b.t - ALTERNATIVE_DT)
        .map(|&(axis, shape, t)| ChannelAlternative {
            channel: AXES[axis].to_string(),
            shape: shape.label().to_string(),
            time_constant_s: shape.tau_s(),
            duration_s: shape.duration_s(),
            chi2: t,
        })
        .collect();
    out.sort_by(|x, y| y.chi2.total_cmp(&x.chi2));
    out
}

/// The event `b` of run `p`; `profile`: `T` along the onsets when the caller has it (a
/// duration profiled out), else that of `b`'s shape; `(tests, thr)`: the family's size and
/// its corrected threshold.
pub(super) fn event(
    p: &Prepared,
    nuis: &Nuisance,
    b: &Best,
    profile: Option<Vec<f64>>,
    (tests, thr): (usize, f64),
    cfg: &EventScanConfig,
) -> TimeLocalEvent {
    // T along the onsets of the event's shape and axis.
    let tm = profile.unwrap_or_else(|| {
        let mut tm = vec![0.0; p.onset_s.len()];
        if let Some(ax) = p.axes.iter().find(|a| a.axis == b.axis) {
            ax.visit(&p.onset_s, p.start_s, cfg, &mut |shape, m, sig| {
                if shape == b.shape {
                    let (a, bb) = nuis.stat(sig.as_slice());
                    tm[m] = if bb > 0.0 { a * a / bb } else { 0.0 };
                }
            });
        }
        tm
    });
    let onset_s = p.onset_of(b.shape, b.m);
    let (onset_sigma_s, onset_interval_s) = match b.shape {
        // The turn-on is known: the first sample.
        Shape::Transient { turn_on: true, .. } => (0.0, [onset_s, onset_s]),
        _ => {
            // Profile-likelihood interval at three sigma: contiguous onsets whose T is within
            // 9 of the best. The onset of a slow signature (a gyro step) is weakly determined
            // and its profile is far from quadratic, so the sigma is a third of the larger
            // side of that interval, not the curvature at the peak.
            let (mut lo, mut hi) = (b.m, b.m);
            while lo > 0 && tm[lo - 1] >= b.t - 9.0 {
                lo -= 1;
            }
            while hi + 1 < tm.len() && tm[hi + 1] >= b.t - 9.0 {
                hi += 1;
            }
            let (a, z) = (p.onset_s[lo], p.onset_s[hi]);
            let side = (onset_s - a).max(z - onset_s);
            (
                (side / 3.0).max(cfg.onset_every_s as f64 / 12f64.sqrt()),
                [a, z],
            )
        }
    };
    let kind = b.shape.kind(b.axis);
    let unit = kind.unit();
    // Explained by a candidate when the gap less that candidate's fit (one magnitude for all
    // runs) leaves the event insignificant. (Its columns of this run alone, free, would absorb
    // a step in one run with a temperature-rate signature that no other run supports.)
    let explained_by = p
        .candidates
        .iter()
        .filter_map(|(name, contribution)| {
            let mut c = contribution.clone();
            for q in &nuis.q {
                let k = q.dot(&c);
                c.axpy(-k, q, 1.0);
            }
            let n2 = Nuisance {
                q: nuis.q.clone(),
                r: &nuis.r - c,
            };
            let (a2, b2) = n2.stat(b.signal.as_slice());
            (b2 > 0.0).then(|| (name, a2 * a2 / b2))
        })
        .filter(|(_, t2)| *t2 < thr)
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map(|(n, _)| n.clone());
    TimeLocalEvent {
        run: p.run.clone(),
        channel: AXES[b.axis].to_string(),
        shape: b.shape.label().to_string(),
        kind: kind.name().to_string(),
        onset_s,
        onset_sigma_s,
        onset_interval_s,
        size: unit.from_si(b.a / b.b),
        size_sigma: unit.from_si(1.0 / b.b.sqrt()),
        unit: unit.label.to_string(),
        time_constant_s: b.shape.tau_s(),
        duration_s: b.shape.duration_s(),
        chi2: b.t,
        p_value: (chi2_sf(b.t, 1.0) * tests as f64).min(1.0),
        explained_by,
        alternatives: alternatives(b),
    }
}

/// Detectable levels of every shape and axis of a run at onsets `detectable_every_s` apart.
pub(super) fn detectable_curves(
    p: &Prepared,
    nuis: &Nuisance,
    thr: f64,
    cfg: &EventScanConfig,
) -> Vec<DetectableCurve> {
    let z = thr.sqrt() + 1.281_551_565_545;
    let stride =
        ((cfg.detectable_every_s / cfg.onset_every_s.max(1) as f64).round() as usize).max(1);
    let mut out: Vec<(Shape, usize, DetectableCurve)> = Vec::new();
    for ax in &p.axes {
        ax.visit(&p.onset_s, p.start_s, cfg, &mut |shape, m, sig| {
            let turn_on = matches!(shape, Shape::Transient { turn_on: true, .. });
            if !turn_on && m % stride != 0 {
                return;
            }
            let (_, b) = nuis.stat(sig.as_slice());
            let unit = shape.kind(ax.axis).unit();
            let level = if b > 0.0 {
                unit.from_si(z / b.sqrt())
            } else {
                f64::INFINITY
            };
            let i = match out
                .iter()
                .position(|(s, a, _)| *s == shape && *a == ax.axis)
            {
                Some(i) => i,
                None => {
                    out.push((
                        shape,
                        ax.axis,
                        DetectableCurve {
                            run: p.run.clone(),
                            channel: AXES[ax.axis].to_string(),
                            shape: shape.label().to_string(),
                            time_constant_s: shape.tau_s(),
                            duration_s: shape.duration_s(),
                            unit: unit.label.to_string(),
                            onset_s: Vec::new(),
                            level: Vec::new(),
                        },
                    ));
                    out.len() - 1
                }
            };
            out[i].2.onset_s.push(p.onset_of(shape, m));
            out[i].2.level.push(level);
        });
    }
    // The visit runs backwards in time.
    out.into_iter()
        .map(|(_, _, mut c)| {
            c.onset_s.reverse();
            c.level.reverse();
            c
        })
        .collect()
}
