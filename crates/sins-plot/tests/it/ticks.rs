//! Tick generation: 1-2-5 steps, coverage of the range, labels, over many magnitudes.

use sins_plot::{Ticks, nice_ticks};

fn ticks(lo: f64, hi: f64, max_intervals: usize, expand: bool) -> Ticks {
    nice_ticks(lo, hi, max_intervals, expand).unwrap_or_else(|| panic!("no ticks for [{lo}, {hi}]"))
}

/// Properties every tick set must have.
fn check(t: &Ticks, lo: f64, hi: f64, max_intervals: usize, expand: bool) {
    let mantissa = t.step / 10f64.powf(t.step.log10().floor());
    assert!(
        [1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-9),
        "step {} is not 1-2-5",
        t.step
    );
    assert!(
        ((hi - lo) / t.step) <= max_intervals as f64 + 1e-9,
        "too many intervals"
    );
    assert!(
        t.values.len() >= 2,
        "fewer than two ticks for [{lo}, {hi}]: {t:?}"
    );
    let tol = t.step * 1e-6;
    if expand {
        assert!(
            t.lo <= lo + tol && t.hi >= hi - tol,
            "{t:?} misses [{lo}, {hi}]"
        );
        assert!(
            t.lo > lo - t.step && t.hi < hi + t.step,
            "{t:?} overshoots [{lo}, {hi}]"
        );
        assert!(
            (t.values[0] - t.lo).abs() < tol && (t.values[t.values.len() - 1] - t.hi).abs() < tol
        );
    } else {
        assert_eq!((t.lo, t.hi), (lo, hi));
        assert!(t.values[0] >= lo - tol && t.values[0] < lo + t.step);
        assert!(t.values[t.values.len() - 1] <= hi + tol);
        assert!(t.values[t.values.len() - 1] > hi - t.step);
    }
    for w in t.values.windows(2) {
        assert!(
            ((w[1] - w[0]) / t.step - 1.0).abs() < 1e-6,
            "uneven ticks {t:?}"
        );
    }
    for v in &t.values {
        assert!(
            (v / t.step - (v / t.step).round()).abs() < 1e-6,
            "{v} not a multiple of {}",
            t.step
        );
    }
    assert_eq!(t.labels.len(), t.values.len());
    let mut labels = t.labels.clone();
    labels.dedup();
    assert_eq!(
        labels.len(),
        t.labels.len(),
        "duplicate labels {:?}",
        t.labels
    );
}

#[test]
fn hours_axis() {
    let t = ticks(0.0, 15.0, 8, false);
    check(&t, 0.0, 15.0, 8, false);
    assert_eq!(t.step, 2.0);
    assert_eq!(t.labels, ["0", "2", "4", "6", "8", "10", "12", "14"]);
    let t = ticks(0.0, 15.0, 16, false);
    assert_eq!(t.step, 1.0);
    assert_eq!(t.values.len(), 16);
}

#[test]
fn negative_range_expands_to_whole_steps() {
    let t = ticks(-37.0, -2.0, 5, true);
    check(&t, -37.0, -2.0, 5, true);
    assert_eq!((t.lo, t.hi, t.step), (-40.0, 0.0, 10.0));
    assert_eq!(t.labels, ["-40", "-30", "-20", "-10", "0"]);
}

#[test]
fn straddling_zero_with_decimals() {
    let t = ticks(-0.25, 0.71, 10, true);
    check(&t, -0.25, 0.71, 10, true);
    assert_eq!(t.step, 0.1);
    assert_eq!(t.labels[0], "-0.3");
    assert!(t.labels.contains(&"0".to_string()));
    assert_eq!(t.labels[t.labels.len() - 1], "0.8");
}

#[test]
fn tiny_range_uses_scientific_labels() {
    let t = ticks(1e-9, 3e-9, 4, true);
    check(&t, 1e-9, 3e-9, 4, true);
    assert!((t.step - 5e-10).abs() < 1e-24);
    assert_eq!(t.labels, ["1.0e-9", "1.5e-9", "2.0e-9", "2.5e-9", "3.0e-9"]);
}

#[test]
fn huge_range_uses_scientific_labels() {
    let t = ticks(0.0, 4.2e12, 5, false);
    check(&t, 0.0, 4.2e12, 5, false);
    assert_eq!(t.step, 1e12);
    assert_eq!(t.labels, ["0", "1e12", "2e12", "3e12", "4e12"]);
}

#[test]
fn narrow_range_at_large_offset_keeps_distinct_labels() {
    let t = ticks(1000.0, 1000.001, 5, false);
    check(&t, 1000.0, 1000.001, 5, false);
    assert_eq!(t.labels[0], "1000.0000");
    assert_eq!(t.labels[1], "1000.0002");
}

#[test]
fn many_magnitudes_and_interval_counts() {
    for exp in -12..=12 {
        for (a, b) in [
            (0.0, 1.0),
            (-3.7, 8.2),
            (1.01, 1.09),
            (-9.9, -9.1),
            (0.3, 47.0),
        ] {
            let (lo, hi) = (a * 10f64.powi(exp), b * 10f64.powi(exp));
            for max_intervals in [2, 5, 8, 13] {
                for expand in [false, true] {
                    check(
                        &ticks(lo, hi, max_intervals, expand),
                        lo,
                        hi,
                        max_intervals.max(2) + 2,
                        expand,
                    );
                }
            }
        }
    }
}

#[test]
fn invalid_ranges_have_no_ticks() {
    assert!(nice_ticks(1.0, 1.0, 5, true).is_none());
    assert!(nice_ticks(2.0, 1.0, 5, true).is_none());
    assert!(nice_ticks(f64::NAN, 1.0, 5, true).is_none());
    assert!(nice_ticks(0.0, f64::INFINITY, 5, true).is_none());
    assert!(nice_ticks(-f64::MAX, f64::MAX, 5, true).is_none());
    assert!(nice_ticks(1e15, 1e15 + 0.5, 5, true).is_none());
}
