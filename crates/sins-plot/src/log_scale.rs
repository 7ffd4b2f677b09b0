//! Logarithmic axes by transformation: the layout picks ranges and ticks in data units; for
//! drawing, a panel's data on a log axis are replaced by their `log10` (axis units) and the
//! axis's ticks moved to axis units, so the linear drawing code draws them unchanged
//! ([`crate::PanelGeometry`] keeps data units).

use std::borrow::Cow;

use crate::panel::Panel;
use crate::series::{Band, Line, Marker, Span};
use crate::ticks::Ticks;

/// `log10(v)` for a positive `v`; NaN otherwise (a gap in lines and bands, ignored by the
/// automatic ranges).
pub(crate) fn log10_or_nan(v: f64) -> f64 {
    if v > 0.0 { v.log10() } else { f64::NAN }
}

/// A value in axis units: `log10(v)` (NaN unless positive) on a log axis, `v` on a linear one.
pub(crate) fn to_axis(v: f64, log: bool) -> f64 {
    if log { log10_or_nan(v) } else { v }
}

/// A data-unit range in axis units.
fn range_to_axis(r: Option<(f64, f64)>, log: bool) -> Option<(f64, f64)> {
    r.map(|(lo, hi)| (to_axis(lo, log), to_axis(hi, log)))
}

fn all_to_axis(v: &[f64]) -> Vec<f64> {
    v.iter().map(|&x| log10_or_nan(x)).collect()
}

/// A span bound on a log x axis: a finite bound at or below 0 lies left of any positive x, so
/// it becomes the most negative finite number (the span reaches past the left edge; drawing
/// clamps far-off pixel coordinates).
fn span_bound_to_axis(v: f64) -> f64 {
    if v.is_finite() && v <= 0.0 {
        f64::MIN
    } else {
        log10_or_nan(v)
    }
}

/// `spans` with their bounds in axis units (borrowed unchanged for a linear x axis).
pub(crate) fn spans_to_axis(spans: &[Span], x_log: bool) -> Cow<'_, [Span]> {
    if !x_log {
        return Cow::Borrowed(spans);
    }
    Cow::Owned(
        spans
            .iter()
            .map(|s| Span {
                x_start: span_bound_to_axis(s.x_start),
                x_end: span_bound_to_axis(s.x_end),
                ..s.clone()
            })
            .collect(),
    )
}

/// `panel` with every value on a log axis in axis units: lines, bands, fixed ranges, `y_include`,
/// markers and spans (borrowed unchanged when both axes are linear).
pub(crate) fn panel_to_axis(panel: &Panel) -> Cow<'_, Panel> {
    let (xl, yl) = (panel.x_log, panel.y_log);
    if !(xl || yl) {
        return Cow::Borrowed(panel);
    }
    let axis = |v: &[f64], log: bool| if log { all_to_axis(v) } else { v.to_vec() };
    Cow::Owned(Panel {
        title: panel.title.clone(),
        x_label: panel.x_label.clone(),
        y_label: panel.y_label.clone(),
        x_range: range_to_axis(panel.x_range, xl),
        y_range: range_to_axis(panel.y_range, yl),
        x_log: xl,
        y_log: yl,
        y_include: panel.y_include.iter().map(|&v| to_axis(v, yl)).collect(),
        grid: panel.grid,
        legend: panel.legend,
        lines: panel
            .lines
            .iter()
            .map(|l| Line {
                label: l.label.clone(),
                x: axis(&l.x, xl),
                y: axis(&l.y, yl),
                color: l.color,
                width_px: l.width_px,
                dash_px: l.dash_px,
            })
            .collect(),
        bands: panel
            .bands
            .iter()
            .map(|b| Band {
                label: b.label.clone(),
                x: axis(&b.x, xl),
                lower: axis(&b.lower, yl),
                upper: axis(&b.upper, yl),
                color: b.color,
                alpha: b.alpha,
            })
            .collect(),
        spans: spans_to_axis(&panel.spans, xl).into_owned(),
        markers: panel
            .markers
            .iter()
            .map(|m| Marker {
                x: to_axis(m.x, xl),
                ..m.clone()
            })
            .collect(),
    })
}

/// `t` in axis units: on a log axis its ends, ticks and minor ticks become their `log10` and
/// it reads as linear (what drawing the transformed data needs); a linear axis is unchanged.
pub(crate) fn ticks_to_axis(t: &Ticks) -> Ticks {
    if !t.log {
        return t.clone();
    }
    Ticks {
        lo: t.lo.log10(),
        hi: t.hi.log10(),
        step: t.step,
        values: all_to_axis(&t.values),
        labels: t.labels.clone(),
        log: false,
        minor: all_to_axis(&t.minor),
    }
}
