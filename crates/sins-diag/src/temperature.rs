//! One-second means of the recorded accelerometer temperatures and their smoothed rate of
//! change, which temperature-rate effects need (the thermometers' white noise makes a
//! sample-to-sample difference useless: 0.01 degC per 5 ms is 2 degC/s of noise).

use serde::{Deserialize, Serialize};
use sins_imu::ImuSample;

/// Per-second temperature means of a run, built while streaming its samples.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TemperatureSeries {
    /// Start of the first one-second cell (s).
    pub t0_s: f64,
    /// Mean thermometer readings of each cell `[t0 + k, t0 + k + 1)` (degC; NaN if the data
    /// carry no temperatures).
    pub mean_degc: Vec<[f64; 3]>,
    /// Smoothed rate of change in each cell (degC/s), filled by [`TemperatureSeries::finish`].
    pub rate_degc_per_s: Vec<[f64; 3]>,
    #[serde(skip)]
    acc: Option<Cell>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Cell {
    index: usize,
    sum: [f64; 3],
    n: usize,
}

impl TemperatureSeries {
    /// An empty series whose first cell starts at `t0_s`.
    pub fn new(t0_s: f64) -> Self {
        Self {
            t0_s,
            ..Default::default()
        }
    }

    /// Add one sample (attributed to the cell holding the middle of its interval `h_s`).
    #[inline]
    pub fn push(&mut self, s: &ImuSample, h_s: f64) {
        let index = (s.t_s - 0.5 * h_s - self.t0_s).floor().max(0.0) as usize;
        match &mut self.acc {
            Some(c) if c.index == index => {
                for j in 0..3 {
                    c.sum[j] += s.temp_degc[j];
                }
                c.n += 1;
            }
            _ => {
                self.close_cell();
                self.acc = Some(Cell {
                    index,
                    sum: s.temp_degc,
                    n: 1,
                });
            }
        }
    }

    fn close_cell(&mut self) {
        if let Some(c) = self.acc.take() {
            let mean = c.sum.map(|x| x / c.n as f64);
            let last = self.mean_degc.last().copied().unwrap_or(mean);
            while self.mean_degc.len() < c.index {
                self.mean_degc.push(last);
            }
            if self.mean_degc.len() == c.index {
                self.mean_degc.push(mean);
            }
        }
    }

    /// Close the last cell and compute the rates by a local linear fit over
    /// `±half_window_s` cells (one-sided at the ends).
    pub fn finish(&mut self, half_window_s: usize) {
        self.close_cell();
        let n = self.mean_degc.len();
        let w = half_window_s.max(1);
        self.rate_degc_per_s = (0..n)
            .map(|k| {
                let lo = k.saturating_sub(w);
                let hi = (k + w).min(n.saturating_sub(1));
                let mut out = [0.0; 3];
                if hi > lo {
                    let m = (hi - lo + 1) as f64;
                    let tm = (lo + hi) as f64 / 2.0;
                    let stt: f64 = (lo..=hi).map(|i| (i as f64 - tm).powi(2)).sum();
                    for (j, o) in out.iter_mut().enumerate() {
                        let mean = (lo..=hi).map(|i| self.mean_degc[i][j]).sum::<f64>() / m;
                        let sty: f64 = (lo..=hi)
                            .map(|i| (i as f64 - tm) * (self.mean_degc[i][j] - mean))
                            .sum();
                        *o = sty / stt;
                    }
                }
                out
            })
            .collect();
    }

    /// Smoothed temperature rate (degC/s) at time `t_s` (nearest cell; zero when empty).
    #[inline]
    pub fn rate_at(&self, t_s: f64) -> [f64; 3] {
        let n = self.rate_degc_per_s.len();
        if n == 0 {
            return [0.0; 3];
        }
        let k = ((t_s - self.t0_s).floor().max(0.0) as usize).min(n - 1);
        self.rate_degc_per_s[k]
    }

    /// Cell mean (degC) at time `t_s` (nearest cell; NaN when empty).
    pub fn mean_at(&self, t_s: f64) -> [f64; 3] {
        let n = self.mean_degc.len();
        if n == 0 {
            return [f64::NAN; 3];
        }
        let k = ((t_s - self.t0_s).floor().max(0.0) as usize).min(n - 1);
        self.mean_degc[k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_rate_is_recovered() {
        let h = 0.01;
        let mut ts = TemperatureSeries::new(0.0);
        for k in 0..100_000 {
            let t = (k + 1) as f64 * h;
            let mut s = ImuSample::zero(t);
            let tm = t - 0.5 * h;
            s.temp_degc = [20.0 + 0.01 * tm, 5.0 - 0.002 * tm, 1.0];
            ts.push(&s, h);
        }
        ts.finish(30);
        assert_eq!(ts.mean_degc.len(), 1000);
        for t in [0.5, 500.0, 999.5] {
            let r = ts.rate_at(t);
            assert!(
                (r[0] - 0.01).abs() < 1e-12 && (r[1] + 0.002).abs() < 1e-12 && r[2].abs() < 1e-12
            );
        }
        assert!((ts.mean_at(10.2)[0] - (20.0 + 0.105)).abs() < 1e-9);
    }
}
