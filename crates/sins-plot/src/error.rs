//! Errors of figure rendering and PNG encoding.

/// Why a figure could not be rendered or encoded.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The figure has no panel to draw.
    #[error("the figure has no panels")]
    NoPanels,
    /// The image size is outside the supported range or leaves no room for a plot area.
    #[error(
        "figure size {width_px} x {height_px} px is unusable: {reason} (width 200-16384 px, panel height 100-8192 px, total height at most 16384 px)"
    )]
    InvalidSize {
        /// Requested width in pixels.
        width_px: u32,
        /// Resulting total height in pixels.
        height_px: u32,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A series has x and y (or band bound) slices of different lengths.
    #[error(
        "panel {panel} ({panel_title:?}), {kind} {series:?}: x has {x_len} points but {what} has {other_len}"
    )]
    LengthMismatch {
        /// Zero-based panel index, top to bottom.
        panel: usize,
        /// Panel title.
        panel_title: String,
        /// "line" or "band".
        kind: &'static str,
        /// Series label (empty if unlabelled).
        series: String,
        /// Which other slice disagrees ("y", "lower", "upper").
        what: &'static str,
        /// Number of x values.
        x_len: usize,
        /// Number of values in the other slice.
        other_len: usize,
    },
    /// An axis range is not finite, inverted, empty, or too wide to represent.
    #[error("panel {panel} ({panel_title:?}): invalid {axis} axis range [{lo}, {hi}]: {reason}")]
    InvalidRange {
        /// Zero-based panel index, top to bottom.
        panel: usize,
        /// Panel title.
        panel_title: String,
        /// "x" or "y".
        axis: &'static str,
        /// Lower bound, data units.
        lo: f64,
        /// Upper bound, data units.
        hi: f64,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A style parameter (line width, dash pattern, opacity) is not finite or out of range.
    #[error("panel {panel} ({panel_title:?}): {what} {value} is out of range ({allowed})")]
    InvalidStyle {
        /// Zero-based panel index, top to bottom.
        panel: usize,
        /// Panel title.
        panel_title: String,
        /// Which parameter.
        what: &'static str,
        /// The rejected value.
        value: f64,
        /// The accepted range.
        allowed: &'static str,
    },
    /// Panels of a figure with a shared x axis ([`crate::Figure::share_x`]) disagree on whether
    /// it is logarithmic ([`crate::Panel::log_x`]).
    #[error(
        "panel {panel} ({panel_title:?}) has a {scale} x axis but panel 0 has not; a shared x axis is logarithmic in every panel or in none"
    )]
    SharedXScaleMismatch {
        /// Zero-based index of the first panel that differs from panel 0, top to bottom.
        panel: usize,
        /// Its title.
        panel_title: String,
        /// Its x axis: "logarithmic" or "linear".
        scale: &'static str,
    },
    /// The PNG encoder failed.
    #[error("PNG encoding failed: {0}")]
    Png(#[from] png::EncodingError),
}
