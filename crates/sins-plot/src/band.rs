//! Filling the region between two curves, one pixel column at a time: each column takes the
//! extreme bounds of the samples in it, and columns between sparse samples interpolate linearly.

use crate::canvas::{Blender, Rect, RgbImage};
use crate::color::Rgb;
use crate::layout::PanelGeometry;
use crate::series::Band;

/// Clamp for far-off pixel coordinates (keeps arithmetic finite).
const FAR_PX: f64 = 1e7;

/// Per-column vertical extent (top and bottom continuous pixel y) of the band.
struct Extents {
    area: Rect,
    top: Vec<f64>,
    bottom: Vec<f64>,
}

impl Extents {
    fn widen(&mut self, column: i64, top: f64, bottom: f64) {
        let k = column - i64::from(self.area.x);
        if k >= 0 && k < i64::from(self.area.width) {
            let k = k as usize;
            self.top[k] = self.top[k].min(top);
            self.bottom[k] = self.bottom[k].max(bottom);
        }
    }
}

/// Blends `color` at opacity `alpha` over the plot-area pixels between the band's curves.
pub(crate) fn fill_band(
    image: &mut RgbImage,
    band: &Band,
    geometry: &PanelGeometry,
    color: Rgb,
    alpha: f32,
) {
    let area = geometry.plot_area;
    let w = area.width.max(0) as usize;
    let mut ext = Extents {
        area,
        top: vec![f64::INFINITY; w],
        bottom: vec![f64::NEG_INFINITY; w],
    };
    // (px, top py, bottom py) of the previous finite sample.
    let mut prev: Option<(f64, f64, f64)> = None;
    let samples = band.x.iter().zip(&band.lower).zip(&band.upper);
    for ((&x, &lo), &hi) in samples {
        if !(x.is_finite() && lo.is_finite() && hi.is_finite()) {
            prev = None;
            continue;
        }
        let px = geometry.x_to_px(x).clamp(-FAR_PX, FAR_PX);
        let (a, b) = (
            geometry.y_to_px(hi).clamp(-FAR_PX, FAR_PX),
            geometry.y_to_px(lo).clamp(-FAR_PX, FAR_PX),
        );
        let (top, bottom) = (a.min(b), a.max(b));
        ext.widen(px.floor() as i64, top, bottom);
        if let Some((p0, t0, b0)) = prev {
            let (l, r) = (p0.min(px), p0.max(px));
            let c0 = ((l - 0.5).ceil() as i64).max(i64::from(area.x));
            let c1 = ((r - 0.5).floor() as i64).min(i64::from(area.right()) - 1);
            for c in c0..=c1 {
                let t = if r > l {
                    (c as f64 + 0.5 - p0) / (px - p0)
                } else {
                    0.0
                };
                ext.widen(c, t0 + t * (top - t0), b0 + t * (bottom - b0));
            }
        }
        prev = Some((px, top, bottom));
    }
    let blender = Blender::new(color, alpha);
    for (k, (&top, &bottom)) in ext.top.iter().zip(&ext.bottom).enumerate() {
        if top > bottom {
            continue;
        }
        // Rows whose pixel interval meets [top, bottom].
        let r0 = (top.floor() as i64).max(i64::from(area.y));
        let r1 = ((bottom.ceil() as i64) - 1)
            .max(top.floor() as i64)
            .min(i64::from(area.bottom()) - 1);
        image.blend_column(area.x + k as i32, r0 as i32, r1 as i32, &blender, &area);
    }
}
