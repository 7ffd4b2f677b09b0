//! Helpers shared by the pixel-level tests: the line colours they draw with, rendering,
//! reading a pixel, and a panel without grid or legend.
#![allow(dead_code)]

use sins_plot::{Figure, LegendPosition, Panel, PanelGeometry, Rgb, RgbImage};

/// The line colour whose ink the tests look for.
pub const RED: Rgb = Rgb::new(255, 0, 0);
/// A second colour (bands, spans).
pub const TEAL: Rgb = Rgb::new(0, 128, 128);

/// The rendered image and each panel's geometry (a render error fails the test).
pub fn render(fig: &Figure) -> (RgbImage, Vec<PanelGeometry>) {
    match fig.render() {
        Ok(r) => (r.image, r.panels),
        Err(e) => panic!("render failed: {e}"),
    }
}

/// The pixel at `(x, y)` (outside the image fails the test).
pub fn px(img: &RgbImage, x: i32, y: i32) -> Rgb {
    img.pixel(x, y)
        .unwrap_or_else(|| panic!("pixel ({x}, {y}) outside the image"))
}

/// A panel with no grid and no legend, so that only the data leave ink.
pub fn bare_panel() -> Panel {
    Panel::new("").grid(false).legend(LegendPosition::Hidden)
}
