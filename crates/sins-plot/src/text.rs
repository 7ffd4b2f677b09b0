//! Text with the built-in 6x10 bitmap font: measuring and drawing, horizontal or rotated.

use crate::canvas::{Rect, RgbImage};
use crate::color::Rgb;
use crate::font_data::{ASCII_GLYPHS, EXTRA_GLYPHS, GLYPH_HEIGHT_PX, GLYPH_WIDTH_PX};

/// The bitmap of `ch`; characters the font lacks are drawn as `?`.
fn glyph(ch: char) -> &'static [u8; 10] {
    let code = ch as u32;
    if (32..=126).contains(&code) {
        return &ASCII_GLYPHS[(code - 32) as usize];
    }
    EXTRA_GLYPHS
        .iter()
        .find(|(c, _)| *c == ch)
        .map_or(&ASCII_GLYPHS[(u32::from('?') - 32) as usize], |(_, g)| g)
}

/// Width in pixels of `text` drawn at integer `scale` (without the spacing after the last
/// character; 0 for empty text).
pub fn text_width_px(text: &str, scale: u32) -> u32 {
    let n = text.chars().count() as u32;
    (n * GLYPH_WIDTH_PX).saturating_sub(1) * scale.max(1)
}

/// Height in pixels of one line of text at integer `scale` (the full glyph cell).
pub fn text_height_px(scale: u32) -> u32 {
    GLYPH_HEIGHT_PX * scale.max(1)
}

/// Horizontal anchor of a text box.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum HAlign {
    Left,
    Center,
    Right,
}

/// Vertical anchor of a text box (the glyph cell, descenders included).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum VAlign {
    Top,
    Middle,
    Bottom,
}

/// How a text box is placed around its anchor point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TextStyle {
    pub color: Rgb,
    pub scale: u32,
    pub h: HAlign,
    pub v: VAlign,
}

impl TextStyle {
    pub fn new(color: Rgb, scale: u32, h: HAlign, v: VAlign) -> Self {
        Self {
            color,
            scale: scale.max(1),
            h,
            v,
        }
    }
}

fn offset(len: i32, align_start: bool, align_center: bool) -> i32 {
    if align_start {
        0
    } else if align_center {
        len / 2
    } else {
        len
    }
}

impl RgbImage {
    /// Draws `text` in `color` with its glyph cell's top-left corner at (`x`, `y`), each font
    /// pixel as a `scale` x `scale` block. Pixels outside the image are skipped.
    pub fn draw_text(&mut self, x: i32, y: i32, text: &str, color: Rgb, scale: u32) {
        let clip = self.bounds();
        let style = TextStyle::new(color, scale, HAlign::Left, VAlign::Top);
        self.text_at(x, y, text, &style, &clip);
    }

    /// Draws horizontal `text` anchored at (`x`, `y`) as given by `style`, clipped to `clip`.
    pub(crate) fn text_at(&mut self, x: i32, y: i32, text: &str, style: &TextStyle, clip: &Rect) {
        let s = style.scale as i32;
        let w = text_width_px(text, style.scale) as i32;
        let h = text_height_px(style.scale) as i32;
        let x0 = x - offset(w, style.h == HAlign::Left, style.h == HAlign::Center);
        let y0 = y - offset(h, style.v == VAlign::Top, style.v == VAlign::Middle);
        for (i, ch) in text.chars().enumerate() {
            let gx = x0 + i as i32 * GLYPH_WIDTH_PX as i32 * s;
            for (row, bits) in glyph(ch).iter().enumerate() {
                for col in 0..GLYPH_WIDTH_PX as i32 {
                    if bits & (0x80 >> col) != 0 {
                        let rect = Rect {
                            x: gx + col * s,
                            y: y0 + row as i32 * s,
                            width: s,
                            height: s,
                        };
                        self.fill_rect(&rect, style.color, 1.0, clip);
                    }
                }
            }
        }
    }

    /// Draws `text` rotated 90 degrees counter-clockwise (reading bottom to top). The anchor
    /// refers to the rotated box: `h` along the image x axis (the glyph cell's height), `v`
    /// along the image y axis (the text's length; `Top` means the end of the text is at `y`).
    pub(crate) fn text_up_at(
        &mut self,
        x: i32,
        y: i32,
        text: &str,
        style: &TextStyle,
        clip: &Rect,
    ) {
        let s = style.scale as i32;
        let len = text_width_px(text, style.scale) as i32;
        let h = text_height_px(style.scale) as i32;
        let left = x - offset(h, style.h == HAlign::Left, style.h == HAlign::Center);
        let top = y - offset(len, style.v == VAlign::Top, style.v == VAlign::Middle);
        let bottom = top + len;
        for (i, ch) in text.chars().enumerate() {
            let along0 = i as i32 * GLYPH_WIDTH_PX as i32 * s;
            for (row, bits) in glyph(ch).iter().enumerate() {
                for col in 0..GLYPH_WIDTH_PX as i32 {
                    if bits & (0x80 >> col) != 0 {
                        // Glyph column runs up the image, glyph row runs right.
                        let rect = Rect {
                            x: left + row as i32 * s,
                            y: bottom - along0 - (col + 1) * s,
                            width: s,
                            height: s,
                        };
                        self.fill_rect(&rect, style.color, 1.0, clip);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widths_and_fallback_glyph() {
        assert_eq!(text_width_px("", 1), 0);
        assert_eq!(text_width_px("ab", 1), 11);
        assert_eq!(text_width_px("ab", 2), 22);
        assert_eq!(glyph('\u{2603}'), glyph('?'));
        assert_ne!(glyph('\u{00b1}'), glyph('?'));
        assert_ne!(glyph('0'), glyph('O'));
    }
}
