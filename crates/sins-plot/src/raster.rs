//! Anti-aliased thick polylines: each segment is a capsule whose coverage goes into a mask
//! (maximum over segments, so joints are not darkened), then the mask is blended in one colour.
//! Coordinates are continuous pixels: pixel (i, j) spans [i, i+1) x [j, j+1), centre (i+0.5, j+0.5).

use crate::canvas::{Rect, RgbImage};
use crate::color::Rgb;

/// Per-pixel coverage (0-255) over a clip rectangle.
pub(crate) struct Mask {
    clip: Rect,
    coverage: Vec<u8>,
    /// Touched region (x0, y0, x1, y1), inclusive, or `None`.
    dirty: Option<(i32, i32, i32, i32)>,
}

impl Mask {
    pub fn new(clip: Rect) -> Self {
        let n = clip.width.max(0) as usize * clip.height.max(0) as usize;
        Self {
            clip,
            coverage: vec![0; n],
            dirty: None,
        }
    }

    fn mark(&mut self, x0: i32, y0: i32, x1: i32, y1: i32) {
        self.dirty = Some(match self.dirty {
            None => (x0, y0, x1, y1),
            Some((a, b, c, d)) => (a.min(x0), b.min(y0), c.max(x1), d.max(y1)),
        });
    }

    /// Adds the capsule of radius `radius` around the segment (x0, y0)-(x1, y1).
    pub fn capsule(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, radius: f64) {
        let reach = radius + 0.5;
        let Some((x0, y0, x1, y1)) = clip_segment(x0, y0, x1, y1, &self.clip, reach + 1.0) else {
            return;
        };
        let (dx, dy) = (x1 - x0, y1 - y0);
        let len2 = dx * dx + dy * dy;
        let len = len2.sqrt();
        let c = self.clip;
        let bx0 = ((x0.min(x1) - reach).floor() as i32).max(c.x);
        let bx1 = ((x0.max(x1) + reach).floor() as i32).min(c.right() - 1);
        let by0 = ((y0.min(y1) - reach).floor() as i32).max(c.y);
        let by1 = ((y0.max(y1) + reach).floor() as i32).min(c.bottom() - 1);
        if bx0 > bx1 || by0 > by1 {
            return;
        }
        self.mark(bx0, by0, bx1, by1);
        for j in by0..=by1 {
            let yc = f64::from(j) + 0.5;
            // Columns of this row that can be within `reach` of the segment.
            let (mut i0, mut i1) = (bx0, bx1);
            if dy.abs() > 1e-9 * len.max(1.0) {
                let xl = x0 + (yc - y0) * dx / dy;
                let half = (reach + 1.0) * len / dy.abs();
                i0 = i0.max((xl - half).floor() as i32);
                i1 = i1.min((xl + half).floor() as i32);
            }
            let row = ((j - c.y) * c.width) as usize;
            for i in i0..=i1 {
                let xc = f64::from(i) + 0.5;
                let t = if len2 > 0.0 {
                    (((xc - x0) * dx + (yc - y0) * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let (ex, ey) = (xc - (x0 + t * dx), yc - (y0 + t * dy));
                let cov = (reach - (ex * ex + ey * ey).sqrt()).clamp(0.0, 1.0);
                if cov > 0.0 {
                    let v = (cov * 255.0).round() as u8;
                    let k = row + (i - c.x) as usize;
                    if v > self.coverage[k] {
                        self.coverage[k] = v;
                    }
                }
            }
        }
    }

    /// Blends `color` over `image` with the mask as opacity, then clears the mask.
    pub fn composite(&mut self, image: &mut RgbImage, color: Rgb) {
        let Some((x0, y0, x1, y1)) = self.dirty.take() else {
            return;
        };
        let c = self.clip;
        for j in y0..=y1 {
            let row = ((j - c.y) * c.width) as usize;
            for i in x0..=x1 {
                let k = row + (i - c.x) as usize;
                let v = self.coverage[k];
                if v > 0 {
                    image.blend(i, j, color, f32::from(v) / 255.0, &c);
                    self.coverage[k] = 0;
                }
            }
        }
    }
}

/// Liang-Barsky clipping of a segment to `clip` grown by `margin` pixels; `None` if outside.
fn clip_segment(
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    clip: &Rect,
    margin: f64,
) -> Option<(f64, f64, f64, f64)> {
    let (xmin, xmax) = (f64::from(clip.x) - margin, f64::from(clip.right()) + margin);
    let (ymin, ymax) = (
        f64::from(clip.y) - margin,
        f64::from(clip.bottom()) + margin,
    );
    let (dx, dy) = (x1 - x0, y1 - y0);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, x0 - xmin),
        (dx, xmax - x0),
        (-dy, y0 - ymin),
        (dy, ymax - y0),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 || t0.is_nan() || t1.is_nan() {
        return None;
    }
    Some((x0 + t0 * dx, y0 + t0 * dy, x0 + t1 * dx, y0 + t1 * dy))
}

/// Strokes the polyline `points` of width `width_px` into `mask`, solid or with the dash pattern
/// `(on, off)` in pixels measured along the path.
pub(crate) fn stroke_polyline(
    mask: &mut Mask,
    points: &[(f64, f64)],
    width_px: f64,
    dash_px: Option<(f64, f64)>,
) {
    let radius = width_px / 2.0;
    if let [(x, y)] = points {
        mask.capsule(*x, *y, *x, *y, radius);
        return;
    }
    let mut phase = 0.0;
    for w in points.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        match dash_px {
            None => mask.capsule(x0, y0, x1, y1, radius),
            Some((on, off)) => {
                let len = ((x1 - x0).powi(2) + (y1 - y0).powi(2)).sqrt();
                if len > 1e5 {
                    // Far off-screen chords: dashing them piece by piece is pointless work.
                    mask.capsule(x0, y0, x1, y1, radius);
                    continue;
                }
                let mut s = 0.0;
                while s < len {
                    let drawing = phase < on;
                    let left_in_dash = if drawing {
                        on - phase
                    } else {
                        on + off - phase
                    };
                    let step = left_in_dash.min(len - s);
                    if drawing {
                        let (ta, tb) = (s / len, (s + step) / len);
                        mask.capsule(
                            x0 + ta * (x1 - x0),
                            y0 + ta * (y1 - y0),
                            x0 + tb * (x1 - x0),
                            y0 + tb * (y1 - y0),
                            radius,
                        );
                    }
                    s += step;
                    phase += step;
                    if phase >= on + off {
                        phase -= on + off;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn horizontal_capsule_covers_expected_rows() {
        let clip = Rect {
            x: 0,
            y: 0,
            width: 20,
            height: 9,
        };
        let mut mask = Mask::new(clip);
        mask.capsule(2.0, 4.5, 17.0, 4.5, 1.0);
        let at = |i: usize, j: usize| mask.coverage[j * 20 + i];
        assert_eq!(at(10, 4), 255);
        assert_eq!(at(10, 3), 128);
        assert_eq!(at(10, 5), 128);
        assert_eq!(at(10, 2), 0);
        assert_eq!(at(10, 6), 0);
        assert_eq!(at(0, 4), 0);
    }

    #[test]
    fn clipping_rejects_outside_and_trims_crossing() {
        let clip = Rect {
            x: 0,
            y: 0,
            width: 10,
            height: 10,
        };
        assert!(clip_segment(-5.0, 20.0, 15.0, 20.0, &clip, 1.0).is_none());
        let (x0, _, x1, _) = clip_segment(-1e9, 5.0, 1e9, 5.0, &clip, 1.0).unwrap_or_default();
        assert_eq!((x0, x1), (-1.0, 11.0));
    }
}
