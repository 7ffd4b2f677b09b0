//! Min/max decimation: reduces a long series to at most four points per pixel column (first,
//! minimum, maximum and last, in their original order), so drawing costs O(plot width) while
//! every extreme (a one-sample spike) stays visible. Non-finite points split the polyline.

use crate::layout::PanelGeometry;

/// Pixel coordinates are clamped to this magnitude so far-off values stay finite (the visible
/// part of a chord to such a point moves by well under a pixel).
const FAR_PX: f64 = 1e7;

#[derive(Clone, Copy)]
struct Pt {
    index: usize,
    px: f64,
    py: f64,
}

struct Column {
    key: i64,
    first: Pt,
    last: Pt,
    min: Pt,
    max: Pt,
}

impl Column {
    fn new(key: i64, p: Pt) -> Self {
        Self {
            key,
            first: p,
            last: p,
            min: p,
            max: p,
        }
    }

    fn add(&mut self, p: Pt) {
        self.last = p;
        if p.py < self.min.py {
            self.min = p;
        }
        if p.py > self.max.py {
            self.max = p;
        }
    }

    /// Appends the column's representative points in index order, without duplicates.
    fn emit(&self, out: &mut Vec<(f64, f64)>) {
        let mut pts = [self.first, self.min, self.max, self.last];
        pts.sort_by_key(|p| p.index);
        let mut prev = usize::MAX;
        for p in pts {
            if p.index != prev {
                out.push((p.px, p.py));
                prev = p.index;
            }
        }
    }
}

/// The polylines (pixel coordinates, see [`PanelGeometry::x_to_px`]) that draw `(x, y)` in
/// `geometry`'s plot area; one per run of finite points.
pub(crate) fn decimate(x: &[f64], y: &[f64], geometry: &PanelGeometry) -> Vec<Vec<(f64, f64)>> {
    let area = geometry.plot_area;
    // Everything left (right) of the plot area shares one column key.
    let (key_lo, key_hi) = (f64::from(area.x) - 1.0, f64::from(area.right()));
    let mut lines = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let mut column: Option<Column> = None;
    for (index, (&xv, &yv)) in x.iter().zip(y).enumerate() {
        if !(xv.is_finite() && yv.is_finite()) {
            if let Some(c) = column.take() {
                c.emit(&mut current);
            }
            if !current.is_empty() {
                lines.push(std::mem::take(&mut current));
            }
            continue;
        }
        let p = Pt {
            index,
            px: geometry.x_to_px(xv).clamp(-FAR_PX, FAR_PX),
            py: geometry.y_to_px(yv).clamp(-FAR_PX, FAR_PX),
        };
        let key = p.px.floor().clamp(key_lo, key_hi) as i64;
        match &mut column {
            Some(c) if c.key == key => c.add(p),
            _ => {
                if let Some(c) = column.replace(Column::new(key, p)) {
                    c.emit(&mut current);
                }
            }
        }
    }
    if let Some(c) = column {
        c.emit(&mut current);
    }
    if !current.is_empty() {
        lines.push(current);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canvas::Rect;
    use crate::ticks::nice_ticks;

    fn geometry(width: i32) -> Option<PanelGeometry> {
        Some(PanelGeometry {
            plot_area: Rect {
                x: 10,
                y: 5,
                width,
                height: 101,
            },
            x_ticks: nice_ticks(0.0, 1.0, 5, false)?,
            y_ticks: nice_ticks(-1.0, 1.0, 5, false)?,
        })
    }

    #[test]
    fn spike_survives_and_output_is_bounded() {
        let Some(g) = geometry(100) else {
            panic!("ticks for a valid range")
        };
        let n = 54_000;
        let x: Vec<f64> = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
        let mut y = vec![0.0; n];
        y[31_337] = 1.0; // top of the y range
        let lines = decimate(&x, &y, &g);
        assert_eq!(lines.len(), 1);
        assert!(lines[0].len() <= 4 * 100, "{} points", lines[0].len());
        let top = g.y_to_px(1.0);
        let spike_px = g.x_to_px(x[31_337]);
        assert!(lines[0].iter().any(|&(px, py)| py == top && px == spike_px));
    }

    #[test]
    fn non_finite_points_split_the_line() {
        let Some(g) = geometry(100) else {
            panic!("ticks for a valid range")
        };
        let x = [0.0, 0.1, 0.2, 0.3, f64::NAN, 0.5, 0.6, 0.7];
        let y = [0.0, 0.1, f64::INFINITY, 0.3, 0.4, 0.5, 0.6, 0.7];
        let lines = decimate(&x, &y, &g);
        let lens: Vec<usize> = lines.iter().map(Vec::len).collect();
        assert_eq!(lens, [2, 1, 3]);
    }
}
