//! Drawing one panel: spans, grid, bands, markers, lines, axes, labels and legend, in that order.
//! Panel and geometry come in axis units (a log axis's data as `log10`, drawn linearly).

use crate::band::fill_band;
use crate::canvas::{Rect, RgbImage};
use crate::color::{Rgb, series_color, span_color};
use crate::decimate::decimate;
use crate::layout::{Metrics, PanelGeometry};
use crate::legend::{Swatch, draw_legend};
use crate::panel::Panel;
use crate::raster::{Mask, stroke_polyline};
use crate::series::{DEFAULT_DASH_PX, Span};
use crate::text::{HAlign, TextStyle, VAlign, text_width_px};

/// Opacity of black for grid lines (light grey on white, still visible over shading).
const GRID_ALPHA: f32 = 0.13;
/// Width of marker lines in pixels.
const MARKER_WIDTH_PX: f64 = 1.5;

/// A dash pattern in image pixels at the figure scale.
fn dash(d: Option<(f32, f32)>, m: &Metrics) -> Option<(f64, f64)> {
    d.map(|(on, off)| (f64::from(on) * m.stroke(), f64::from(off) * m.stroke()))
}

/// Columns of `area` whose centres lie in `[x0, x1]` (data units), as an inclusive range.
fn span_columns(g: &PanelGeometry, x0: f64, x1: f64) -> Option<(i32, i32)> {
    if !(x0.is_finite() && x1.is_finite()) {
        return None;
    }
    let a = g.plot_area;
    let lo = (g.x_to_px(x0).clamp(-1e7, 1e7) - 0.5 - 1e-6).ceil() as i32;
    let hi = (g.x_to_px(x1).clamp(-1e7, 1e7) - 0.5 + 1e-6).floor() as i32;
    let (lo, hi) = (lo.max(a.x), hi.min(a.right() - 1));
    (lo <= hi).then_some((lo, hi))
}

/// Draws `panel` (plus the figure-wide `figure_spans`) into its `g.plot_area`; `x_labels`
/// controls the x tick labels and x label (off for upper panels of a shared x axis).
pub(crate) fn draw_panel(
    image: &mut RgbImage,
    panel: &Panel,
    figure_spans: &[Span],
    g: &PanelGeometry,
    m: &Metrics,
    x_labels: bool,
) {
    let area = g.plot_area;
    let spans: Vec<&Span> = figure_spans.iter().chain(&panel.spans).collect();
    for (k, s) in spans.iter().enumerate() {
        if let Some((c0, c1)) = span_columns(g, s.x_start, s.x_end) {
            let r = Rect {
                x: c0,
                y: area.y,
                width: c1 - c0 + 1,
                height: area.height,
            };
            image.fill_rect(&r, s.color.unwrap_or_else(|| span_color(k)), s.alpha, &area);
        }
    }
    if panel.grid {
        draw_grid(image, g);
    }
    for (k, b) in panel.bands.iter().enumerate() {
        fill_band(
            image,
            b,
            g,
            b.color.unwrap_or_else(|| series_color(k)),
            b.alpha,
        );
    }
    let mut mask = Mask::new(area);
    let (top, bottom) = (f64::from(area.y), f64::from(area.bottom()));
    for mk in &panel.markers {
        if mk.x.is_finite() {
            let px = g.x_to_px(mk.x).floor() + 0.5;
            let d = dash(mk.dashed.then_some(DEFAULT_DASH_PX), m);
            let width = MARKER_WIDTH_PX * m.stroke();
            stroke_polyline(&mut mask, &[(px, top), (px, bottom)], width, d);
            mask.composite(image, mk.color);
        }
    }
    for (k, l) in panel.lines.iter().enumerate() {
        for poly in decimate(&l.x, &l.y, g) {
            stroke_polyline(
                &mut mask,
                &poly,
                f64::from(l.width_px) * m.stroke(),
                dash(l.dash_px, m),
            );
        }
        mask.composite(image, l.color.unwrap_or_else(|| series_color(k)));
    }
    draw_axes(image, g, m, x_labels);
    draw_span_labels(image, g, &spans, m);
    draw_marker_labels(image, panel, g, m);
    let mut entries = Vec::new();
    for (k, l) in panel
        .lines
        .iter()
        .enumerate()
        .filter(|(_, l)| !l.label.is_empty())
    {
        let c = l.color.unwrap_or_else(|| series_color(k));
        let swatch = Swatch::Line(c, f64::from(l.width_px) * m.stroke(), dash(l.dash_px, m));
        entries.push((l.label.clone(), swatch));
    }
    for (k, b) in panel
        .bands
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.label.is_empty())
    {
        let swatch = Swatch::Fill(b.color.unwrap_or_else(|| series_color(k)), b.alpha);
        entries.push((b.label.clone(), swatch));
    }
    let span_row = if spans.iter().any(|s| !s.label.is_empty()) {
        m.text_h
    } else {
        0
    };
    draw_legend(image, &area, panel.legend, &entries, span_row, m);
    draw_titles(image, panel, g, m, x_labels);
}

fn draw_grid(image: &mut RgbImage, g: &PanelGeometry) {
    let area = g.plot_area;
    for &v in &g.x_ticks.values {
        let c = g.x_to_px(v).floor() as i32;
        let r = Rect {
            x: c,
            y: area.y,
            width: 1,
            height: area.height,
        };
        image.fill_rect(&r, Rgb::BLACK, GRID_ALPHA, &area);
    }
    for &v in &g.y_ticks.values {
        let r = Rect {
            x: area.x,
            y: g.y_to_px(v).floor() as i32,
            width: area.width,
            height: 1,
        };
        image.fill_rect(&r, Rgb::BLACK, GRID_ALPHA, &area);
    }
}

/// Frame one pixel outside the plot area, outward ticks, tick labels, shorter unlabelled minor
/// ticks (log axes).
fn draw_axes(image: &mut RgbImage, g: &PanelGeometry, m: &Metrics, x_labels: bool) {
    let a = g.plot_area;
    let all = image.bounds();
    let t = m.u(1);
    for k in 1..=t {
        let ring = Rect {
            x: a.x - k,
            y: a.y - k,
            width: a.width + 2 * k,
            height: a.height + 2 * k,
        };
        image.stroke_rect(&ring, Rgb::BLACK);
    }
    let frame = Rect {
        x: a.x - t,
        y: a.y - t,
        width: a.width + 2 * t,
        height: a.height + 2 * t,
    };
    let tick_style = |h, v| TextStyle::new(Rgb::BLACK, m.scale, h, v);
    let minor_len = (m.tick_len * 3 / 5).max(1);
    for &v in &g.x_ticks.minor {
        let tick = Rect {
            x: g.x_to_px(v).floor() as i32,
            y: frame.bottom(),
            width: t,
            height: minor_len,
        };
        image.fill_rect(&tick, Rgb::BLACK, 1.0, &all);
    }
    for &v in &g.y_ticks.minor {
        let tick = Rect {
            x: frame.x - minor_len,
            y: g.y_to_px(v).floor() as i32,
            width: minor_len,
            height: t,
        };
        image.fill_rect(&tick, Rgb::BLACK, 1.0, &all);
    }
    for (&v, label) in g.x_ticks.values.iter().zip(&g.x_ticks.labels) {
        let c = g.x_to_px(v).floor() as i32;
        let tick = Rect {
            x: c,
            y: frame.bottom(),
            width: t,
            height: m.tick_len,
        };
        image.fill_rect(&tick, Rgb::BLACK, 1.0, &all);
        if x_labels {
            let style = tick_style(HAlign::Center, VAlign::Top);
            image.text_at(c + 1, tick.bottom() + m.u(4), label, &style, &all);
        }
    }
    for (&v, label) in g.y_ticks.values.iter().zip(&g.y_ticks.labels) {
        let r = g.y_to_px(v).floor() as i32;
        let tick = Rect {
            x: frame.x - m.tick_len,
            y: r,
            width: m.tick_len,
            height: t,
        };
        image.fill_rect(&tick, Rgb::BLACK, 1.0, &all);
        let style = tick_style(HAlign::Right, VAlign::Middle);
        image.text_at(tick.x - m.u(4), r + 1, label, &style, &all);
    }
}

/// Span labels along the top edge: horizontal if they fit the span, else upwards, else none.
fn draw_span_labels(image: &mut RgbImage, g: &PanelGeometry, spans: &[&Span], m: &Metrics) {
    let a = g.plot_area;
    for s in spans.iter().filter(|s| !s.label.is_empty()) {
        let Some((c0, c1)) = span_columns(g, s.x_start, s.x_end) else {
            continue;
        };
        let span_w = c1 - c0 + 1;
        let text_w = text_width_px(&s.label, m.scale) as i32;
        let mid = (c0 + c1 + 1) / 2;
        let style = TextStyle::new(Rgb::DARK_GREY, m.scale, HAlign::Center, VAlign::Top);
        if text_w + m.u(6) <= span_w {
            image.text_at(mid, a.y + m.u(3), &s.label, &style, &a);
        } else if m.text_h + m.u(2) <= span_w && text_w + m.u(6) <= a.height / 2 {
            image.text_up_at(mid, a.y + m.u(4), &s.label, &style, &a);
        }
    }
}

/// Marker labels beside the top of their line (left of it near the right edge), one text row
/// below the span labels.
fn draw_marker_labels(image: &mut RgbImage, panel: &Panel, g: &PanelGeometry, m: &Metrics) {
    let a = g.plot_area;
    for mk in panel
        .markers
        .iter()
        .filter(|mk| !mk.label.is_empty() && mk.x.is_finite())
    {
        let c = g.x_to_px(mk.x).floor() as i32;
        if c < a.x || c >= a.right() {
            continue;
        }
        let w = text_width_px(&mk.label, m.scale) as i32;
        let y = a.y + m.u(3) + m.text_h + m.u(4);
        let (x, h) = if c + m.u(4) + w < a.right() - m.u(2) {
            (c + m.u(4), HAlign::Left)
        } else {
            (c - m.u(3), HAlign::Right)
        };
        let style = TextStyle::new(mk.color, m.scale, h, VAlign::Top);
        let back = Rect {
            x: if h == HAlign::Left { x - 1 } else { x - w - 1 },
            y: y - 1,
            width: w + 2,
            height: m.text_h,
        };
        image.fill_rect(&back, Rgb::WHITE, 0.75, &a);
        image.text_at(x, y, &mk.label, &style, &a);
    }
}

/// Panel title (bold) above the plot, x label below, y label upwards at the left edge.
fn draw_titles(
    image: &mut RgbImage,
    panel: &Panel,
    g: &PanelGeometry,
    m: &Metrics,
    x_labels: bool,
) {
    let a = g.plot_area;
    let all = image.bounds();
    let cx = a.x + a.width / 2;
    if !panel.title.is_empty() {
        let style = TextStyle::new(Rgb::BLACK, m.scale, HAlign::Center, VAlign::Bottom);
        // Drawn twice, one pixel apart: a faux bold face.
        image.text_at(cx, a.y - m.u(4), &panel.title, &style, &all);
        image.text_at(cx + 1, a.y - m.u(4), &panel.title, &style, &all);
    }
    if x_labels && !panel.x_label.is_empty() {
        let y = a.bottom() + m.u(1) + m.tick_len + m.u(4) + m.text_h + m.u(6);
        let style = TextStyle::new(Rgb::BLACK, m.scale, HAlign::Center, VAlign::Top);
        image.text_at(cx, y, &panel.x_label, &style, &all);
    }
    if !panel.y_label.is_empty() {
        let style = TextStyle::new(Rgb::BLACK, m.scale, HAlign::Left, VAlign::Middle);
        image.text_up_at(m.pad, a.y + a.height / 2, &panel.y_label, &style, &all);
    }
}
