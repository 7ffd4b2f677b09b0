//! Ticks of a logarithmic (base 10) axis: labelled decades written as the value (`0.01`, `1`,
//! `1000`, `1e5`), 1-2-5 ticks when the range spans few decades, unlabelled minor ticks at
//! 2-9 x 10^k.

use crate::ticks::{Ticks, nice_step, nice_ticks};

/// Tolerance, in decades, for a tick on an end of the range (1e-9 decades is a relative
/// difference of 2.3e-9).
const SNAP_DECADES: f64 = 1e-9;

/// Powers of ten from 10^FIXED_MIN_EXP to 10^FIXED_MAX_EXP (times 1-9) are written in fixed
/// point (`0.001` to `90000`), the others as `2e-4`, `1e5`.
const FIXED_MIN_EXP: i32 = -3;
const FIXED_MAX_EXP: i32 = 4;

/// Sub-decade ticks are tried while at most this many decade ticks fit the range (3: a range
/// of up to about two decades gets 1-2-5 ticks, e.g. 0.1, 0.2, 0.5, 1, 2, 5, 10).
const MAX_DECADES_FOR_SUBTICKS: usize = 3;

/// `m` x 10^`k` as the f64 nearest to it (the decimal text parses correctly rounded; `powi`
/// would not: 10^-2 is not the f64 nearest 0.01).
fn value(m: u32, k: i32) -> f64 {
    format!("{m}e{k}").parse().unwrap_or(f64::NAN)
}

/// The label of `m` x 10^`k` (`m` 1-9): fixed point from 0.001 to 90000 (`"0.002"`, `"1"`,
/// `"50"`), otherwise `"2e-4"`, `"1e5"` (no `+`, no leading zeros: short, and only digits,
/// `.`, `e` and `-`, which the built-in font draws).
fn label(m: u32, k: i32) -> String {
    if (FIXED_MIN_EXP..=FIXED_MAX_EXP).contains(&k) {
        if k >= 0 {
            format!("{m}{}", "0".repeat(k as usize))
        } else {
            format!("0.{}{m}", "0".repeat((-k - 1) as usize))
        }
    } else {
        format!("{m}e{k}")
    }
}

/// `(m, k)` of every m x 10^k with `m` in `mantissas` whose log10 lies in `[a, b]` (within
/// [`SNAP_DECADES`]), ascending.
fn candidates(a: f64, b: f64, mantissas: &[u32]) -> Vec<(u32, i32)> {
    let (k0, k1) = (a.floor() as i32 - 1, b.ceil() as i32);
    let mut out = Vec::new();
    for k in k0..=k1 {
        for &m in mantissas {
            let l = f64::from(m).log10() + f64::from(k);
            if l >= a - SNAP_DECADES && l <= b + SNAP_DECADES {
                out.push((m, k));
            }
        }
    }
    out
}

/// Ticks for a logarithmic axis over `[lo, hi]` (data units, `0 < lo < hi`, both finite).
///
/// With `expand` the ends move out to the enclosing labelled decades (at least one decade:
/// data from 2 to 5 get the axis 1 to 10); otherwise they stay and only ticks inside are
/// listed. The labelled ticks are, in order of preference:
/// - decades 10^k, every `step`-th decade (1, 2, 5, 10, ... decades apart, so that at most
///   `max_intervals` intervals lie between the ends), when more than three decades fall in the
///   range (or the decades are thinned); minor ticks at 2-9 x 10^k (or, thinned, at the
///   unlabelled decades); `step` is the number of decades between labelled ticks;
/// - 1-2-5 x 10^k (e.g. 0.5, 1, 2, 5, 10, 20) when at most three decades fall in the range and
///   at least two such ticks in at most `max_intervals` intervals do; minor ticks at 3, 4, 6-9
///   x 10^k; `step` 0;
/// - decades alone if at least two fall in the range;
/// - 1-9 x 10^k (e.g. 2, 3, 4, 5) for a range within one decade; `step` 0;
/// - linear [`nice_ticks`] (e.g. 2.2, 2.4, 2.6) for a range between two neighbouring 1-9 x 10^k
///   values; `step` is then their linear step.
///
/// So a range of less than a decade still has at least two labelled ticks. Labels write the
/// value: fixed point from 0.001 to 90000 (`"0.01"`, `"1"`, `"1000"`), else `"1e-4"`, `"2e5"`;
/// the linear fallback labels as [`crate::format_ticks`] does. `None` if the range is not
/// positive, finite and increasing (or too narrow to resolve).
pub fn log_ticks(lo: f64, hi: f64, max_intervals: usize, expand: bool) -> Option<Ticks> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return None;
    }
    let max_intervals = max_intervals.max(1);
    let (mut a, mut b) = (lo.log10(), hi.log10());
    // Labelled decades are `every` decades apart.
    let every = nice_step(b - a, max_intervals).map_or(1.0, |s| s.max(1.0).round());
    let (mut lo, mut hi) = (lo, hi);
    if expand {
        a = ((a + SNAP_DECADES) / every).floor() * every;
        b = ((b - SNAP_DECADES) / every).ceil() * every;
        if b <= a {
            b = a + every;
        }
        (lo, hi) = (value(1, a as i32), value(1, b as i32));
        if !(lo > 0.0 && hi.is_finite()) {
            return None;
        }
    }
    let every_i = every as i32;
    let decades: Vec<(u32, i32)> = candidates(a, b, &[1])
        .into_iter()
        .filter(|&(_, k)| k.rem_euclid(every_i) == 0)
        .collect();
    let fits = |t: &[(u32, i32)]| t.len() >= 2 && t.len() - 1 <= max_intervals;
    let (major, minor, step) =
        if decades.len() > MAX_DECADES_FOR_SUBTICKS || (every_i > 1 && decades.len() >= 2) {
            let minor: Vec<(u32, i32)> = if every_i > 1 {
                candidates(a, b, &[1])
                    .into_iter()
                    .filter(|&(_, k)| k.rem_euclid(every_i) != 0)
                    .collect()
            } else {
                candidates(a, b, &[2, 3, 4, 5, 6, 7, 8, 9])
            };
            (decades, minor, every)
        } else {
            let one_two_five = candidates(a, b, &[1, 2, 5]);
            let one_to_nine = candidates(a, b, &[1, 2, 3, 4, 5, 6, 7, 8, 9]);
            if fits(&one_two_five) {
                (one_two_five, candidates(a, b, &[3, 4, 6, 7, 8, 9]), 0.0)
            } else if decades.len() >= 2 {
                (decades, Vec::new(), every)
            } else if fits(&one_to_nine) {
                (one_to_nine, Vec::new(), 0.0)
            } else {
                let mut t = nice_ticks(lo, hi, max_intervals, false)?;
                t.log = true;
                return Some(t);
            }
        };
    Some(Ticks {
        lo,
        hi,
        step,
        values: major.iter().map(|&(m, k)| value(m, k)).collect(),
        labels: major.iter().map(|&(m, k)| label(m, k)).collect(),
        log: true,
        minor: minor.iter().map(|&(m, k)| value(m, k)).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ticks(lo: f64, hi: f64, max_intervals: usize, expand: bool) -> Ticks {
        log_ticks(lo, hi, max_intervals, expand)
            .unwrap_or_else(|| panic!("no log ticks for [{lo}, {hi}]"))
    }

    #[test]
    fn labels_write_the_value() {
        assert_eq!(label(1, 0), "1");
        assert_eq!(label(1, -2), "0.01");
        assert_eq!(label(5, -3), "0.005");
        assert_eq!(label(1, 3), "1000");
        assert_eq!(label(9, 4), "90000");
        assert_eq!(label(1, 5), "1e5");
        assert_eq!(label(1, -4), "1e-4");
        assert_eq!(label(2, -7), "2e-7");
        assert_eq!(value(1, -2), 0.01);
        assert_eq!(value(3, -1), 0.3);
        assert_eq!(value(1, 5), 100_000.0);
    }

    #[test]
    fn decades_for_a_wide_range() {
        let t = ticks(0.013, 870.0, 10, true);
        assert_eq!(t.values, [0.01, 0.1, 1.0, 10.0, 100.0, 1000.0]);
        assert_eq!(t.labels, ["0.01", "0.1", "1", "10", "100", "1000"]);
        assert_eq!((t.lo, t.hi, t.step, t.log), (0.01, 1000.0, 1.0, true));
        // Minor ticks: 2-9 x 10^k inside the range, 8 per decade over 5 decades.
        assert_eq!(t.minor.len(), 40);
        assert_eq!(&t.minor[..3], [0.02, 0.03, 0.04]);
        assert_eq!(t.minor[39], 900.0);
        // Tight: the range stays, only the decades inside are ticks.
        let t = ticks(0.013, 870.0, 10, false);
        assert_eq!(t.values, [0.1, 1.0, 10.0, 100.0]);
        assert_eq!(t.labels, ["0.1", "1", "10", "100"]);
        assert_eq!((t.lo, t.hi), (0.013, 870.0));
        assert_eq!(t.minor[0], 0.02);
        assert_eq!(t.minor[t.minor.len() - 1], 800.0);
    }

    #[test]
    fn far_decades_are_written_short() {
        let t = ticks(2e-6, 3e6, 20, true);
        assert_eq!(
            t.labels,
            [
                "1e-6", "1e-5", "1e-4", "0.001", "0.01", "0.1", "1", "10", "100", "1000", "10000",
                "1e5", "1e6", "1e7"
            ]
        );
    }

    #[test]
    fn many_decades_are_thinned_to_fit() {
        // 13 decades in at most 5 intervals: every 5th decade labelled (1e-10, 1e-5, 1, 1e5),
        // the range widened to those.
        let t = ticks(3e-9, 2e3, 5, true);
        assert_eq!(t.labels, ["1e-10", "1e-5", "1", "1e5"]);
        assert_eq!((t.lo, t.hi, t.step), (1e-10, 1e5, 5.0));
        // The decades in between are the minor ticks.
        assert_eq!(t.minor.len(), 15 - 3);
        assert!(t.minor.contains(&1e-9) && !t.minor.contains(&1e-5));
    }

    #[test]
    fn few_decades_get_one_two_five_ticks() {
        let t = ticks(0.5, 20.0, 10, false);
        assert_eq!(t.labels, ["0.5", "1", "2", "5", "10", "20"]);
        assert_eq!(t.values, [0.5, 1.0, 2.0, 5.0, 10.0, 20.0]);
        assert_eq!(t.step, 0.0);
        assert_eq!(t.minor[..5], [0.6, 0.7, 0.8, 0.9, 3.0]);
        // Too many for the intervals allowed: the decades alone.
        let t = ticks(0.5, 20.0, 3, false);
        assert_eq!(t.labels, ["1", "10"]);
    }

    #[test]
    fn sub_decade_ranges_keep_two_labelled_ticks() {
        // Expanded: the enclosing decade with its 1-2-5 ticks.
        let t = ticks(2.3, 4.1, 8, true);
        assert_eq!((t.lo, t.hi), (1.0, 10.0));
        assert_eq!(t.labels, ["1", "2", "5", "10"]);
        // Tight, within a decade: 1-9 x 10^k.
        let t = ticks(0.23, 0.61, 8, false);
        assert_eq!(t.labels, ["0.3", "0.4", "0.5", "0.6"]);
        // Tight, between neighbouring integers: linear ticks, still labelled with the value.
        let t = ticks(2.12, 2.87, 8, false);
        assert!(t.values.len() >= 2, "{t:?}");
        assert!(t.log);
        assert!(
            t.values.iter().all(|&v| (2.12..=2.87).contains(&v)),
            "{t:?}"
        );
        assert_eq!(t.labels[0], "2.2");
    }

    #[test]
    fn invalid_ranges_have_no_ticks() {
        assert!(log_ticks(0.0, 10.0, 5, true).is_none());
        assert!(log_ticks(-1.0, 10.0, 5, true).is_none());
        assert!(log_ticks(10.0, 1.0, 5, true).is_none());
        assert!(log_ticks(1.0, f64::INFINITY, 5, true).is_none());
        assert!(log_ticks(f64::NAN, 1.0, 5, true).is_none());
    }
}
