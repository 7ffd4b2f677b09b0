//! Where a run's gap lies: per segment and channel, the first exit from the twin's 3-sigma
//! envelope, and a time-scale decomposition.
//!
//! The decomposition fits the gap of each channel by least squares on nested groups of bases of
//! the navigation time τ, in a fixed order, and reports the extra share of the gap's energy each
//! group explains: `secular` (1, τ, τ²), `foucault_24h` (sine and cosine of the sidereal day:
//! heading errors and the Earth-rate oscillation), `schuler_84min` (sine and cosine at the Schuler
//! frequency √(g/R), also times τ for the slow Foucault modulation), `segment_steps` (a step and a
//! ramp at each change of segment label: an effect that switches with vibration or motion), and
//! the `residual`. The order makes the shares add up to one; a signal that several groups can
//! represent goes to the earliest.

use crate::gls::pseudo_inverse;
use crate::report::{ChiSquareTest, RunLocalisation, SegmentGap, TimeScaleShare};
use nalgebra::{DMatrix, DVector};

/// A run's gap and twin sigma on the output grid.
#[derive(Clone, Debug)]
pub struct GapSeries {
    /// Run name.
    pub run: String,
    /// Start of navigation (s).
    pub nav_start_s: f64,
    /// Output times (s).
    pub t_s: Vec<f64>,
    /// Segment label index at each time.
    pub segment: Vec<u16>,
    /// Gap real - twin mean `[north, east]` (m).
    pub gap_m: Vec<[f64; 2]>,
    /// Twin mean `[north, east]` (m).
    pub twin_m: Vec<[f64; 2]>,
    /// Twin 1-sigma `[north, east]` (m).
    pub sigma_m: Vec<[f64; 2]>,
}

const CHANNELS: [&str; 2] = ["north", "east"];

/// Localise the gap of `s` (`labels` names its segment indices; `schuler_radps` is √(g/R)).
pub fn localise(
    s: &GapSeries,
    labels: &[String],
    schuler_radps: f64,
    chi2: ChiSquareTest,
) -> RunLocalisation {
    let label = |g: u16| {
        labels
            .get(g as usize)
            .cloned()
            .unwrap_or_else(|| format!("segment {g}"))
    };
    let mut order: Vec<u16> = Vec::new();
    for &g in &s.segment {
        if !order.contains(&g) {
            order.push(g);
        }
    }
    let mut segments = Vec::new();
    for &g in &order {
        for (c, name) in CHANNELS.iter().enumerate() {
            let idx: Vec<usize> = (0..s.t_s.len()).filter(|&k| s.segment[k] == g).collect();
            let max_abs_m = idx.iter().map(|&k| s.gap_m[k][c].abs()).fold(0.0, f64::max);
            let rms_m = (idx.iter().map(|&k| s.gap_m[k][c].powi(2)).sum::<f64>()
                / idx.len().max(1) as f64)
                .sqrt();
            let max_sigmas = idx
                .iter()
                .map(|&k| s.gap_m[k][c].abs() / s.sigma_m[k][c].max(1e-9))
                .fold(0.0, f64::max);
            segments.push(SegmentGap {
                segment: label(g),
                channel: name.to_string(),
                max_abs_m,
                rms_m,
                max_sigmas,
                points: idx.len(),
            });
        }
    }
    let exit = (0..s.t_s.len()).find_map(|k| {
        (0..2)
            .find(|&c| s.gap_m[k][c].abs() > 3.0 * s.sigma_m[k][c])
            .map(|c| (k, c))
    });
    RunLocalisation {
        run: s.run.clone(),
        segments,
        first_exit_s: exit.map(|(k, _)| s.t_s[k]),
        first_exit_channel: exit.map(|(_, c)| CHANNELS[c].to_string()),
        first_exit_segment: exit.map(|(k, _)| label(s.segment[k])),
        time_scales: time_scales(s, schuler_radps),
        chi2,
    }
}

/// Nested least-squares shares of each channel's gap energy.
fn time_scales(s: &GapSeries, schuler_radps: f64) -> Vec<TimeScaleShare> {
    let n = s.t_s.len();
    let tau: Vec<f64> = s.t_s.iter().map(|t| t - s.nav_start_s).collect();
    let span = tau.last().copied().unwrap_or(1.0).max(1.0);
    let x: Vec<f64> = tau.iter().map(|t| t / span).collect();
    let day = 86_164.1;
    let w_day = std::f64::consts::TAU / day;
    let mut groups: Vec<(&str, Vec<Vec<f64>>)> = vec![
        (
            "secular",
            vec![vec![1.0; n], x.clone(), x.iter().map(|v| v * v).collect()],
        ),
        (
            "foucault_24h",
            vec![
                tau.iter().map(|t| (w_day * t).sin()).collect(),
                tau.iter().map(|t| (w_day * t).cos()).collect(),
            ],
        ),
        (
            "schuler_84min",
            vec![
                tau.iter().map(|t| (schuler_radps * t).sin()).collect(),
                tau.iter().map(|t| (schuler_radps * t).cos()).collect(),
                tau.iter()
                    .zip(&x)
                    .map(|(t, v)| v * (schuler_radps * t).sin())
                    .collect(),
                tau.iter()
                    .zip(&x)
                    .map(|(t, v)| v * (schuler_radps * t).cos())
                    .collect(),
            ],
        ),
    ];
    let mut steps = Vec::new();
    for k in 1..n {
        if s.segment[k] != s.segment[k - 1] {
            let t0 = tau[k];
            steps.push(tau.iter().map(|t| f64::from(u8::from(*t >= t0))).collect());
            steps.push(tau.iter().map(|t| (t - t0).max(0.0) / span).collect());
        }
    }
    groups.push(("segment_steps", steps));
    let mut out = Vec::new();
    for (c, name) in CHANNELS.iter().enumerate() {
        let g = DVector::from_fn(n, |k, _| s.gap_m[k][c]);
        let total = g.norm_squared();
        let mut basis: Vec<Vec<f64>> = Vec::new();
        let mut explained_prev = 0.0;
        for (gname, cols) in &groups {
            basis.extend(cols.iter().cloned());
            let explained = if total > 0.0 && !basis.is_empty() {
                let xm = DMatrix::from_fn(n, basis.len(), |i, j| basis[j][i]);
                let (pinv, _) = pseudo_inverse(&(xm.transpose() * &xm));
                let beta = pinv * (xm.transpose() * &g);
                (&xm * beta).norm_squared().min(total)
            } else {
                0.0
            };
            out.push(TimeScaleShare {
                channel: name.to_string(),
                basis: gname.to_string(),
                share: if total > 0.0 {
                    ((explained - explained_prev) / total).max(0.0)
                } else {
                    0.0
                },
            });
            explained_prev = explained.max(explained_prev);
        }
        out.push(TimeScaleShare {
            channel: name.to_string(),
            basis: "residual".into(),
            share: if total > 0.0 {
                (1.0 - explained_prev / total).max(0.0)
            } else {
                0.0
            },
        });
    }
    out
}
