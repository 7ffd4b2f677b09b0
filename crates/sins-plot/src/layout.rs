//! Figure layout: axis ranges (fixed, tight or 'nice'), tick choice, and where each panel's plot
//! area lies. All panels share the same left edge so stacked x axes line up. Ranges and ticks
//! are in data units, also on log axes (where only positive values count).

use crate::canvas::Rect;
use crate::error::PlotError;
use crate::log_scale::{ticks_to_axis, to_axis};
use crate::log_ticks::log_ticks;
use crate::panel::Panel;
use crate::text::{text_height_px, text_width_px};
use crate::ticks::{Ticks, nice_ticks};

/// Where a panel's data went: its plot area in the image and its axes. Data map linearly (on a
/// log axis, their `log10` maps linearly; see [`Ticks::log`]) onto pixel centres: x =
/// `x_ticks.lo` lands on the centre of the first column of the plot area, `x_ticks.hi` on the
/// centre of the last; y = `y_ticks.hi` on the top row, `y_ticks.lo` on the bottom row.
#[derive(Debug, Clone, PartialEq)]
pub struct PanelGeometry {
    /// The plot area (inside the axis frame), image pixels.
    pub plot_area: Rect,
    /// The x axis: range and ticks, data units, and whether it is logarithmic.
    pub x_ticks: Ticks,
    /// The y axis: range and ticks, data units, and whether it is logarithmic.
    pub y_ticks: Ticks,
}

impl PanelGeometry {
    /// Continuous image x coordinate of data `x` (pixel i spans [i, i+1), centre i + 0.5); NaN
    /// for an `x` that is not positive on a log axis.
    pub fn x_to_px(&self, x: f64) -> f64 {
        let a = &self.plot_area;
        let log = self.x_ticks.log;
        let (lo, hi) = (to_axis(self.x_ticks.lo, log), to_axis(self.x_ticks.hi, log));
        let t = (to_axis(x, log) - lo) / (hi - lo);
        f64::from(a.x) + 0.5 + t * f64::from(a.width - 1)
    }

    /// Continuous image y coordinate of data `y` (row j spans [j, j+1), centre j + 0.5); NaN
    /// for a `y` that is not positive on a log axis.
    pub fn y_to_px(&self, y: f64) -> f64 {
        let a = &self.plot_area;
        let log = self.y_ticks.log;
        let (lo, hi) = (to_axis(self.y_ticks.lo, log), to_axis(self.y_ticks.hi, log));
        let t = (hi - to_axis(y, log)) / (hi - lo);
        f64::from(a.y) + 0.5 + t * f64::from(a.height - 1)
    }

    /// The same geometry in axis units: a log axis's ends and ticks as their `log10`, read as a
    /// linear axis (for drawing data already in axis units).
    pub(crate) fn in_axis_units(&self) -> PanelGeometry {
        PanelGeometry {
            plot_area: self.plot_area,
            x_ticks: ticks_to_axis(&self.x_ticks),
            y_ticks: ticks_to_axis(&self.y_ticks),
        }
    }
}

/// Pixel sizes derived from the figure scale (1 for the default look, 2 for twice the pixel
/// density).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Metrics {
    /// Integer magnification of text, strokes and spacing.
    pub scale: u32,
    /// Height of one text line.
    pub text_h: i32,
    pub pad: i32,
    pub tick_len: i32,
}

impl Metrics {
    pub fn new(scale: u32) -> Self {
        let scale = scale.clamp(1, 4);
        Self {
            scale,
            text_h: text_height_px(scale) as i32,
            pad: 8 * scale as i32,
            tick_len: 5 * scale as i32,
        }
    }

    /// `n` unscaled pixels at this scale.
    pub fn u(&self, n: i32) -> i32 {
        n * self.scale as i32
    }

    /// Stroke widths and dash lengths are multiplied by this.
    pub fn stroke(&self) -> f64 {
        f64::from(self.scale)
    }

    /// Height of the figure title strip (0 without a title).
    pub fn figure_title_h(&self, has_title: bool) -> i32 {
        if has_title {
            2 * self.text_h + self.u(10)
        } else {
            0
        }
    }

    /// Space above a plot area within its panel slot (panel title row).
    pub fn top_margin(&self) -> i32 {
        self.pad + self.text_h + self.u(6)
    }

    /// Space below a plot area: ticks, tick labels, x label.
    pub fn bottom_margin(&self) -> i32 {
        self.tick_len + self.u(4) + self.text_h + self.u(6) + self.text_h + self.pad
    }

    pub fn right_margin(&self) -> i32 {
        text_width_px("00000", self.scale) as i32 / 2 + self.u(12)
    }
}

fn range_error(
    i: usize,
    p: &Panel,
    axis: &'static str,
    r: (f64, f64),
    why: &'static str,
) -> PlotError {
    PlotError::InvalidRange {
        panel: i,
        panel_title: p.title.clone(),
        axis,
        lo: r.0,
        hi: r.1,
        reason: why,
    }
}

/// Whether `v` can be drawn on an axis: finite, and positive on a log axis.
fn drawable(v: f64, log: bool) -> bool {
    v.is_finite() && (!log || v > 0.0)
}

fn widen(acc: Option<(f64, f64)>, v: f64, log: bool) -> Option<(f64, f64)> {
    if !drawable(v, log) {
        return acc;
    }
    Some(acc.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))))
}

/// Tight range of the drawable x values of all lines and bands of `panel`.
fn data_x_range(panel: &Panel) -> Option<(f64, f64)> {
    let xs = panel
        .lines
        .iter()
        .map(|l| &l.x)
        .chain(panel.bands.iter().map(|b| &b.x));
    xs.flatten()
        .fold(None, |acc, &v| widen(acc, v, panel.x_log))
}

/// Range of the drawable y values (band bounds included) at x inside `[xlo, xhi]`, plus the
/// panel's drawable `y_include` values.
fn data_y_range(panel: &Panel, xlo: f64, xhi: f64) -> Option<(f64, f64)> {
    let log = panel.y_log;
    let inside = |x: f64| x >= xlo && x <= xhi;
    let mut acc = panel
        .y_include
        .iter()
        .fold(None, |acc, &v| widen(acc, v, log));
    for l in &panel.lines {
        for (&x, &y) in l.x.iter().zip(&l.y) {
            if inside(x) {
                acc = widen(acc, y, log);
            }
        }
    }
    for b in &panel.bands {
        for ((&x, &lo), &hi) in b.x.iter().zip(&b.lower).zip(&b.upper) {
            if inside(x) && drawable(lo, log) && drawable(hi, log) {
                acc = widen(widen(acc, lo, log), hi, log);
            }
        }
    }
    acc
}

/// A usable automatic range: no data gives [0, 1] ([1, 10] on a log axis), a single value v
/// gives v +- 1% (+-1 for 0; a log axis has no 0).
fn auto_range(r: Option<(f64, f64)>, log: bool) -> (f64, f64) {
    match r {
        None if log => (1.0, 10.0),
        None => (0.0, 1.0),
        Some((lo, hi)) if hi - lo <= lo.abs().max(hi.abs()) * 1e-10 => {
            let c = 0.5 * (lo + hi);
            let half = if c == 0.0 { 1.0 } else { c.abs() * 0.01 };
            (c - half, c + half)
        }
        Some(r) => r,
    }
}

/// Ticks for the range `r`: [`log_ticks`] on a log axis, [`nice_ticks`] otherwise.
fn axis_ticks(r: (f64, f64), log: bool, max_intervals: usize, expand: bool) -> Option<Ticks> {
    if log {
        log_ticks(r.0, r.1, max_intervals, expand)
    } else {
        nice_ticks(r.0, r.1, max_intervals, expand)
    }
}

/// The x range of panel `i`: fixed, or the tight data range.
fn panel_x_range(i: usize, p: &Panel) -> Result<(f64, f64), PlotError> {
    match p.x_range {
        Some(r) => {
            if axis_ticks(r, p.x_log, 1, false).is_none() {
                return Err(range_error(
                    i,
                    p,
                    "x",
                    r,
                    "bounds must be finite and increasing",
                ));
            }
            Ok(r)
        }
        None => Ok(auto_range(data_x_range(p), p.x_log)),
    }
}

/// What the layout needs of a figure besides its panels (pixels).
pub(crate) struct Frame {
    pub width_px: u32,
    pub panel_height_px: u32,
    pub total_height_px: u32,
    pub titled: bool,
    pub share_x: bool,
    pub x_range: Option<(f64, f64)>,
}

/// Lays out every panel of a figure (validated size) and picks its axes.
pub(crate) fn layout(
    fig: &Frame,
    panels: &[Panel],
    m: &Metrics,
) -> Result<Vec<PanelGeometry>, PlotError> {
    let n = panels.len();
    let top0 = m.figure_title_h(fig.titled);
    let slot_h = fig.panel_height_px as i32;
    let plot_h = slot_h - m.top_margin() - m.bottom_margin();
    let x_ranges: Vec<(f64, f64)> = panels
        .iter()
        .enumerate()
        .map(|(i, p)| panel_x_range(i, p))
        .collect::<Result<_, _>>()?;
    let shared = match (fig.share_x, fig.x_range) {
        (false, _) => None,
        (true, Some(r)) => {
            if axis_ticks(r, panels[0].x_log, 1, false).is_none() {
                let why = "the figure's shared x range must be finite and increasing";
                return Err(range_error(0, &panels[0], "x", r, why));
            }
            Some(r)
        }
        (true, None) => x_ranges
            .iter()
            .copied()
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1))),
    };
    // y axes first: their label widths decide the common left margin.
    let mut y_axes = Vec::with_capacity(n);
    for (i, p) in panels.iter().enumerate() {
        let xr = shared.unwrap_or(x_ranges[i]);
        let max_intervals = (plot_h / (3 * m.text_h + m.u(6))).max(2) as usize;
        let ticks = match p.y_range {
            Some(r) => axis_ticks(r, p.y_log, max_intervals, false)
                .ok_or_else(|| range_error(i, p, "y", r, "bounds must be finite and increasing"))?,
            None => {
                let r = auto_range(data_y_range(p, xr.0, xr.1), p.y_log);
                axis_ticks(r, p.y_log, max_intervals, true)
                    .ok_or_else(|| range_error(i, p, "y", r, "data range cannot be represented"))?
            }
        };
        y_axes.push(ticks);
    }
    let label_w = y_axes
        .iter()
        .flat_map(|t| t.labels.iter())
        .map(|l| text_width_px(l, m.scale) as i32)
        .max()
        .unwrap_or(0);
    let left = m.pad + m.text_h + m.u(8) + label_w + m.u(4) + m.tick_len;
    let plot_w = fig.width_px as i32 - left - m.right_margin();
    if plot_w < 20 || plot_h < 20 {
        return Err(PlotError::InvalidSize {
            width_px: fig.width_px,
            height_px: fig.total_height_px,
            reason: "too small for the axes and labels",
        });
    }
    let mut out = Vec::with_capacity(n);
    for (i, (p, y_ticks)) in panels.iter().zip(y_axes).enumerate() {
        let xr = shared.unwrap_or(x_ranges[i]);
        let x_ticks = x_axis_ticks(xr, p.x_log, plot_w, m)
            .ok_or_else(|| range_error(i, p, "x", xr, "range cannot be represented"))?;
        out.push(PanelGeometry {
            plot_area: Rect {
                x: left,
                y: top0 + i as i32 * slot_h + m.top_margin(),
                width: plot_w,
                height: plot_h,
            },
            x_ticks,
            y_ticks,
        });
    }
    Ok(out)
}

/// x ticks over the tight range `r`: as many as fit with their labels at least two characters
/// apart.
fn x_axis_ticks(r: (f64, f64), log: bool, plot_w: i32, m: &Metrics) -> Option<Ticks> {
    let mut max_intervals = (plot_w / (50 * m.scale as i32 + 20)).max(1) as usize;
    loop {
        let t = axis_ticks(r, log, max_intervals, false)?;
        let widest = t
            .labels
            .iter()
            .map(|l| text_width_px(l, m.scale))
            .max()
            .unwrap_or(0);
        // The closest pair of ticks (a log axis's ticks need not be evenly spaced), as a
        // fraction of the axis.
        let closest = if log {
            let a = ticks_to_axis(&t);
            let gap = a.values.windows(2).map(|w| w[1] - w[0]);
            gap.fold(f64::INFINITY, f64::min) / (a.hi - a.lo)
        } else {
            t.step / (r.1 - r.0)
        };
        let step_px = closest * f64::from(plot_w - 1);
        if max_intervals <= 1 || step_px >= f64::from(widest + 12 * m.scale) {
            return Some(t);
        }
        max_intervals -= 1;
    }
}
