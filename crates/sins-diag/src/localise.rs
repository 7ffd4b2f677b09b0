//! Where a run's gap lies: per segment and channel, the first exit from the twin's 3-sigma
//! envelope, and a time-scale decomposition.
//!
//! The decomposition fits the gap of each channel by least squares on nested groups of bases of
//! the navigation time τ, in a fixed order, and reports the extra share of the gap's energy each
//! group explains: `secular` (1, τ, τ²), `foucault_24h` (sine and cosine of the sidereal day:
//! heading errors and the Earth-rate oscillation), `schuler_84min` (sine and cosine at the Schuler
//! frequency √(g/R), also times τ for the slow Foucault modulation), `segment_steps` (a step and a
//! ramp at each change of segment label: an effect that switches with vibration or motion), and
//! the `residual`. The order makes the nested shares add up to one (a signal that several
//! groups can represent goes to the earliest); the unique share of a group is what only it
//! explains (full model less the model without it).

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
        let explained = |cols: &[&Vec<f64>]| -> f64 {
            if total <= 0.0 || cols.is_empty() {
                return 0.0;
            }
            let xm = DMatrix::from_fn(n, cols.len(), |i, j| cols[j][i]);
            let (pinv, _) = pseudo_inverse(&(xm.transpose() * &xm));
            let beta = pinv * (xm.transpose() * &g);
            (&xm * beta).norm_squared().min(total)
        };
        let all: Vec<&Vec<f64>> = groups.iter().flat_map(|(_, cols)| cols.iter()).collect();
        let full = explained(&all);
        let frac = |e: f64| {
            if total > 0.0 {
                (e / total).max(0.0)
            } else {
                0.0
            }
        };
        let mut prev = 0.0;
        for (k, (gname, _)) in groups.iter().enumerate() {
            let upto: Vec<&Vec<f64>> = groups[..=k].iter().flat_map(|(_, c)| c.iter()).collect();
            let nested = explained(&upto).max(prev);
            let without: Vec<&Vec<f64>> = groups
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != k)
                .flat_map(|(_, (_, c))| c.iter())
                .collect();
            out.push(TimeScaleShare {
                channel: name.to_string(),
                basis: gname.to_string(),
                share: frac(nested - prev),
                unique: frac(full - explained(&without)),
            });
            prev = nested;
        }
        out.push(TimeScaleShare {
            channel: name.to_string(),
            basis: "residual".into(),
            share: frac(total - prev),
            unique: 0.0,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(gap: impl Fn(f64) -> [f64; 2], step_at: f64) -> GapSeries {
        let t_s: Vec<f64> = (1..=5000).map(|k| 1200.0 + 10.0 * k as f64).collect();
        GapSeries {
            run: "r".into(),
            nav_start_s: 1200.0,
            segment: t_s.iter().map(|&t| u16::from(t >= step_at)).collect(),
            gap_m: t_s.iter().map(|&t| gap(t - 1200.0)).collect(),
            twin_m: vec![[0.0; 2]; t_s.len()],
            sigma_m: vec![[10.0; 2]; t_s.len()],
            t_s,
        }
    }

    fn share(l: &RunLocalisation, channel: &str, basis: &str) -> f64 {
        l.time_scales
            .iter()
            .find(|s| s.channel == channel && s.basis == basis)
            .map_or(f64::NAN, |s| s.share)
    }

    #[test]
    fn time_scales_segments_and_envelope_exit_are_found() {
        let ws = 2.0 * std::f64::consts::PI / (84.4 * 60.0);
        let labels = vec!["stationary".to_string(), "pattern1".to_string()];
        let test = ChiSquareTest {
            chi2: 0.0,
            dof: 1.0,
            p_value: 1.0,
            consistent: true,
        };
        // North: a pure Schuler oscillation; east: a step at 30000 s growing as a ramp.
        let s = series(
            |tau| {
                let east = if tau >= 28_800.0 {
                    50.0 + 0.01 * (tau - 28_800.0)
                } else {
                    0.0
                };
                [40.0 * (ws * tau).sin(), east]
            },
            30_000.0,
        );
        let l = localise(&s, &labels, ws, test);
        assert!(
            share(&l, "north", "schuler_84min") > 0.95,
            "{:?}",
            l.time_scales
        );
        let unique = |basis: &str| {
            l.time_scales
                .iter()
                .find(|s| s.channel == "east" && s.basis == basis)
                .map_or(f64::NAN, |s| s.unique)
        };
        assert!(unique("segment_steps") > 0.003, "{:?}", l.time_scales);
        assert!(unique("segment_steps") > 10.0 * unique("schuler_84min"));
        let total: f64 = l
            .time_scales
            .iter()
            .filter(|s| s.channel == "east")
            .map(|s| s.share)
            .sum();
        assert!((total - 1.0).abs() < 1e-9);
        // The Schuler wave reaches 4 sigma first, a quarter period in.
        let exit = l.first_exit_s.expect("exits");
        assert!((exit - 1200.0 - 84.4 * 60.0 / 4.0).abs() < 600.0, "{exit}");
        assert_eq!(l.first_exit_channel.as_deref(), Some("north"));
        let seg = l
            .segments
            .iter()
            .find(|g| g.segment == "pattern1" && g.channel == "east");
        assert!(seg.is_some_and(|g| g.max_abs_m > 50.0 && g.points > 0));
    }
}
