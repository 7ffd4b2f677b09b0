//! 'Nice' axis ranges and tick marks (steps of 1, 2 or 5 times a power of ten) and their labels.

/// Relative tolerance for deciding whether a value sits on a tick.
const SNAP: f64 = 1e-9;

/// Smallest axis span accepted (narrower spans are below useful f64 resolution).
const MIN_SPAN: f64 = 1e-280;

/// Tick marks of one axis, linear ([`nice_ticks`]) or logarithmic ([`crate::log_ticks`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Ticks {
    /// Lower end of the axis, data units (a multiple of `step` when expanded; on a log axis a
    /// power of ten when expanded).
    pub lo: f64,
    /// Upper end of the axis, data units.
    pub hi: f64,
    /// Linear axis: distance between ticks, 1, 2 or 5 times a power of ten (data units). Log
    /// axis with ticks at decades: how many decades apart the labelled ticks are (1: every
    /// decade); 0 for the unevenly spaced 1-2-5 or 1-9 ticks within few decades; the linear
    /// step when a range inside one decade gets linear ticks.
    pub step: f64,
    /// Tick positions in `[lo, hi]`, ascending, data units (on a linear axis each an integer
    /// multiple of `step`).
    pub values: Vec<f64>,
    /// One label per tick, the value written out (see [`format_ticks`] and
    /// [`crate::log_ticks`]).
    pub labels: Vec<String>,
    /// Whether the axis is logarithmic (base 10): a value's position along the axis goes with
    /// its `log10`, between `log10(lo)` and `log10(hi)`.
    pub log: bool,
    /// Unlabelled minor tick positions in `[lo, hi]`, ascending, data units: on a log axis
    /// 2-9 x 10^k between labelled ticks (or the unlabelled decades when only every n-th decade
    /// is labelled); empty on a linear axis.
    pub minor: Vec<f64>,
}

/// The smallest step of the form {1, 2, 5} x 10^k that divides `span` into at most
/// `max_intervals` intervals; `None` unless `span` is positive and finite.
pub fn nice_step(span: f64, max_intervals: usize) -> Option<f64> {
    if !(span.is_finite() && span >= MIN_SPAN) {
        return None;
    }
    let raw = span / max_intervals.max(1) as f64;
    let mut exp = raw.log10().floor() as i32;
    // log10 may round across a power of ten; make sure 10^exp <= raw < 10^(exp+1).
    if 10f64.powi(exp) > raw * (1.0 + SNAP) {
        exp -= 1;
    } else if 10f64.powi(exp + 1) <= raw * (1.0 - SNAP) {
        exp += 1;
    }
    let mag = 10f64.powi(exp);
    let f = raw / mag;
    let m = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .find(|m| f <= m * (1.0 + SNAP))
        .unwrap_or(10.0);
    Some(m * mag)
}

/// The next smaller 1-2-5 step: 10 -> 5 -> 2 -> 1 (times the power of ten).
fn smaller_step(step: f64) -> f64 {
    let mag = 10f64.powi((step.log10() + SNAP).floor() as i32);
    let m = (step / mag).round();
    if m >= 5.0 {
        2.0 * mag
    } else if m >= 2.0 {
        mag
    } else {
        0.5 * mag
    }
}

/// Ticks for the axis `[lo, hi]` with at most `max_intervals` steps of the span (a tight range
/// that would then hold fewer than two ticks gets a finer step instead, up to one decade).
/// With `expand` the ends move out to the enclosing multiples of the step (a 'nice' range);
/// otherwise they stay and only ticks inside are listed. `None` if the range is not finite,
/// not increasing, or narrower than f64 can resolve at its magnitude.
pub fn nice_ticks(lo: f64, hi: f64, max_intervals: usize, expand: bool) -> Option<Ticks> {
    if !(lo.is_finite() && hi.is_finite() && hi > lo) {
        return None;
    }
    let span = hi - lo;
    let max_abs = lo.abs().max(hi.abs());
    if !span.is_finite() || span < max_abs * 1e-12 {
        return None;
    }
    let mut step = nice_step(span, max_intervals)?;
    let (mut i0, mut i1) = ((lo / step - SNAP).ceil(), (hi / step + SNAP).floor());
    // A tight range may hold fewer than two multiples of the step: refine (at most twice a
    // decade) until it holds two.
    for _ in 0..3 {
        if expand || i1 > i0 {
            break;
        }
        step = smaller_step(step);
        (i0, i1) = ((lo / step - SNAP).ceil(), (hi / step + SNAP).floor());
    }
    let (mut lo, mut hi) = (lo, hi);
    if expand {
        i0 = (lo / step + SNAP).floor();
        i1 = (hi / step - SNAP).ceil();
        lo = i0 * step;
        hi = i1 * step;
    }
    let values: Vec<f64> = (0..=(i1 - i0).max(-1.0) as i64)
        .map(|k| {
            let v = (i0 + k as f64) * step;
            if v.abs() < step * SNAP { 0.0 } else { v }
        })
        .collect();
    let labels = format_ticks(&values, step);
    Some(Ticks {
        lo,
        hi,
        step,
        values,
        labels,
        log: false,
        minor: Vec::new(),
    })
}

/// Labels for tick `values` spaced `step` apart: fixed-point with just enough decimals for the
/// step (`"0.25"` is never needed: steps are 1-2-5), or scientific (`"2.5e-7"`, `"1.5e9"`)
/// when the largest magnitude is at least 1e6 or below 1e-3. Zero is always `"0"`.
pub fn format_ticks(values: &[f64], step: f64) -> Vec<String> {
    let max_abs = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let step_exp = (step.abs().log10() + SNAP).floor() as i32;
    let scientific = max_abs >= 1e6 || (max_abs > 0.0 && max_abs < 1e-3);
    values
        .iter()
        .map(|&v| {
            if v == 0.0 {
                return "0".to_string();
            }
            if scientific {
                let value_exp = (max_abs.log10() + SNAP).floor() as i32;
                let digits = (value_exp - step_exp).max(0) as usize;
                format!("{v:.digits$e}")
            } else {
                let decimals = (-step_exp).max(0) as usize;
                let s = format!("{v:.decimals$}");
                if s.trim_start_matches('-')
                    .chars()
                    .all(|c| c == '0' || c == '.')
                {
                    "0".to_string()
                } else {
                    s
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_is_one_two_five() {
        assert_eq!(nice_step(10.0, 10), Some(1.0));
        assert_eq!(nice_step(10.0, 5), Some(2.0));
        assert_eq!(nice_step(10.0, 3), Some(5.0));
        assert_eq!(nice_step(10.0, 1), Some(10.0));
        assert_eq!(nice_step(0.0, 5), None);
        assert_eq!(nice_step(f64::NAN, 5), None);
        assert_eq!(nice_step(f64::INFINITY, 5), None);
    }

    #[test]
    fn format_examples() {
        assert_eq!(format_ticks(&[0.0, 0.5, 1.0], 0.5), ["0", "0.5", "1.0"]);
        assert_eq!(format_ticks(&[-20.0, 0.0, 20.0], 20.0), ["-20", "0", "20"]);
        assert_eq!(format_ticks(&[2e-7, 4e-7], 2e-7), ["2e-7", "4e-7"]);
        assert_eq!(format_ticks(&[1.4e-6, 1.6e-6], 2e-7), ["1.4e-6", "1.6e-6"]);
        assert_eq!(format_ticks(&[5e8, 1e9], 5e8), ["5.0e8", "1.0e9"]);
    }
}
