//! The one typeface of every picture gonio draws (plot PNGs, render and compare labels):
//! DejaVu Sans, bundled in the binary (Bitstream Vera licence, `assets/DejaVuSans-LICENSE.txt`)
//! so that text looks the same on every machine and is there on one with no fonts installed.

use resvg::usvg;

/// The font file.
const DEJAVU_SANS: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// SVG parsing options whose font database holds the bundled font only, also as the generic
/// `sans-serif` family (the system's fonts are never consulted).
pub fn svg_options() -> usvg::Options<'static> {
    let mut opt = usvg::Options::default();
    let db = opt.fontdb_mut();
    db.load_font_data(DEJAVU_SANS.to_vec());
    db.set_sans_serif_family("DejaVu Sans");
    opt
}

/// `text` escaped for SVG character data and attribute values.
pub fn escape(text: &str) -> String {
    let mut o = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            c => o.push(c),
        }
    }
    o
}
