//! Turning a [`Figure`] into bytes: SVG with its raster image embedded as a PNG data URI, or
//! a PNG rasterised by resvg (text in the bundled font, `font.rs`) with the raster image
//! composited into its place.

use super::{Figure, Image, IMAGE_SLOT};
use anyhow::{anyhow, Context, Result};
use resvg::tiny_skia::{FilterQuality, IntSize, Pixmap, PixmapPaint, Transform};
use resvg::usvg;

fn pixmap(image: &Image) -> Result<Pixmap> {
    let size = IntSize::from_wh(image.width, image.height).context("empty raster image")?;
    // Opaque pixels, so premultiplied RGBA is the same bytes.
    Pixmap::from_vec(image.rgba.clone(), size).context("raster image has the wrong number of bytes")
}

/// The figure as an SVG document.
pub fn to_svg(fig: &Figure) -> Result<String> {
    let Some(img) = &fig.image else { return Ok(fig.svg.replace(IMAGE_SLOT, "")) };
    let png = pixmap(img)?.encode_png().map_err(|e| anyhow!("cannot encode the slice image: {e}"))?;
    let (x, y, w, h) = img.at;
    let tag = format!(
        r#"<image x="{x}" y="{y}" width="{w}" height="{h}" preserveAspectRatio="none" style="image-rendering:pixelated" href="data:image/png;base64,{}"/>"#,
        base64(&png)
    );
    Ok(fig.svg.replace(IMAGE_SLOT, &tag))
}

/// The figure as PNG bytes, `width` pixels wide (default: the SVG's own width).
pub fn to_png(fig: &Figure, width: Option<u32>) -> Result<Vec<u8>> {
    let opt = crate::font::svg_options();
    let svg = fig.svg.replace(IMAGE_SLOT, "");
    let tree = usvg::Tree::from_data(svg.as_bytes(), &opt).context("internal error: the plot is not valid SVG")?;
    let size = tree.size();
    let scale = width.map_or(1.0, |w| w as f32 / size.width());
    let (pw, ph) = ((size.width() * scale).round() as u32, (size.height() * scale).round() as u32);
    if !(1..=16384).contains(&pw) || !(1..=16384).contains(&ph) {
        anyhow::bail!("a {pw}×{ph} PNG is out of range; give --width between 1 and 16384");
    }
    let mut canvas = Pixmap::new(pw, ph).context("cannot allocate the PNG")?;
    resvg::render(&tree, Transform::from_scale(scale, scale), &mut canvas.as_mut());
    if let Some(img) = &fig.image {
        let src = pixmap(img)?;
        let (x, y, w, h) = img.at;
        let (sx, sy) = (w as f32 * scale / img.width as f32, h as f32 * scale / img.height as f32);
        let paint = PixmapPaint { quality: FilterQuality::Nearest, ..PixmapPaint::default() };
        let t = Transform::from_row(sx, 0.0, 0.0, sy, x as f32 * scale, y as f32 * scale);
        canvas.draw_pixmap(0, 0, src.as_ref(), &paint, t, None);
    }
    canvas.encode_png().map_err(|e| anyhow!("cannot encode the PNG: {e}"))
}

/// Standard base64 with padding (RFC 4648 §4).
pub fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut o = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                o.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                o.push('=');
            }
        }
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_the_rfc_vectors() {
        let cases =
            [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foob", "Zm9vYg=="), ("foobar", "Zm9vYmFy")];
        for (i, o) in cases {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }

    #[test]
    fn png_text_comes_from_the_bundled_font() {
        // The plots' own font list, as svg.rs writes it; the build reads no system fonts (resvg
        // without its system-fonts feature), so this is what a machine without fonts renders.
        let text = |t: &str| {
            let svg = format!(
                r##"<svg xmlns="http://www.w3.org/2000/svg" width="120" height="30"><rect width="120" height="30" fill="white"/><text x="4" y="22" font-family="{}" font-size="18" fill="#222222">{t}</text></svg>"##,
                crate::plot::svg::FONT
            );
            let png = to_png(&Figure { svg, image: None }, None).unwrap();
            let pix = Pixmap::decode_png(&png).unwrap();
            pix.pixels().iter().filter(|p| p.red() < 128).count()
        };
        let (some, none) = (text("θi albedo"), text(""));
        assert_eq!(none, 0);
        // Nine glyphs at 18 px: well over a hundred dark pixels.
        assert!(some > 100, "{some} dark pixels");
    }
}
