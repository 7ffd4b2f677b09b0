//! One chart of a figure: axes, labels and the items it shows.

use crate::series::{Band, LegendPosition, Line, Marker, Span};

/// One chart: title, axis labels, axis ranges (automatic unless fixed), linear or logarithmic
/// axes, grid, legend, and the lines, bands, shaded spans and markers drawn in it. Built by
/// value: `Panel::new("title").x_label("time [h]").line(...)`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    pub(crate) title: String,
    pub(crate) x_label: String,
    pub(crate) y_label: String,
    pub(crate) x_range: Option<(f64, f64)>,
    pub(crate) y_range: Option<(f64, f64)>,
    pub(crate) x_log: bool,
    pub(crate) y_log: bool,
    pub(crate) y_include: Vec<f64>,
    pub(crate) grid: bool,
    pub(crate) legend: LegendPosition,
    pub(crate) lines: Vec<Line>,
    pub(crate) bands: Vec<Band>,
    pub(crate) spans: Vec<Span>,
    pub(crate) markers: Vec<Marker>,
}

impl Panel {
    /// An empty panel with grid lines and the legend at the top right. An empty `title` leaves
    /// the title row blank.
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            grid: true,
            ..Self::default()
        }
    }

    /// Sets the x-axis label (include the unit, e.g. `"time [h]"`).
    pub fn x_label(mut self, label: impl Into<String>) -> Self {
        self.x_label = label.into();
        self
    }

    /// Sets the y-axis label (include the unit, e.g. `"horizontal error [nmi]"`).
    pub fn y_label(mut self, label: impl Into<String>) -> Self {
        self.y_label = label.into();
        self
    }

    /// Fixes the x range to `[lo, hi]` (data units) instead of the tight data range. In a
    /// figure with a shared x axis a figure-level range takes precedence (see
    /// [`crate::Figure::share_x`]).
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// Fixes the y range to `[lo, hi]` (data units) instead of the data range rounded out to
    /// whole tick steps.
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// Makes the x axis logarithmic (base 10). Everything stays in data units (x values, the x
    /// range, spans, markers): a value's position goes with its `log10`. An x that is not
    /// positive (or not finite) breaks lines and bands there (a gap) and hides a marker; a span
    /// bound at or below 0 reaches past the left edge. A fixed range ([`Panel::x_range`],
    /// [`crate::Figure::x_range`]) must be positive. Ticks are decades labelled with the value
    /// (`0.01`, `1`, `1000`, `1e5`), 1-2-5 ticks over a few decades, at least two labelled ticks
    /// for less than a decade, unlabelled minor ticks at 2-9 x 10^k (see [`crate::log_ticks`]);
    /// the automatic range is the tight data range. With a shared x axis
    /// ([`crate::Figure::share_x`]) every panel must be logarithmic in x or none
    /// ([`crate::PlotError::SharedXScaleMismatch`] otherwise).
    pub fn log_x(mut self) -> Self {
        self.x_log = true;
        self
    }

    /// Makes the y axis logarithmic (base 10). Everything stays in data units (y values, band
    /// bounds, the y range, [`Panel::y_include`]): a value's position goes with its `log10`. A y
    /// (or band bound) that is not positive (or not finite) breaks lines and bands there (a
    /// gap) and is left out of the automatic range, as is a non-positive `y_include`. A fixed
    /// range ([`Panel::y_range`]) must be positive. The automatic range widens to the enclosing
    /// decades (data from 0.3 to 4 get the axis 0.1 to 10); ticks as for [`Panel::log_x`].
    pub fn log_y(mut self) -> Self {
        self.y_log = true;
        self
    }

    /// Makes the automatic y range include `value` (e.g. 0 for an error magnitude).
    pub fn y_include(mut self, value: f64) -> Self {
        self.y_include.push(value);
        self
    }

    /// Switches the light grid lines at the ticks on or off (on by default).
    pub fn grid(mut self, on: bool) -> Self {
        self.grid = on;
        self
    }

    /// Places (or hides) the legend; it lists labelled lines and bands.
    pub fn legend(mut self, position: LegendPosition) -> Self {
        self.legend = position;
        self
    }

    /// Adds a line (drawn in insertion order, after bands and spans).
    pub fn line(mut self, line: Line) -> Self {
        self.lines.push(line);
        self
    }

    /// Adds a filled band (drawn under the lines).
    pub fn band(mut self, band: Band) -> Self {
        self.bands.push(band);
        self
    }

    /// Adds a shaded x span (drawn under everything else).
    pub fn span(mut self, span: Span) -> Self {
        self.spans.push(span);
        self
    }

    /// Adds a vertical marker line (drawn under the lines, its label on top).
    pub fn marker(mut self, marker: Marker) -> Self {
        self.markers.push(marker);
        self
    }
}
