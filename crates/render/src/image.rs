//! A linear float RGB image, row-major with row 0 at the top, and its loading and saving.

use crate::error::{Error, Result};
use crate::io;
use radiometry::Rgb;
use std::path::Path;

/// A linear RGB image.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels, row-major from the top-left corner.
    pub pixels: Vec<Rgb>,
}

impl Image {
    /// A black image.
    pub fn new(width: u32, height: u32) -> Self {
        Image { width, height, pixels: vec![Rgb::ZERO; width as usize * height as usize] }
    }

    /// The pixel in column `x`, row `y`.
    #[inline]
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Sets the pixel in column `x`, row `y`.
    #[inline]
    pub fn set(&mut self, x: u32, y: u32, c: Rgb) {
        self.pixels[(y * self.width + x) as usize] = c;
    }

    /// The mean of all pixels, accumulated in f64.
    pub fn mean(&self) -> [f64; 3] {
        let mut s = [0.0f64; 3];
        for p in &self.pixels {
            for (a, &c) in s.iter_mut().zip(&p.0) {
                *a += c as f64;
            }
        }
        s.map(|a| a / self.pixels.len().max(1) as f64)
    }

    /// Loads an image by extension: `.exr` (OpenEXR) or `.hdr` (Radiance RGBE).
    pub fn load(path: impl AsRef<Path>) -> Result<Image> {
        let path = path.as_ref();
        match extension(path).as_str() {
            "exr" => io::exr::read_exr(path),
            "hdr" | "rgbe" | "pic" => io::hdr::read_hdr(path),
            other => Err(Error::format(path, format!("cannot read images of type '.{other}'; expected .exr or .hdr"))),
        }
    }

    /// Saves by extension, atomically: `.exr` writes the raw float image, `.png` an sRGB
    /// encoding at exposure 0 (see [`Image::save_png`]).
    pub fn save(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        match extension(path).as_str() {
            "exr" => io::atomic::write_atomically(path, |tmp| io::exr::write_exr(self, tmp)),
            "png" => self.save_png(path, 0.0),
            other => Err(Error::format(path, format!("cannot write images of type '.{other}'; expected .exr or .png"))),
        }
    }

    /// Saves an 8-bit sRGB PNG of the image scaled by 2^`exposure`, atomically.
    pub fn save_png(&self, path: impl AsRef<Path>, exposure: f32) -> Result<()> {
        let path = path.as_ref();
        io::atomic::write_atomically(path, |tmp| io::png::write_png(self, tmp, exposure))
    }
}

fn extension(path: &Path) -> String {
    path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn test_image() -> Image {
        let mut img = Image::new(5, 3);
        for y in 0..3 {
            for x in 0..5 {
                img.set(x, y, Rgb::new(x as f32 * 0.25, y as f32 * 1.5, 1e3 + (x * y) as f32));
            }
        }
        img
    }

    #[test]
    fn exr_round_trip_is_exact_and_leaves_no_temp_file() {
        let dir = std::env::temp_dir().join(format!("gonio-render-exr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.exr");
        let img = test_image();
        img.save(&path).unwrap();
        assert_eq!(Image::load(&path).unwrap(), img);
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names.len(), 1, "{names:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn png_writes_and_bad_extensions_are_named() {
        let dir = std::env::temp_dir().join(format!("gonio-render-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.png");
        test_image().save_png(&path, -1.0).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        let e = test_image().save(dir.join("a.bmp")).unwrap_err().to_string();
        assert!(e.contains("a.bmp") && e.contains(".bmp"), "{e}");
        let e = Image::load(dir.join("missing.exr")).unwrap_err().to_string();
        assert!(e.contains("missing.exr"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
