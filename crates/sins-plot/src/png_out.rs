//! PNG encoding of an RGB image with the `png` crate.

use crate::canvas::RgbImage;
use crate::error::PlotError;

impl RgbImage {
    /// Encodes the image as an 8-bit RGB PNG (non-interlaced, fast deflate, adaptive filters).
    pub fn to_png_bytes(&self) -> Result<Vec<u8>, PlotError> {
        let mut out = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut out, self.width(), self.height());
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            encoder.set_compression(png::Compression::Fast);
            let mut writer = encoder.write_header()?;
            writer.write_image_data(self.as_rgb_bytes())?;
            writer.finish()?;
        }
        Ok(out)
    }
}
