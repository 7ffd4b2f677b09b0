#![doc = include_str!("../README.md")]

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
mod log_scale;
mod log_ticks;
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
pub use log_ticks::log_ticks;
pub use panel::Panel;
pub use series::{
    Band, DEFAULT_DASH_PX, DEFAULT_LINE_WIDTH_PX, LegendPosition, Line, Marker, Span,
};
pub use text::{text_height_px, text_width_px};
pub use ticks::{Ticks, format_ticks, nice_step, nice_ticks};
