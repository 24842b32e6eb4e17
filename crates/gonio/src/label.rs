//! Labels drawn onto rendered images: lines of text in the bundled font (`font.rs`),
//! anti-aliased, white on a dark halo so that they read on any background. They are blended
//! into the linear image scaled by 2^−exposure, so that the PNG shows them white whatever
//! `--exposure`, and an EXR carries them too.

use anyhow::{Context, Result};
use radiometry::Rgb;
use render::texture::bitmap::srgb_to_linear;
use render::Image;
use resvg::tiny_skia::{Pixmap, Transform};
use resvg::usvg;

/// Height of a label's first line in pixels for a panel `side` pixels high; later lines are
/// 0.8 of it.
pub fn size_for(side: u32) -> f32 {
    (side as f32 / 16.0).clamp(9.0, 40.0)
}

/// Pixels from the first line's top to the last line's bottom, for `lines` lines at `size`.
pub fn height(lines: usize, size: f32) -> f32 {
    if lines == 0 {
        return 0.0;
    }
    1.25 * size + (lines - 1) as f32 * 1.25 * 0.8 * size
}

/// Draws `lines` with the first line's top-left corner at (`x`, `y`), the first line `size`
/// pixels high, clipped to the image and to `width` pixels.
pub fn draw(img: &mut Image, lines: &[String], x: u32, y: u32, width: u32, size: f32, exposure: f32) -> Result<()> {
    let w = width.min(img.width.saturating_sub(x));
    let h = (height(lines.len(), size).ceil() as u32 + 2).min(img.height.saturating_sub(y));
    if lines.is_empty() || w == 0 || h == 0 {
        return Ok(());
    }
    let mut svg = format!(r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}">"#);
    let mut baseline = 0.0;
    for (i, line) in lines.iter().enumerate() {
        let s = if i == 0 { size } else { 0.8 * size };
        baseline += if i == 0 { 0.95 * s } else { 1.25 * s };
        svg += &format!(
            r#"<text x="{:.2}" y="{baseline:.2}" font-family="{}" font-size="{s:.2}" fill="white" stroke="black" stroke-opacity="0.75" stroke-width="{:.2}" stroke-linejoin="round" paint-order="stroke">{}</text>"#,
            0.1 * size,
            crate::font::FAMILY,
            0.2 * s,
            crate::plot::svg::esc(line)
        );
    }
    svg += "</svg>";
    let tree = usvg::Tree::from_data(svg.as_bytes(), &crate::font::svg_options())
        .context("internal error: the label is not valid SVG")?;
    let mut pix = Pixmap::new(w, h).context("cannot allocate the label")?;
    resvg::render(&tree, Transform::identity(), &mut pix.as_mut());
    let scale = (-exposure).exp2();
    for (k, p) in pix.pixels().iter().enumerate() {
        let a = p.alpha();
        if a == 0 {
            continue;
        }
        let a = a as f32 / 255.0;
        // Premultiplied sRGB bytes → straight linear colour at the image's exposure.
        let lin = |c: u8| srgb_to_linear((c as f64 / 255.0 / a as f64).min(1.0)) as f32 * scale;
        let c = Rgb::new(lin(p.red()), lin(p.green()), lin(p.blue()));
        let (px, py) = (x + k as u32 % w, y + k as u32 / w);
        img.set(px, py, img.get(px, py) * (1.0 - a) + c * a);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_drawn_inside_its_box_only_and_clips() {
        let mut img = Image::new(240, 70);
        for p in img.pixels.iter_mut() {
            *p = Rgb::splat(0.5);
        }
        draw(&mut img, &["ggx".into(), "alpha 0.1".into()], 10, 5, 200, 20.0, 0.0).unwrap();
        let h = height(2, 20.0).ceil() as u32 + 2;
        let (mut white, mut changed_outside) = (0, 0);
        for y in 0..70 {
            for x in 0..240 {
                let p = img.get(x, y);
                let inside = (10..210).contains(&x) && (5..5 + h).contains(&y);
                if p != Rgb::splat(0.5) && !inside {
                    changed_outside += 1;
                }
                if inside && p.0.iter().all(|&c| c > 0.95) {
                    white += 1;
                }
            }
        }
        assert_eq!(changed_outside, 0);
        // Glyph strokes two pixels wide over 11 characters: dozens of white pixels.
        assert!(white > 40, "{white} white pixels");
        // Exposure +2 stops: the text's linear value is a quarter, so it still encodes white.
        let mut dim = Image::new(60, 20);
        draw(&mut dim, &["g".into()], 0, 0, 60, 16.0, 2.0).unwrap();
        let max = dim.pixels.iter().map(|p| p.0[1]).fold(0.0, f32::max);
        assert!((max - 0.25).abs() < 1e-3, "{max}");
        // Past the edges: nothing to draw, no panic.
        draw(&mut dim, &["cook-torrance".into()], 59, 19, 200, 30.0, 0.0).unwrap();
        draw(&mut dim, &["x".into()], 80, 0, 10, 10.0, 0.0).unwrap();
    }
}
