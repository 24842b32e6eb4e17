//! Plots of reflection models, drawn as hand-written SVG and rasterised to PNG on request.

pub mod albedo;
pub mod fresnel;
pub mod lobe3d;
pub mod polar;
pub mod raster;
pub mod slice;
pub mod svg;

use brdf::Brdf;

/// One model on a plot: its legend label and the model.
pub struct Series {
    /// Legend text, e.g. `ward (alpha=0.1)`.
    pub label: String,
    /// The model.
    pub brdf: Box<dyn Brdf>,
}

/// A raster image placed in a figure (the slice plot's pixels).
#[derive(Clone, Debug)]
pub struct Image {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Opaque RGBA, row by row from the top.
    pub rgba: Vec<u8>,
    /// Where it goes in the figure: x, y, width, height in figure pixels.
    pub at: (f64, f64, f64, f64),
}

/// A finished plot: SVG markup with at most one raster image marked by [`IMAGE_SLOT`].
pub struct Figure {
    /// The SVG document.
    pub svg: String,
    /// The image that belongs in the slot, if any.
    pub image: Option<Image>,
}

/// Where a figure's raster image goes in its SVG markup.
pub const IMAGE_SLOT: &str = "<!--gonio:image-->";
