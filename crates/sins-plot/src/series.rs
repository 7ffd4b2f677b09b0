//! What a panel shows: lines, filled bands, shaded x spans and vertical markers.

use crate::color::{DEFAULT_BAND_ALPHA, DEFAULT_SPAN_ALPHA, Rgb};

/// Default line width in pixels.
pub const DEFAULT_LINE_WIDTH_PX: f32 = 2.0;
/// Dash pattern of [`Line::dashed`] and [`Marker::dashed`]: 9 px drawn, 6 px gap.
pub const DEFAULT_DASH_PX: (f32, f32) = (9.0, 6.0);

/// A polyline through (x, y) points, in data units. NaN or infinite points break the line
/// (nothing is drawn between the neighbours of a gap). Dense data are decimated per pixel
/// column (first, minimum, maximum and last point of each column), so spikes survive.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    pub(crate) label: String,
    pub(crate) x: Vec<f64>,
    pub(crate) y: Vec<f64>,
    pub(crate) color: Option<Rgb>,
    pub(crate) width_px: f32,
    pub(crate) dash_px: Option<(f32, f32)>,
}

impl Line {
    /// A solid line of width [`DEFAULT_LINE_WIDTH_PX`] with the next palette colour. An empty
    /// `label` keeps the line out of the legend. `x` and `y` must have equal lengths (checked
    /// when the figure is rendered).
    pub fn new(label: impl Into<String>, x: impl Into<Vec<f64>>, y: impl Into<Vec<f64>>) -> Self {
        Self {
            label: label.into(),
            x: x.into(),
            y: y.into(),
            color: None,
            width_px: DEFAULT_LINE_WIDTH_PX,
            dash_px: None,
        }
    }

    /// Uses `color` instead of the next palette colour.
    pub fn color(mut self, color: Rgb) -> Self {
        self.color = Some(color);
        self
    }

    /// Sets the line width in pixels (0.5-20).
    pub fn width_px(mut self, width_px: f32) -> Self {
        self.width_px = width_px;
        self
    }

    /// Draws the line dashed with [`DEFAULT_DASH_PX`].
    pub fn dashed(self) -> Self {
        self.dash_pattern_px(DEFAULT_DASH_PX.0, DEFAULT_DASH_PX.1)
    }

    /// Draws the line dashed: `on_px` pixels drawn, `off_px` pixels gap, measured along the line
    /// (each 0.5-1000).
    pub fn dash_pattern_px(mut self, on_px: f32, off_px: f32) -> Self {
        self.dash_px = Some((on_px, off_px));
        self
    }
}

/// A region filled between a `lower` and an `upper` curve over common `x` (e.g. a +-3 sigma
/// envelope), data units. Points where any of the three values is not finite leave a gap.
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    pub(crate) label: String,
    pub(crate) x: Vec<f64>,
    pub(crate) lower: Vec<f64>,
    pub(crate) upper: Vec<f64>,
    pub(crate) color: Option<Rgb>,
    pub(crate) alpha: f32,
}

impl Band {
    /// A band with the next palette colour (bands count separately from lines, so band k
    /// matches line k) at opacity [`DEFAULT_BAND_ALPHA`]. An empty `label` keeps it out of the
    /// legend.
    pub fn new(
        label: impl Into<String>,
        x: impl Into<Vec<f64>>,
        lower: impl Into<Vec<f64>>,
        upper: impl Into<Vec<f64>>,
    ) -> Self {
        Self {
            label: label.into(),
            x: x.into(),
            lower: lower.into(),
            upper: upper.into(),
            color: None,
            alpha: DEFAULT_BAND_ALPHA,
        }
    }

    /// Uses `color` instead of the next palette colour.
    pub fn color(mut self, color: Rgb) -> Self {
        self.color = Some(color);
        self
    }

    /// Sets the fill opacity (0-1).
    pub fn alpha(mut self, alpha: f32) -> Self {
        self.alpha = alpha;
        self
    }
}

/// A shaded interval `[x_start, x_end]` of the x axis over the full plot height, with its label
/// written at the top (horizontally if it fits, else upwards along the span, else omitted).
#[derive(Debug, Clone, PartialEq)]
pub struct Span {
    pub(crate) label: String,
    pub(crate) x_start: f64,
    pub(crate) x_end: f64,
    pub(crate) color: Option<Rgb>,
    pub(crate) alpha: f32,
}

impl Span {
    /// A span with the next span-palette colour at opacity [`DEFAULT_SPAN_ALPHA`]; data units.
    /// Reversed bounds are swapped; non-finite bounds make the span invisible.
    pub fn new(label: impl Into<String>, x_start: f64, x_end: f64) -> Self {
        Self {
            label: label.into(),
            x_start: x_start.min(x_end),
            x_end: x_start.max(x_end),
            color: None,
            alpha: DEFAULT_SPAN_ALPHA,
        }
    }

    /// Uses `color` instead of the next span-palette colour.
    pub fn color(mut self, color: Rgb) -> Self {
        self.color = Some(color);
        self
    }

    /// Sets the shading opacity (0-1).
    pub fn alpha(mut self, alpha: f32) -> Self {
        self.alpha = alpha;
        self
    }
}

/// A vertical line at `x` (data units) over the full plot height with a label beside its top
/// (nothing is drawn for a non-finite `x` or one outside the x range).
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    pub(crate) label: String,
    pub(crate) x: f64,
    pub(crate) color: Rgb,
    pub(crate) dashed: bool,
}

impl Marker {
    /// A solid dark-grey marker.
    pub fn new(label: impl Into<String>, x: f64) -> Self {
        Self {
            label: label.into(),
            x,
            color: Rgb::DARK_GREY,
            dashed: false,
        }
    }

    /// Uses `color` for the line and its label.
    pub fn color(mut self, color: Rgb) -> Self {
        self.color = color;
        self
    }

    /// Draws the marker dashed with [`DEFAULT_DASH_PX`].
    pub fn dashed(mut self) -> Self {
        self.dashed = true;
        self
    }
}

/// Where a panel's legend box goes (inside the plot area), or whether it is hidden.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LegendPosition {
    /// Top-left corner.
    TopLeft,
    /// Top-right corner (the default).
    #[default]
    TopRight,
    /// Bottom-left corner.
    BottomLeft,
    /// Bottom-right corner.
    BottomRight,
    /// No legend.
    Hidden,
}
