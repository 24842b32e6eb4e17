//! Mitsuba 3's `bitmap` texture: an image over the unit square of uv, after `to_uv`.
//!
//! Row 0 is the image's top row and covers v ∈ [0, 1/H); texel (i, j) is centred at
//! ((i + ½)/W, (j + ½)/H). `nearest` takes texel (⌊uW⌋, ⌊vH⌋); `bilinear` blends the four
//! texels around (uW − ½, vH − ½). Each integer texel index is wrapped on its own: `repeat`
//! (modulo), `clamp` (to the edge) or `mirror` (…, 1, 0 | 0, 1, …, W−1 | W−1, …, the edge
//! texel repeated). 8- and 16-bit images are sRGB-decoded per texel unless `raw`; float images
//! (EXR, HDR) are linear and kept as they are. Alpha is dropped, as Mitsuba drops it; a grey
//! image keeps one channel. An image narrower or shorter than 2 texels is doubled to 2, as
//! Mitsuba resamples it. Sources: Mitsuba 3, `src/textures/bitmap.cpp` and Dr.Jit's texture
//! lookup (behaviour only); IEC 61966-2-1 for the sRGB curve.

use crate::error::{Error, Result};
use crate::floor::floor;
use crate::texture::UvTransform;
use glam::Vec2;
use radiometry::Rgb;
use std::path::Path;
use std::sync::OnceLock;

/// How texels are blended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterType {
    /// The nearest texel.
    Nearest,
    /// The four nearest texels, bilinearly.
    Bilinear,
}

/// What lies outside the unit square.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrapMode {
    /// The image repeated.
    Repeat,
    /// The image mirrored at each edge.
    Mirror,
    /// The edge texels extended.
    Clamp,
}

/// How a bitmap is read and looked up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BitmapOptions {
    /// Texel blending.
    pub filter: FilterType,
    /// Outside the unit square.
    pub wrap: WrapMode,
    /// No sRGB decoding of 8- and 16-bit images.
    pub raw: bool,
    /// The map applied to uv first.
    pub to_uv: UvTransform,
}

impl Default for BitmapOptions {
    /// Mitsuba's defaults: bilinear, repeat, sRGB-decoded, no uv map.
    fn default() -> Self {
        BitmapOptions { filter: FilterType::Bilinear, wrap: WrapMode::Repeat, raw: false, to_uv: UvTransform::IDENTITY }
    }
}

/// The luminance weights of linear sRGB (Mitsuba's).
const LUMINANCE: [f32; 3] = [0.212671, 0.715160, 0.072169];

/// Largest image side accepted, so that a header cannot ask for an absurd allocation.
const MAX_SIDE: u32 = 1 << 15;

/// Texel storage.
#[derive(Clone, Debug)]
enum Texels {
    /// Bytes, turned into linear values through a 256-entry table (sRGB or /255).
    Bytes(Vec<u8>, &'static [f32; 256]),
    /// Linear floats.
    Floats(Vec<f32>),
}

/// An image texture.
#[derive(Clone, Debug)]
pub struct Bitmap {
    width: usize,
    height: usize,
    /// 1 (grey) or 3 (RGB).
    channels: usize,
    texels: Texels,
    /// Lookup options.
    pub options: BitmapOptions,
}

/// An image file's content, decoded but not yet given its lookup options: decoding, the slow
/// part of loading, can then run for several files at once.
pub struct Decoded(DecodedKind);

enum DecodedKind {
    /// EXR or Radiance HDR: linear floats.
    Float(crate::image::Image),
    /// PNG, JPEG and the other formats of the `image` crate.
    Other(image::DynamicImage),
}

/// Decodes the image file at `path` (the format from its extension, else its content).
pub fn decode(path: &Path) -> Result<Decoded> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    if ["exr", "hdr", "rgbe", "pic"].contains(&ext.as_str()) {
        return Ok(Decoded(DecodedKind::Float(crate::image::Image::load(path)?)));
    }
    let mut reader = image::ImageReader::open(path).map_err(|e| Error::io(path, e))?;
    reader = reader.with_guessed_format().map_err(|e| Error::io(path, e))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    reader.limits(limits);
    let img = reader.decode().map_err(|e| {
        Error::format(path, format!("cannot decode the image (PNG, JPEG, BMP, TGA, EXR and HDR are read): {e}"))
    })?;
    Ok(Decoded(DecodedKind::Other(img)))
}

/// The sRGB decoding curve.
pub fn srgb_to_linear(x: f64) -> f64 {
    if x <= 0.04045 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

fn byte_table(raw: bool) -> &'static [f32; 256] {
    static SRGB: OnceLock<[f32; 256]> = OnceLock::new();
    static RAW: OnceLock<[f32; 256]> = OnceLock::new();
    let build = |decode: bool| {
        std::array::from_fn(|i| if decode { srgb_to_linear(i as f64 / 255.0) as f32 } else { i as f32 / 255.0 })
    };
    if raw {
        RAW.get_or_init(|| build(false))
    } else {
        SRGB.get_or_init(|| build(true))
    }
}

impl Bitmap {
    /// Reads an image file (PNG, JPEG, BMP, TGA, OpenEXR, Radiance HDR) as a texture.
    pub fn load(path: &Path, options: BitmapOptions) -> Result<Bitmap> {
        Self::from_decoded(path, decode(path)?, options)
    }

    /// The texture of an image file decoded by [`decode`] from `path`.
    pub fn from_decoded(path: &Path, decoded: Decoded, options: BitmapOptions) -> Result<Bitmap> {
        match decoded.0 {
            DecodedKind::Float(img) => {
                let floats = img.pixels.iter().flat_map(|p| p.0).collect();
                Self::from_floats(img.width as usize, img.height as usize, 3, floats, options)
            }
            DecodedKind::Other(img) => Self::from_image(img, options),
        }
        .map_err(|m| Error::format(path, m))
    }

    /// A texture from a decoded image: 8-bit stays bytes; 16-bit is decoded to floats now.
    pub fn from_image(img: image::DynamicImage, options: BitmapOptions) -> std::result::Result<Bitmap, String> {
        use image::DynamicImage as D;
        let (w, h) = (img.width() as usize, img.height() as usize);
        let grey = matches!(
            img.color(),
            image::ColorType::L8 | image::ColorType::La8 | image::ColorType::L16 | image::ColorType::La16
        );
        let channels = if grey { 1 } else { 3 };
        let sixteen = matches!(&img, D::ImageLuma16(_) | D::ImageLumaA16(_) | D::ImageRgb16(_) | D::ImageRgba16(_));
        let float = matches!(&img, D::ImageRgb32F(_) | D::ImageRgba32F(_));
        if float {
            let data = img.into_rgb32f().into_raw();
            return Self::from_floats(w, h, 3, data, options);
        }
        if sixteen {
            let data: Vec<u16> = if grey { img.into_luma16().into_raw() } else { img.into_rgb16().into_raw() };
            let decode = |v: u16| {
                let x = v as f64 / 65535.0;
                (if options.raw { x } else { srgb_to_linear(x) }) as f32
            };
            return Self::from_floats(w, h, channels, data.into_iter().map(decode).collect(), options);
        }
        let data = if grey { img.into_luma8().into_raw() } else { img.into_rgb8().into_raw() };
        let (w2, h2, data) = at_least_two(w, h, channels, data)?;
        Ok(Bitmap { width: w2, height: h2, channels, texels: Texels::Bytes(data, byte_table(options.raw)), options })
    }

    /// A texture from linear float texels, `channels` (1 or 3) per texel, row-major from the top.
    pub fn from_floats(
        width: usize,
        height: usize,
        channels: usize,
        data: Vec<f32>,
        options: BitmapOptions,
    ) -> std::result::Result<Bitmap, String> {
        let (w, h, data) = at_least_two(width, height, channels, data)?;
        Ok(Bitmap { width: w, height: h, channels, texels: Texels::Floats(data), options })
    }

    /// (width, height) in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// 1 for a grey image, 3 for RGB.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// The linear value of channel `c` of texel index `k`.
    #[inline]
    fn value(&self, k: usize) -> f32 {
        match &self.texels {
            Texels::Bytes(b, table) => table[b[k] as usize],
            Texels::Floats(f) => f[k],
        }
    }

    /// Texel (x, y) after wrapping, as RGB (a grey texel in every channel).
    #[inline]
    fn texel(&self, x: i64, y: i64) -> Rgb {
        let (x, y) = (wrap(x, self.width, self.options.wrap), wrap(y, self.height, self.options.wrap));
        self.assemble((y * self.width + x) * self.channels, |k| self.value(k))
    }

    /// The texel whose first value is at `k`, as RGB (a grey texel in every channel),
    /// `value(k)` reading one stored value.
    #[inline(always)]
    fn assemble(&self, k: usize, value: impl Fn(usize) -> f32) -> Rgb {
        if self.channels == 1 {
            Rgb::splat(value(k))
        } else {
            Rgb::new(value(k), value(k + 1), value(k + 2))
        }
    }

    /// Texel (x, y) as one number: its value, or its luminance.
    #[inline]
    fn texel_1(&self, x: i64, y: i64) -> f32 {
        let t = self.texel(x, y);
        if self.channels == 1 {
            t.0[0]
        } else {
            luminance(t)
        }
    }

    /// The lower-left texel of the bilinear footprint at texel coordinates p, and the weights
    /// of its right and upper neighbours.
    #[inline]
    fn footprint(&self, uv: Vec2) -> (i64, i64, f32, f32) {
        let fx = uv.x * self.width as f32 - 0.5;
        let fy = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (floor(fx), floor(fy));
        (x0 as i64, y0 as i64, fx - x0, fy - y0)
    }

    /// Starts loading the texels that `eval(uv)` and `eval_1(uv)` read: a hint, which changes
    /// no result; asked for early, their cache misses overlap other work. The rows are found
    /// by wrapping uv into [0, 1) in floating point, not by the lookup's exact integer wrap (with
    /// its two divisions), which costs more than the load it announces: a texel off at an edge
    /// or under another wrap mode only makes the hint miss.
    #[inline]
    pub fn prefetch(&self, uv: Vec2) {
        let uv = self.options.to_uv.apply(uv);
        let near = |u: f32, n: usize| (((u - floor(u)) * n as f32) as usize).min(n - 1);
        let half = 0.5 / self.height as f32;
        let x = near(uv.x, self.width);
        // The two rows of the bilinear footprint (a nearest lookup reads one of these texels).
        for y in [near(uv.y - half, self.height), near(uv.y + half, self.height)] {
            let k = (y * self.width + x) * self.channels;
            match &self.texels {
                Texels::Bytes(b, _) => radiometry::prefetch::prefetch(&b[k]),
                Texels::Floats(f) => radiometry::prefetch::prefetch(&f[k]),
            }
        }
    }

    /// The RGB value at `uv` (before `to_uv`).
    pub fn eval(&self, uv: Vec2) -> Rgb {
        let uv = self.options.to_uv.apply(uv);
        match self.options.filter {
            FilterType::Nearest => {
                let (x, y) = (floor(uv.x * self.width as f32), floor(uv.y * self.height as f32));
                self.texel(x as i64, y as i64)
            }
            FilterType::Bilinear => {
                let (x0, y0, wx1, wy1) = self.footprint(uv);
                let (wx0, wy0) = (1.0 - wx1, 1.0 - wy1);
                let w = [wx0 * wy0, wx1 * wy0, wx0 * wy1, wx1 * wy1];
                let ks = self.corners(x0, y0);
                // The storage chosen once for the four texels, not at every channel read.
                match &self.texels {
                    Texels::Bytes(b, table) => self.bilinear(ks, w, |k| table[b[k] as usize]),
                    Texels::Floats(f) => self.bilinear(ks, w, |k| f[k]),
                }
            }
        }
    }

    /// The first values of the four texels of the bilinear footprint whose lower-left texel
    /// is (x0, y0): (x0, y0), (x0 + 1, y0), (x0, y0 + 1), (x0 + 1, y0 + 1), each row and
    /// column wrapped once.
    #[inline]
    fn corners(&self, x0: i64, y0: i64) -> [usize; 4] {
        let mode = self.options.wrap;
        let ((xa, xb), (ya, yb)) = (wrap_pair(x0, self.width, mode), wrap_pair(y0, self.height, mode));
        let (ya, yb) = (ya * self.width, yb * self.width);
        [ya + xa, ya + xb, yb + xa, yb + xb].map(|i| i * self.channels)
    }

    /// Σ wᵢ·texelᵢ over the texels starting at `ks`, `value(k)` reading one stored value.
    #[inline(always)]
    fn bilinear(&self, ks: [usize; 4], w: [f32; 4], value: impl Fn(usize) -> f32) -> Rgb {
        let texel = |k: usize| self.assemble(k, &value);
        texel(ks[0]) * w[0] + texel(ks[1]) * w[1] + texel(ks[2]) * w[2] + texel(ks[3]) * w[3]
    }

    /// The one-number value at `uv`: the grey value, or the luminance of the RGB value.
    pub fn eval_1(&self, uv: Vec2) -> f32 {
        let c = self.eval(uv);
        if self.channels == 1 {
            c.0[0]
        } else {
            luminance(c)
        }
    }

    /// ∂/∂(u, v) of `eval_1`, as Mitsuba computes it: the bilinear interpolant's slopes in
    /// texels, scaled by the image size and by `to_uv`'s linear part (transposed: its rows
    /// times the slopes); zero when `nearest`.
    pub fn eval_1_grad(&self, uv: Vec2) -> Vec2 {
        if self.options.filter == FilterType::Nearest {
            return Vec2::ZERO;
        }
        let m = self.options.to_uv.m;
        let (x0, y0, wx1, wy1) = self.footprint(self.options.to_uv.apply(uv));
        let (f00, f10) = (self.texel_1(x0, y0), self.texel_1(x0 + 1, y0));
        let (f01, f11) = (self.texel_1(x0, y0 + 1), self.texel_1(x0 + 1, y0 + 1));
        let gx = (1.0 - wy1) * (f10 - f00) + wy1 * (f11 - f01);
        let gy = (1.0 - wx1) * (f01 - f00) + wx1 * (f11 - f10);
        Vec2::new(self.width as f32 * (m[0][0] * gx + m[1][0] * gy), self.height as f32 * (m[0][1] * gx + m[1][1] * gy))
    }

    /// The mean texel, as RGB.
    pub fn mean(&self) -> Rgb {
        let n = self.width * self.height;
        let mut sum = [0.0f64; 3];
        // Straight over the stored values: no wrapping, no per-texel RGB assembly.
        for k in 0..n {
            let base = k * self.channels;
            for (c, s) in sum.iter_mut().enumerate() {
                *s += self.value(base + c.min(self.channels - 1)) as f64;
            }
        }
        Rgb(sum.map(|s| (s / n.max(1) as f64) as f32))
    }

    /// The smallest and largest texel channel.
    pub fn range(&self) -> (f32, f32) {
        let n = self.width * self.height * self.channels;
        (0..n).map(|k| self.value(k)).fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
    }
}

/// Luminance with Mitsuba's weights.
#[inline]
fn luminance(c: Rgb) -> f32 {
    LUMINANCE[0] * c.0[0] + LUMINANCE[1] * c.0[1] + LUMINANCE[2] * c.0[2]
}

/// A texel index wrapped into [0, n).
#[inline(always)]
fn wrap(i: i64, n: usize, mode: WrapMode) -> usize {
    let n = n as i64;
    // Inside the image every mode is the identity; only the edges need a division.
    if (0..n).contains(&i) {
        return i as usize;
    }
    (match mode {
        WrapMode::Clamp => i.clamp(0, n - 1),
        WrapMode::Repeat => i.rem_euclid(n),
        WrapMode::Mirror => {
            let m = i.rem_euclid(n);
            if i.div_euclid(n) % 2 == 0 {
                m
            } else {
                n - 1 - m
            }
        }
    }) as usize
}

/// `wrap(i, …)` and `wrap(i + 1, …)`, with one division where `wrap` would make two: a
/// repeated texture (scaled by `to_uv`, most lookups fall outside the image) wraps i + 1 from
/// i's index.
#[inline(always)]
fn wrap_pair(i: i64, n: usize, mode: WrapMode) -> (usize, usize) {
    let a = wrap(i, n, mode);
    match mode {
        WrapMode::Repeat => (a, if a + 1 == n { 0 } else { a + 1 }),
        WrapMode::Clamp | WrapMode::Mirror => (a, wrap(i + 1, n, mode)),
    }
}

/// Checks the size against the data and doubles a side shorter than 2 texels.
fn at_least_two<T: Copy>(
    w: usize,
    h: usize,
    channels: usize,
    data: Vec<T>,
) -> std::result::Result<(usize, usize, Vec<T>), String> {
    if w == 0 || h == 0 {
        return Err(format!("the image is {w}×{h}: it has no texels"));
    }
    if data.len() != w * h * channels {
        return Err(format!("{} values for a {w}×{h} image of {channels} channels", data.len()));
    }
    let (w2, h2) = (w.max(2), h.max(2));
    if (w2, h2) == (w, h) {
        return Ok((w, h, data));
    }
    let mut out = Vec::with_capacity(w2 * h2 * channels);
    for y in 0..h2 {
        for x in 0..w2 {
            let k = ((y.min(h - 1)) * w + x.min(w - 1)) * channels;
            out.extend_from_slice(&data[k..k + channels]);
        }
    }
    Ok((w2, h2, out))
}

#[cfg(test)]
#[allow(clippy::excessive_precision)] // Mitsuba's reference numbers, as it prints them
mod tests {
    use super::*;

    /// Mitsuba's test image t32.png: 3 × 2 RGB8.
    fn t32(filter: FilterType, wrap: WrapMode, raw: bool) -> Bitmap {
        #[rustfmt::skip]
        let bytes = vec![10, 20, 30, 100, 110, 120, 200, 210, 220, 40, 50, 60, 130, 140, 150, 250, 0, 128];
        let img = image::DynamicImage::ImageRgb8(image::RgbImage::from_raw(3, 2, bytes).unwrap());
        Bitmap::from_image(img, BitmapOptions { filter, wrap, raw, to_uv: UvTransform::IDENTITY }).unwrap()
    }

    /// Within Mitsuba's rational fit of the sRGB curve (2.5e-6 relative) and f32 rounding.
    fn close(a: Rgb, b: [f32; 3]) -> bool {
        (0..3).all(|c| (a.0[c] - b[c]).abs() <= 4e-6 * b[c].abs() + 1e-9)
    }

    #[test]
    fn a_wrapped_pair_is_two_wraps() {
        for mode in [WrapMode::Repeat, WrapMode::Clamp, WrapMode::Mirror] {
            for n in [1, 2, 3, 7] {
                for i in -5 * n as i64..5 * n as i64 {
                    assert_eq!(wrap_pair(i, n, mode), (wrap(i, n, mode), wrap(i + 1, n, mode)), "{mode:?} {i} in {n}");
                }
            }
        }
    }

    #[test]
    fn lookups_match_mitsuba() {
        use FilterType::*;
        use WrapMode::*;
        // Reference values: Mitsuba 3.9.1 scalar_rgb, texture.eval at the given uv.
        type Case = (FilterType, WrapMode, bool, (f32, f32), [f32; 3]);
        let cases: &[Case] = &[
            (Nearest, Repeat, false, (0.1, 0.1), [0.0030352699, 0.006995399, 0.01298306]),
            (Nearest, Repeat, false, (0.9, 0.9), [0.95597327, 0.0, 0.21586041]),
            (Nearest, Repeat, false, (-0.1, 0.1), [0.57758075, 0.64447987, 0.71569359]),
            (Nearest, Repeat, false, (2.5, -0.7), [0.12743777, 0.15592651, 0.18782076]),
            (Nearest, Mirror, false, (0.1, 1.3), [0.021219011, 0.031895995, 0.045186169]),
            (Nearest, Mirror, false, (2.5, -0.7), [0.22322789, 0.26225057, 0.30498722]),
            (Nearest, Repeat, true, (0.9, 0.9), [0.98039222, 0.0, 0.50196081]),
            (Bilinear, Repeat, false, (0.1, 0.1), [0.14501201, 0.10179964, 0.13126391]),
            (Bilinear, Repeat, false, (0.3, 0.6), [0.087254681, 0.10679684, 0.12925006]),
            (Bilinear, Repeat, false, (0.9, 0.9), [0.67711735, 0.15956034, 0.2997534]),
            (Bilinear, Repeat, false, (1.2, 0.1), [0.023258856, 0.031801417, 0.042676695]),
            (Bilinear, Repeat, false, (0.0, 0.0), [0.3894521, 0.17084281, 0.24743082]),
            (Bilinear, Mirror, false, (1.2, 0.1), [0.53256637, 0.59562445, 0.66290623]),
            (Bilinear, Mirror, false, (2.5, -0.7), [0.21364889, 0.25161818, 0.29327056]),
            (Bilinear, Clamp, false, (1.2, 0.1), [0.57758075, 0.64447987, 0.71569359]),
            (Bilinear, Repeat, true, (0.1, 0.1), [0.22823529, 0.20627452, 0.2732549]),
            (Bilinear, Mirror, true, (2.5, -0.7), [0.49803925, 0.53725493, 0.57647061]),
        ];
        for &(f, w, raw, (u, v), want) in cases {
            let got = t32(f, w, raw).eval(Vec2::new(u, v));
            assert!(close(got, want), "{f:?} {w:?} raw={raw} at ({u}, {v}): {got:?} vs {want:?}");
        }
        let b = t32(Bilinear, Repeat, false);
        assert!((b.eval_1(Vec2::new(0.1, 0.1)) - 0.11311606).abs() < 2e-7);
        assert!((t32(Bilinear, Clamp, false).eval_1(Vec2::new(0.3, 0.6)) - 0.10426122).abs() < 2e-7);
    }

    #[test]
    fn grey_images_gradients_and_small_images() {
        // y8.png, 2×2 grey (0, 64 / 128, 255), bilinear at the centre: Mitsuba 0.31678247 (sRGB), 0.43823531 (raw).
        let grey = |raw| {
            let img = image::DynamicImage::ImageLuma8(image::GrayImage::from_raw(2, 2, vec![0, 64, 128, 255]).unwrap());
            Bitmap::from_image(img, BitmapOptions { raw, ..Default::default() }).unwrap()
        };
        assert!((grey(false).eval_1(Vec2::splat(0.5)) - 0.31678247).abs() < 1e-6);
        assert!((grey(true).eval(Vec2::splat(0.5)).0[2] - 0.43823531).abs() < 1e-6);
        assert_eq!(grey(true).channels(), 1);
        // h.exr, 4 × 3 heights: Mitsuba's eval_1 and eval_1_grad.
        #[rustfmt::skip]
        let h = vec![0.0, 0.1, 0.3, 0.2, 0.5, 0.4, 0.9, 0.6, 0.2, 0.8, 0.7, 1.0];
        let b = Bitmap::from_floats(4, 3, 1, h, BitmapOptions::default()).unwrap();
        assert!((b.eval_1(Vec2::new(0.3, 0.4)) - 0.322).abs() < 1e-6);
        for ((u, v), g) in [((0.3, 0.4), (-0.16, 1.08)), ((0.6, 0.8), (-0.16, -0.42)), ((0.05, 0.1), (-1.28, -1.14))] {
            let got = b.eval_1_grad(Vec2::new(u, v));
            assert!((got - Vec2::new(g.0, g.1)).length() < 1e-5, "({u}, {v}): {got}");
        }
        // A 1 × 1 image becomes 2 × 2 copies; a 3 × 1 row gets a second identical row.
        let one = Bitmap::from_floats(1, 1, 3, vec![0.2, 0.4, 0.6], BitmapOptions::default()).unwrap();
        assert_eq!(one.size(), (2, 2));
        assert!(close(one.eval(Vec2::new(0.7, 0.1)), [0.2, 0.4, 0.6]));
        assert!(Bitmap::from_floats(0, 3, 1, vec![], BitmapOptions::default()).is_err());
        assert!(Bitmap::from_floats(2, 2, 3, vec![0.0; 5], BitmapOptions::default()).is_err());
    }

    #[test]
    fn prefetch_stays_inside_the_image_at_any_uv() {
        // The hint indexes the texels itself: a uv far outside, infinite or NaN must still
        // name a texel of the image (an index past the end panics).
        let odd = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30, -0.0, 1.0, 0.99999994, -1e-8, 2.5];
        for w in [WrapMode::Repeat, WrapMode::Clamp, WrapMode::Mirror] {
            let floats = Bitmap::from_floats(3, 5, 3, vec![0.5; 45], BitmapOptions { wrap: w, ..Default::default() });
            for b in [t32(FilterType::Bilinear, w, false), t32(FilterType::Nearest, w, true), floats.unwrap()] {
                for u in odd {
                    for v in odd {
                        b.prefetch(Vec2::new(u, v));
                    }
                }
            }
        }
    }
}
