//! Colours: an 8-bit sRGB triple and the fixed colour-blind-safe palettes.

/// An 8-bit-per-channel sRGB colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rgb {
    /// Red, 0-255.
    pub r: u8,
    /// Green, 0-255.
    pub g: u8,
    /// Blue, 0-255.
    pub b: u8,
}

impl Rgb {
    /// A colour from its red, green and blue components (0-255).
    pub const fn new(r: u8, g: u8, b: u8) -> Self {
        Self { r, g, b }
    }

    /// Pure white, the figure background.
    pub const WHITE: Rgb = Rgb::new(255, 255, 255);
    /// Pure black (axes and text).
    pub const BLACK: Rgb = Rgb::new(0, 0, 0);
    /// Dark grey used for secondary text (span and marker labels).
    pub const DARK_GREY: Rgb = Rgb::new(64, 64, 64);
    /// Mid grey used for legend borders.
    pub const GREY: Rgb = Rgb::new(128, 128, 128);
    /// Light grey of the grid lines.
    pub const LIGHT_GREY: Rgb = Rgb::new(222, 222, 222);

    /// `self` blended over `other` with opacity `alpha` in [0, 1] (clamped; NaN counts as 0).
    pub fn over(self, other: Rgb, alpha: f32) -> Rgb {
        let a = if alpha.is_nan() {
            0.0
        } else {
            alpha.clamp(0.0, 1.0)
        };
        let mix = |fg: u8, bg: u8| -> u8 {
            let v = f32::from(bg) + (f32::from(fg) - f32::from(bg)) * a;
            // In [0, 255] by construction; the cast rounds to the nearest level.
            v.round().clamp(0.0, 255.0) as u8
        };
        Rgb::new(
            mix(self.r, other.r),
            mix(self.g, other.g),
            mix(self.b, other.b),
        )
    }
}

/// The Okabe-Ito colour-blind-safe palette (Okabe and Ito 2008), ordered for line series:
/// blue, vermillion, bluish green, reddish purple, orange, sky blue, black, yellow.
pub const SERIES_PALETTE: [Rgb; 8] = [
    Rgb::new(0, 114, 178),
    Rgb::new(213, 94, 0),
    Rgb::new(0, 158, 115),
    Rgb::new(204, 121, 167),
    Rgb::new(230, 159, 0),
    Rgb::new(86, 180, 233),
    Rgb::new(0, 0, 0),
    Rgb::new(240, 228, 66),
];

/// Colours for shaded x spans (drawn with [`DEFAULT_SPAN_ALPHA`]): grey, orange, sky blue, bluish
/// green, yellow, reddish purple, blue, vermillion (Okabe-Ito hues, grey first for "alignment").
pub const SPAN_PALETTE: [Rgb; 8] = [
    Rgb::new(150, 150, 150),
    Rgb::new(230, 159, 0),
    Rgb::new(86, 180, 233),
    Rgb::new(0, 158, 115),
    Rgb::new(240, 228, 66),
    Rgb::new(204, 121, 167),
    Rgb::new(0, 114, 178),
    Rgb::new(213, 94, 0),
];

/// Opacity of a shaded x span unless set explicitly.
pub const DEFAULT_SPAN_ALPHA: f32 = 0.16;
/// Opacity of a filled band unless set explicitly.
pub const DEFAULT_BAND_ALPHA: f32 = 0.22;

/// The `index`-th line colour, cycling through [`SERIES_PALETTE`].
pub fn series_color(index: usize) -> Rgb {
    SERIES_PALETTE[index % SERIES_PALETTE.len()]
}

/// The `index`-th span colour, cycling through [`SPAN_PALETTE`].
pub fn span_color(index: usize) -> Rgb {
    SPAN_PALETTE[index % SPAN_PALETTE.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blending_endpoints_and_midpoint() {
        let red = Rgb::new(255, 0, 0);
        assert_eq!(red.over(Rgb::WHITE, 1.0), red);
        assert_eq!(red.over(Rgb::WHITE, 0.0), Rgb::WHITE);
        assert_eq!(red.over(Rgb::WHITE, f32::NAN), Rgb::WHITE);
        assert_eq!(red.over(Rgb::BLACK, 0.5), Rgb::new(128, 0, 0));
        assert_eq!(series_color(8), series_color(0));
        assert_ne!(series_color(0), series_color(1));
    }
}
