//! Checks of a panel's series lengths and style parameters before anything is drawn.

use crate::error::PlotError;
use crate::panel::Panel;
use crate::series::Span;

fn style_error(
    i: usize,
    p: &Panel,
    what: &'static str,
    value: f64,
    allowed: &'static str,
) -> PlotError {
    PlotError::InvalidStyle {
        panel: i,
        panel_title: p.title.clone(),
        what,
        value,
        allowed,
    }
}

fn in_range(v: f32, lo: f32, hi: f32) -> bool {
    v >= lo && v <= hi
}

/// Fails on the first series whose slices differ in length or whose width, dash pattern or
/// opacity is out of range; `figure_spans` are the figure-wide spans drawn in this panel too.
pub(crate) fn check_panel(i: usize, p: &Panel, figure_spans: &[Span]) -> Result<(), PlotError> {
    let mismatch = |kind, series: &str, what, x_len, other_len| PlotError::LengthMismatch {
        panel: i,
        panel_title: p.title.clone(),
        kind,
        series: series.to_string(),
        what,
        x_len,
        other_len,
    };
    for l in &p.lines {
        if l.x.len() != l.y.len() {
            return Err(mismatch("line", &l.label, "y", l.x.len(), l.y.len()));
        }
        if !in_range(l.width_px, 0.5, 20.0) {
            return Err(style_error(
                i,
                p,
                "line width [px]",
                l.width_px.into(),
                "0.5-20",
            ));
        }
        if let Some((on, off)) = l.dash_px {
            for v in [on, off] {
                if !in_range(v, 0.5, 1000.0) {
                    return Err(style_error(i, p, "dash length [px]", v.into(), "0.5-1000"));
                }
            }
        }
    }
    for b in &p.bands {
        if b.x.len() != b.lower.len() {
            return Err(mismatch(
                "band",
                &b.label,
                "lower",
                b.x.len(),
                b.lower.len(),
            ));
        }
        if b.x.len() != b.upper.len() {
            return Err(mismatch(
                "band",
                &b.label,
                "upper",
                b.x.len(),
                b.upper.len(),
            ));
        }
        if !in_range(b.alpha, 0.0, 1.0) {
            return Err(style_error(i, p, "band opacity", b.alpha.into(), "0-1"));
        }
    }
    for s in figure_spans.iter().chain(&p.spans) {
        if !in_range(s.alpha, 0.0, 1.0) {
            return Err(style_error(i, p, "span opacity", s.alpha.into(), "0-1"));
        }
    }
    Ok(())
}
