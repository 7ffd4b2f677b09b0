//! A figure: vertically stacked panels on a white image, rendered to RGB or PNG.

use crate::canvas::RgbImage;
use crate::color::Rgb;
use crate::error::PlotError;
use crate::layout::{Frame, Metrics, PanelGeometry, layout};
use crate::log_scale::{panel_to_axis, spans_to_axis};
use crate::panel::Panel;
use crate::render::draw_panel;
use crate::series::Span;
use crate::text::{HAlign, TextStyle, VAlign};

/// Default image width in pixels.
pub const DEFAULT_WIDTH_PX: u32 = 1200;
/// Default height of one panel in pixels.
pub const DEFAULT_PANEL_HEIGHT_PX: u32 = 400;

/// One or more panels stacked top to bottom, optionally sharing the x axis (then only the bottom
/// panel carries x tick labels and the x label). Built by value:
/// `Figure::new().title("...").panel(a).panel(b).share_x(true)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub(crate) width_px: u32,
    pub(crate) panel_height_px: u32,
    pub(crate) title: String,
    pub(crate) panels: Vec<Panel>,
    pub(crate) share_x: bool,
    pub(crate) x_range: Option<(f64, f64)>,
    pub(crate) spans: Vec<Span>,
    pub(crate) scale: u32,
}

impl Default for Figure {
    fn default() -> Self {
        Self::new()
    }
}

/// A rendered figure: the image and where each panel's data landed (for tests and overlays).
#[derive(Debug, Clone, PartialEq)]
pub struct RenderedFigure {
    /// The RGB image.
    pub image: RgbImage,
    /// One entry per panel, top to bottom.
    pub panels: Vec<PanelGeometry>,
}

impl Figure {
    /// An empty figure, [`DEFAULT_WIDTH_PX`] wide, [`DEFAULT_PANEL_HEIGHT_PX`] per panel, text
    /// scale 1 (6x10 pixel glyphs, 2 px lines), x axes not shared.
    pub fn new() -> Self {
        Self {
            width_px: DEFAULT_WIDTH_PX,
            panel_height_px: DEFAULT_PANEL_HEIGHT_PX,
            title: String::new(),
            panels: Vec::new(),
            share_x: false,
            x_range: None,
            spans: Vec::new(),
            scale: 1,
        }
    }

    /// Sets the image width and the height of each panel, pixels (width 200-16384, panel height
    /// 100-8192, total height at most 16384; checked when rendering).
    pub fn size_px(mut self, width_px: u32, panel_height_px: u32) -> Self {
        self.width_px = width_px;
        self.panel_height_px = panel_height_px;
        self
    }

    /// Sets a title above all panels (drawn with glyphs twice the normal size).
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = title.into();
        self
    }

    /// Appends a panel below the existing ones.
    pub fn panel(mut self, panel: Panel) -> Self {
        self.panels.push(panel);
        self
    }

    /// Shares the x axis between all panels: one range (the union of the panels' ranges unless
    /// [`Figure::x_range`] fixes it), tick labels and x label only under the bottom panel. The
    /// panels must agree on a logarithmic x axis ([`Panel::log_x`] in all or none).
    pub fn share_x(mut self, shared: bool) -> Self {
        self.share_x = shared;
        self
    }

    /// Fixes the shared x range to `[lo, hi]`, data units (only with [`Figure::share_x`]; positive
    /// on a logarithmic x axis).
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// Adds a shaded x span to every panel (e.g. the segments of a run), drawn before the
    /// panels' own spans.
    pub fn span(mut self, span: Span) -> Self {
        self.spans.push(span);
        self
    }

    /// Sets the integer magnification (1-4) of text, line widths, dash lengths, ticks and
    /// margins: 1 draws 6x10 pixel glyphs and 2 px lines; 2 with twice the size in pixels gives
    /// the same figure at twice the pixel density.
    pub fn scale(mut self, scale: u32) -> Self {
        self.scale = scale;
        self
    }

    /// Total image height in pixels: title strip plus one slot per panel.
    pub fn total_height_px(&self) -> u32 {
        let m = Metrics::new(self.scale);
        let title_h = m.figure_title_h(!self.title.is_empty()) as u32;
        self.panel_height_px
            .saturating_mul(self.panels.len() as u32)
            .saturating_add(title_h)
    }

    fn check_size(&self) -> Result<(), PlotError> {
        let height_px = self.total_height_px();
        let bad = |reason| {
            Err(PlotError::InvalidSize {
                width_px: self.width_px,
                height_px,
                reason,
            })
        };
        if self.panels.is_empty() {
            return Err(PlotError::NoPanels);
        }
        if !(200..=16384).contains(&self.width_px) {
            return bad("width out of range");
        }
        if !(100..=8192).contains(&self.panel_height_px) {
            return bad("panel height out of range");
        }
        if height_px > 16384 {
            return bad("too many panels for the panel height");
        }
        Ok(())
    }

    /// Draws the figure into an RGB image and reports each panel's geometry. Fails on an empty
    /// figure, an unusable size, series of mismatched lengths, invalid ranges or styles, or
    /// panels that disagree on a shared logarithmic x axis.
    pub fn render(&self) -> Result<RenderedFigure, PlotError> {
        self.check_size()?;
        for (i, p) in self.panels.iter().enumerate() {
            crate::validate::check_panel(i, p, &self.spans)?;
        }
        crate::validate::check_shared_x(&self.panels, self.share_x, self.x_range)?;
        let m = Metrics::new(self.scale);
        let frame = Frame {
            width_px: self.width_px,
            panel_height_px: self.panel_height_px,
            total_height_px: self.total_height_px(),
            titled: !self.title.is_empty(),
            share_x: self.share_x,
            x_range: self.x_range,
        };
        let geometries = layout(&frame, &self.panels, &m)?;
        let mut image = RgbImage::new(self.width_px, self.total_height_px(), Rgb::WHITE);
        if !self.title.is_empty() {
            let style = TextStyle::new(Rgb::BLACK, 2 * m.scale, HAlign::Center, VAlign::Top);
            let clip = image.bounds();
            image.text_at(self.width_px as i32 / 2, m.u(6), &self.title, &style, &clip);
        }
        let last = self.panels.len() - 1;
        for (i, (p, g)) in self.panels.iter().zip(&geometries).enumerate() {
            let x_labels = !self.share_x || i == last;
            // Log axes: data, spans and ticks in log10, drawn as on linear axes.
            let spans = spans_to_axis(&self.spans, p.x_log);
            let axis_panel = panel_to_axis(p);
            draw_panel(
                &mut image,
                &axis_panel,
                &spans,
                &g.in_axis_units(),
                &m,
                x_labels,
            );
        }
        Ok(RenderedFigure {
            image,
            panels: geometries,
        })
    }

    /// Renders the figure and encodes it as an 8-bit RGB PNG (the caller writes the file).
    pub fn to_png_bytes(&self) -> Result<Vec<u8>, PlotError> {
        self.render()?.image.to_png_bytes()
    }
}
