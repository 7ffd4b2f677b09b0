//! Dependency-light PNG line charts for sinsbench reports.
//!
//! A [`Figure`] stacks one or more [`Panel`]s vertically (optionally sharing the x axis) on a
//! white image, 1200 x 400 pixels per panel by default. A panel draws [`Line`]s (2 px,
//! anti-aliased, optionally dashed; NaN breaks the line; long series are decimated per pixel
//! column keeping each column's minimum and maximum), filled [`Band`]s between two curves,
//! shaded x [`Span`]s with labels, vertical [`Marker`]s, grid lines, 'nice' 1-2-5 ticks and a
//! legend. Text uses a built-in 6x10 bitmap font (printable ASCII plus a few symbols such as
//! degree, plus-minus, micro and sigma), so no font files or system fonts are involved.
//!
//! ```
//! use sins_plot::{Figure, Line, Panel, Span};
//! let t_h: Vec<f64> = (0..=150).map(|i| f64::from(i) * 0.1).collect();
//! let err: Vec<f64> = t_h.iter().map(|t| 0.2 * t).collect();
//! let png = Figure::new()
//!     .panel(
//!         Panel::new("horizontal error")
//!             .x_label("time [h]")
//!             .y_label("error [nmi]")
//!             .span(Span::new("alignment", 0.0, 1.0 / 3.0))
//!             .line(Line::new("42-state", t_h, err)),
//!     )
//!     .to_png_bytes()?;
//! assert_eq!(&png[1..4], b"PNG");
//! # Ok::<(), sins_plot::PlotError>(())
//! ```

mod allan;
mod band;
mod canvas;
mod color;
mod decimate;
mod error;
mod figure;
pub mod font_data;
mod layout;
mod legend;
mod panel;
mod png_out;
mod raster;
mod render;
mod series;
mod text;
mod ticks;
mod validate;

pub use allan::{AllanPanel, AllanSeries, allan_figure};
pub use canvas::{Rect, RgbImage};
pub use color::{
    DEFAULT_BAND_ALPHA, DEFAULT_SPAN_ALPHA, Rgb, SERIES_PALETTE, SPAN_PALETTE, series_color,
    span_color,
};
pub use error::PlotError;
pub use figure::{DEFAULT_PANEL_HEIGHT_PX, DEFAULT_WIDTH_PX, Figure, RenderedFigure};
pub use layout::PanelGeometry;
pub use panel::Panel;
pub use series::{
    Band, DEFAULT_DASH_PX, DEFAULT_LINE_WIDTH_PX, LegendPosition, Line, Marker, Span,
};
pub use text::{text_height_px, text_width_px};
pub use ticks::{Ticks, format_ticks, nice_step, nice_ticks};
