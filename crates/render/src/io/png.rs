//! PNG output: linear radiance scaled by 2^exposure, clamped, sRGB-encoded to 8 bits.

use crate::error::{Error, Result};
use crate::image::Image;
use std::path::Path;

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
#[inline]
pub fn srgb_encode(x: f32) -> f32 {
    if x <= 0.0031308 {
        12.92 * x.max(0.0)
    } else {
        1.055 * x.min(1.0).powf(1.0 / 2.4) - 0.055
    }
}

/// 8-bit sRGB bytes of `image` (row-major RGB), after scaling by 2^`exposure`.
pub fn to_srgb8(image: &Image, exposure: f32) -> Vec<u8> {
    let scale = exposure.exp2();
    image
        .pixels
        .iter()
        .flat_map(|p| p.0.map(|c| (srgb_encode(c * scale) * 255.0 + 0.5).clamp(0.0, 255.0) as u8))
        .collect()
}

/// Writes `image` to `path` as an 8-bit sRGB PNG (not atomically: see `Image::save`).
pub fn write_png(image: &Image, path: &Path, exposure: f32) -> Result<()> {
    let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), image.width, image.height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let fail = |e: png::EncodingError| Error::format(path, format!("PNG encoding failed: {e}"));
    let mut writer = enc.write_header().map_err(fail)?;
    writer.write_image_data(&to_srgb8(image, exposure)).map_err(fail)?;
    writer.finish().map_err(fail)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_known_values() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        // 18% grey encodes to about 0.4614.
        assert!((srgb_encode(0.18) - 0.4614).abs() < 1e-3);
        // Continuous at the junction.
        assert!((srgb_encode(0.0031308) - srgb_encode(0.0031309)).abs() < 1e-5);
    }
}
