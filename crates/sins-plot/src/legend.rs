//! The legend box: one row per labelled line (a stroke sample) or band (a filled swatch).

use crate::canvas::{Rect, RgbImage};
use crate::color::Rgb;
use crate::layout::Metrics;
use crate::raster::{Mask, stroke_polyline};
use crate::series::LegendPosition;
use crate::text::{HAlign, TextStyle, VAlign, text_width_px};

/// What a legend row shows beside its label.
pub(crate) enum Swatch {
    /// A line sample: colour, width in pixels, optional dash pattern.
    Line(Rgb, f64, Option<(f64, f64)>),
    /// A filled box: colour and opacity.
    Fill(Rgb, f32),
}

/// Draws the legend for `entries` (label, swatch) in a corner of `area`, a top corner lowered
/// by `top_reserved_px` (the row of span labels); nothing if there are no entries or the
/// position is `Hidden`.
pub(crate) fn draw_legend(
    image: &mut RgbImage,
    area: &Rect,
    position: LegendPosition,
    entries: &[(String, Swatch)],
    top_reserved_px: i32,
    m: &Metrics,
) {
    if entries.is_empty() || position == LegendPosition::Hidden {
        return;
    }
    let pad = m.u(7);
    let sample_w = m.u(30);
    let gap = m.u(8);
    let row_h = m.text_h + m.u(5);
    let label_w = entries
        .iter()
        .map(|(l, _)| text_width_px(l, m.scale) as i32)
        .max()
        .unwrap_or(0);
    let w = 2 * pad + sample_w + gap + label_w;
    let h = 2 * pad + entries.len() as i32 * row_h - m.u(5);
    let inset = m.u(8);
    let x = match position {
        LegendPosition::TopLeft | LegendPosition::BottomLeft => area.x + inset,
        _ => area.right() - inset - w,
    };
    let y = match position {
        LegendPosition::TopLeft | LegendPosition::TopRight => area.y + top_reserved_px + inset,
        _ => area.bottom() - inset - h,
    };
    let frame = Rect {
        x,
        y,
        width: w,
        height: h,
    }
    .intersect(area);
    image.fill_rect(&frame, Rgb::WHITE, 0.9, area);
    image.stroke_rect(&frame, Rgb::GREY);
    let mut mask = Mask::new(frame);
    for (k, (label, swatch)) in entries.iter().enumerate() {
        let row_top = y + pad + k as i32 * row_h;
        let mid = f64::from(row_top) + f64::from(m.text_h) / 2.0;
        let (sx0, sx1) = (f64::from(x + pad), f64::from(x + pad + sample_w));
        match *swatch {
            Swatch::Line(color, width, dash) => {
                stroke_polyline(
                    &mut mask,
                    &[(sx0 + 1.0, mid), (sx1 - 1.0, mid)],
                    width,
                    dash,
                );
                mask.composite(image, color);
            }
            Swatch::Fill(color, alpha) => {
                let r = Rect {
                    x: x + pad,
                    y: row_top + m.u(1),
                    width: sample_w,
                    height: m.text_h - m.u(2),
                };
                image.fill_rect(&r, color, alpha.max(0.3), &frame);
            }
        }
        let style = TextStyle::new(Rgb::BLACK, m.scale, HAlign::Left, VAlign::Top);
        image.text_at(x + pad + sample_w + gap, row_top, label, &style, &frame);
    }
}
