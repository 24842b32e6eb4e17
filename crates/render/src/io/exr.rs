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
pub fn write_exr(image: &Image, path: &Path) -> Result<()> {
    exr::prelude::write_rgb_file(path, image.width as usize, image.height as usize, |x, y| {
        let p = image.get(x as u32, y as u32).0;
        (p[0], p[1], p[2])
    })
    .map_err(|e| match e {
        exr::error::Error::Io(io) => Error::io(path, io),
        other => Error::format(path, format!("EXR encoding failed: {other}")),
    })
}
