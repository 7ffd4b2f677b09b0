//! The RGB pixel buffer figures are drawn into, and integer pixel rectangles.

use crate::color::Rgb;

/// An axis-aligned rectangle of whole pixels: columns `x..x + width`, rows `y..y + height`
/// (row 0 at the top of the image).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    /// Leftmost column.
    pub x: i32,
    /// Topmost row.
    pub y: i32,
    /// Width in pixels.
    pub width: i32,
    /// Height in pixels.
    pub height: i32,
}

impl Rect {
    /// One past the rightmost column.
    pub fn right(&self) -> i32 {
        self.x + self.width
    }

    /// One past the bottom row.
    pub fn bottom(&self) -> i32 {
        self.y + self.height
    }

    /// Whether pixel (`px`, `py`) lies inside.
    pub fn contains(&self, px: i32, py: i32) -> bool {
        px >= self.x && px < self.right() && py >= self.y && py < self.bottom()
    }

    /// The overlap of two rectangles (zero-sized if they do not overlap).
    pub fn intersect(&self, other: &Rect) -> Rect {
        let x0 = self.x.max(other.x);
        let y0 = self.y.max(other.y);
        let x1 = self.right().min(other.right());
        let y1 = self.bottom().min(other.bottom());
        Rect {
            x: x0,
            y: y0,
            width: (x1 - x0).max(0),
            height: (y1 - y0).max(0),
        }
    }
}

/// An 8-bit RGB image, rows top to bottom, 3 bytes per pixel, no padding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbImage {
    width: u32,
    height: u32,
    data: Vec<u8>,
}

impl RgbImage {
    /// A `width` x `height` image filled with `background`.
    pub fn new(width: u32, height: u32, background: Rgb) -> Self {
        let n = width as usize * height as usize;
        let mut data = Vec::with_capacity(n * 3);
        for _ in 0..n {
            data.extend_from_slice(&[background.r, background.g, background.b]);
        }
        Self {
            width,
            height,
            data,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The raw RGB bytes, row-major from the top-left pixel, 3 bytes per pixel.
    pub fn as_rgb_bytes(&self) -> &[u8] {
        &self.data
    }

    /// The whole image as a rectangle.
    pub fn bounds(&self) -> Rect {
        Rect {
            x: 0,
            y: 0,
            width: self.width as i32,
            height: self.height as i32,
        }
    }

    /// The colour at column `x`, row `y`, or `None` outside the image.
    pub fn pixel(&self, x: i32, y: i32) -> Option<Rgb> {
        let i = self.index(x, y)?;
        Some(Rgb::new(self.data[i], self.data[i + 1], self.data[i + 2]))
    }

    fn index(&self, x: i32, y: i32) -> Option<usize> {
        if x < 0 || y < 0 || x as u32 >= self.width || y as u32 >= self.height {
            return None;
        }
        Some((y as usize * self.width as usize + x as usize) * 3)
    }

    /// Blends `color` with opacity `alpha` (0-1) over pixel (`x`, `y`) if it lies in `clip`
    /// and in the image.
    pub(crate) fn blend(&mut self, x: i32, y: i32, color: Rgb, alpha: f32, clip: &Rect) {
        if !clip.contains(x, y) {
            return;
        }
        if let Some(i) = self.index(x, y) {
            let bg = Rgb::new(self.data[i], self.data[i + 1], self.data[i + 2]);
            let c = if alpha >= 1.0 {
                color
            } else {
                color.over(bg, alpha)
            };
            self.data[i] = c.r;
            self.data[i + 1] = c.g;
            self.data[i + 2] = c.b;
        }
    }

    /// Blends `color` with opacity `alpha` over every pixel of `rect` that lies in `clip`.
    pub(crate) fn fill_rect(&mut self, rect: &Rect, color: Rgb, alpha: f32, clip: &Rect) {
        let r = rect.intersect(clip).intersect(&self.bounds());
        if r.width == 0 || r.height == 0 {
            return;
        }
        if r.width * r.height < 64 {
            for y in r.y..r.bottom() {
                for x in r.x..r.right() {
                    self.blend(x, y, color, alpha, &r);
                }
            }
            return;
        }
        let blender = Blender::new(color, alpha);
        let w = self.width as usize;
        for y in r.y..r.bottom() {
            let start = (y as usize * w + r.x as usize) * 3;
            let end = start + r.width as usize * 3;
            for px in self.data[start..end].chunks_exact_mut(3) {
                blender.apply(px);
            }
        }
    }

    /// Blends with `blender` over rows `y0..=y1` of column `x`, limited to `clip` and the image.
    pub(crate) fn blend_column(
        &mut self,
        x: i32,
        y0: i32,
        y1: i32,
        blender: &Blender,
        clip: &Rect,
    ) {
        let c = clip.intersect(&self.bounds());
        if x < c.x || x >= c.right() {
            return;
        }
        let w = self.width as usize;
        for y in y0.max(c.y)..=y1.min(c.bottom() - 1) {
            let i = (y as usize * w + x as usize) * 3;
            blender.apply(&mut self.data[i..i + 3]);
        }
    }

    /// Draws the 1-pixel outline of `rect` in `color`.
    pub(crate) fn stroke_rect(&mut self, rect: &Rect, color: Rgb) {
        let all = self.bounds();
        let (x0, y0, x1, y1) = (rect.x, rect.y, rect.right() - 1, rect.bottom() - 1);
        for x in x0..=x1 {
            self.blend(x, y0, color, 1.0, &all);
            self.blend(x, y1, color, 1.0, &all);
        }
        for y in y0..=y1 {
            self.blend(x0, y, color, 1.0, &all);
            self.blend(x1, y, color, 1.0, &all);
        }
    }
}

/// Blending of one colour at one opacity as per-channel lookup tables (the same results as
/// [`Rgb::over`], computed once for large fills).
pub(crate) struct Blender {
    lut: [[u8; 256]; 3],
}

impl Blender {
    pub fn new(color: Rgb, alpha: f32) -> Self {
        let mut lut = [[0u8; 256]; 3];
        for v in 0..=255u8 {
            let c = color.over(Rgb::new(v, v, v), alpha);
            lut[0][usize::from(v)] = c.r;
            lut[1][usize::from(v)] = c.g;
            lut[2][usize::from(v)] = c.b;
        }
        Self { lut }
    }

    /// Blends over one RGB pixel (3 bytes).
    pub fn apply(&self, px: &mut [u8]) {
        for (ch, v) in px.iter_mut().enumerate().take(3) {
            *v = self.lut[ch][usize::from(*v)];
        }
    }
}
