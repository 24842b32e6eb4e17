//! OpenEXR input (the first RGB(A) layer, as linear float) and output (float RGB).

use crate::error::{Error, Result};
use crate::image::Image;
use radiometry::Rgb;
use std::path::Path;

/// Reads the first RGB layer of an EXR file (alpha ignored).
pub fn read_exr(path: &Path) -> Result<Image> {
    let img = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |res, _| Image::new(res.width() as u32, res.height() as u32),
        |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            img.set(pos.x() as u32, pos.y() as u32, Rgb::new(r, g, b));
        },
    )
    .map_err(|e| match e {
        exr::error::Error::Io(io) => Error::io(path, io),
        other => Error::format(path, format!("not a readable RGB OpenEXR image: {other}")),
    })?;
    Ok(img.layer_data.channel_data.pixels)
}

/// Writes `image` to `path` as 32-bit float RGB EXR (not atomically: see `Image::save`).
/// Blocks are compressed one after another: in parallel they land in the file in whatever
/// order they finish, and the same image would not always give the same bytes.
pub fn write_exr(image: &Image, path: &Path) -> Result<()> {
    use exr::prelude::{SpecificChannels, Vec2, WritableImage};
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let p = image.get(x as u32, y as u32).0;
        (p[0], p[1], p[2])
    });
    exr::prelude::Image::from_channels((image.width as usize, image.height as usize), channels)
        .write()
        .non_parallel()
        .to_file(path)
        .map_err(|e| match e {
            exr::error::Error::Io(io) => Error::io(path, io),
            other => Error::format(path, format!("EXR encoding failed: {other}")),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_image_gives_the_same_bytes_and_reads_back_exactly() {
        // Large enough for many compressed blocks, so that parallel writing could reorder them.
        let (w, h) = (300u32, 517u32);
        let mut img = Image::new(w, h);
        let mut state = 12345u32;
        for p in img.pixels.iter_mut() {
            let mut next = || {
                state = state.wrapping_mul(1664525).wrapping_add(1013904223);
                (state >> 8) as f32 / (1 << 24) as f32 * 100.0
            };
            *p = Rgb::new(next(), next(), next());
        }
        let dir = std::env::temp_dir().join(format!("gonio-exr-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let bytes: Vec<Vec<u8>> = (0..3)
            .map(|k| {
                let path = dir.join(format!("{k}.exr"));
                write_exr(&img, &path).unwrap();
                std::fs::read(&path).unwrap()
            })
            .collect();
        let back = read_exr(&dir.join("0.exr")).unwrap();
        std::fs::remove_dir_all(&dir).ok();
        assert!(bytes.windows(2).all(|b| b[0] == b[1]), "three writes of one image differ");
        assert_eq!((back.width, back.height), (w, h));
        assert!(back.pixels.iter().zip(&img.pixels).all(|(a, b)| a.0 == b.0), "pixels changed on the round trip");
    }
}
