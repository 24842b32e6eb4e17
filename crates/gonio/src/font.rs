//! The one typeface of every picture gonio draws (plot PNGs, render and compare labels):
//! DejaVu Sans, bundled in the binary (Bitstream Vera licence, `assets/DejaVuSans-LICENSE.txt`)
//! so that text looks the same on every machine and is there on one with no fonts installed.

use resvg::usvg;

/// The font file.
const DEJAVU_SANS: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// The bundled font's family name.
pub const FAMILY: &str = "DejaVu Sans";

/// SVG parsing options whose font database holds the bundled font only, also as the generic
/// `sans-serif` family (the system's fonts are never consulted).
pub fn svg_options() -> usvg::Options<'static> {
    let mut opt = usvg::Options::default();
    let db = opt.fontdb_mut();
    db.load_font_data(DEJAVU_SANS.to_vec());
    db.set_sans_serif_family(FAMILY);
    opt
}
