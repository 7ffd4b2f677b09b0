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
    for (axis, log, range) in [("x", p.x_log, p.x_range), ("y", p.y_log, p.y_range)] {
        if let (true, Some(r)) = (log, range) {
            check_log_range(i, p, axis, r)?;
        }
    }
    Ok(())
}

/// A fixed range of a logarithmic axis must be positive (finite and increasing is checked with
/// the layout).
fn check_log_range(
    i: usize,
    p: &Panel,
    axis: &'static str,
    r: (f64, f64),
) -> Result<(), PlotError> {
    if r.0 > 0.0 && r.1 > 0.0 {
        return Ok(());
    }
    Err(PlotError::InvalidRange {
        panel: i,
        panel_title: p.title.clone(),
        axis,
        lo: r.0,
        hi: r.1,
        reason: "a logarithmic axis needs positive bounds",
    })
}

/// With a shared x axis every panel must agree with panel 0 on a logarithmic x axis, and the
/// figure's fixed x range (reported against panel 0) must then be positive.
pub(crate) fn check_shared_x(
    panels: &[Panel],
    share_x: bool,
    x_range: Option<(f64, f64)>,
) -> Result<(), PlotError> {
    let Some(first) = panels.first() else {
        return Ok(());
    };
    if !share_x {
        return Ok(());
    }
    if let Some((i, p)) = panels
        .iter()
        .enumerate()
        .find(|(_, p)| p.x_log != first.x_log)
    {
        return Err(PlotError::SharedXScaleMismatch {
            panel: i,
            panel_title: p.title.clone(),
            scale: if p.x_log { "logarithmic" } else { "linear" },
        });
    }
    match x_range {
        Some(r) if first.x_log => check_log_range(0, first, "x", r),
        _ => Ok(()),
    }
}
