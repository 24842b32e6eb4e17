//! A small hand-written SVG document builder: lines, polylines, text, legends, axis ticks.
//! Plots are a few hundred elements, so string building beats a dependency.

use std::fmt::Write as _;

/// Font stack: DejaVu Sans is what the PNG rasteriser finds on a bare Linux box.
pub const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";

/// Colour-blind-safe series colours (Okabe & Ito 2008), in legend order.
pub const PALETTE: [&str; 7] = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"];

/// The stroke of series `i`: a palette colour, dashed once the palette has been used up.
pub fn series_style(i: usize) -> (&'static str, Option<&'static str>) {
    let dash = match (i / PALETTE.len()) % 3 {
        0 => None,
        1 => Some("8 4"),
        _ => Some("2 3"),
    };
    (PALETTE[i % PALETTE.len()], dash)
}

/// An SVG document under construction, in user units = pixels.
pub struct Svg {
    width: f64,
    height: f64,
    defs: String,
    body: String,
}

/// Escapes text for XML content and attribute values.
pub fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
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

/// Horizontal text anchoring.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    /// Text starts at x.
    Start,
    /// Text is centred on x.
    Middle,
    /// Text ends at x.
    End,
}

impl Anchor {
    fn as_str(self) -> &'static str {
        match self {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        }
    }
}

impl Svg {
    /// A blank white document of the given size.
    pub fn new(width: f64, height: f64) -> Self {
        let mut s = Svg { width, height, defs: String::new(), body: String::new() };
        s.rect(0.0, 0.0, width, height, "fill=\"#ffffff\"");
        s
    }

    /// Adds raw markup to `<defs>` (gradients, markers).
    pub fn def(&mut self, markup: &str) {
        self.defs.push_str(markup);
        self.defs.push('\n');
    }

    /// Adds raw markup to the body.
    pub fn raw(&mut self, markup: &str) {
        self.body.push_str(markup);
        self.body.push('\n');
    }

    /// A rectangle with extra attributes (`fill=..`, `stroke=..`).
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, attrs: &str) {
        let _ = writeln!(self.body, r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" {attrs}/>"#);
    }

    /// A straight line segment.
    pub fn line(&mut self, (x1, y1): (f64, f64), (x2, y2): (f64, f64), stroke: &str, width: f64, dash: Option<&str>) {
        let dash = dash.map(|d| format!(r#" stroke-dasharray="{d}""#)).unwrap_or_default();
        let _ = writeln!(
            self.body,
            r#"<line x1="{x1:.2}" y1="{y1:.2}" x2="{x2:.2}" y2="{y2:.2}" stroke="{stroke}" stroke-width="{width}"{dash}/>"#
        );
    }

    /// An open polyline as a `<path>`; non-finite points break the line instead of corrupting it.
    pub fn polyline(&mut self, pts: &[(f64, f64)], stroke: &str, width: f64, dash: Option<&str>) {
        let d = path_data(pts, false);
        if d.is_empty() {
            return;
        }
        let dash = dash.map(|d| format!(r#" stroke-dasharray="{d}""#)).unwrap_or_default();
        let _ = writeln!(
            self.body,
            r#"<path d="{d}" fill="none" stroke="{stroke}" stroke-width="{width}" stroke-linejoin="round"{dash}/>"#
        );
    }

    /// A closed filled polygon.
    pub fn polygon(&mut self, pts: &[(f64, f64)], fill: &str, opacity: f64) {
        let d = path_data(pts, true);
        if d.is_empty() {
            return;
        }
        let _ = writeln!(self.body, r#"<path d="{d}" fill="{fill}" fill-opacity="{opacity}" stroke="none"/>"#);
    }

    /// A line of text; `markup` may hold `<tspan>`s, so callers escape plain text with [`esc`].
    pub fn text_markup(&mut self, x: f64, y: f64, markup: &str, size: f64, anchor: Anchor, attrs: &str) {
        let _ = writeln!(
            self.body,
            r##"<text x="{x:.2}" y="{y:.2}" font-family="{FONT}" font-size="{size}" text-anchor="{}" fill="#222222" {attrs}>{markup}</text>"##,
            anchor.as_str()
        );
    }

    /// A line of plain text.
    pub fn text(&mut self, x: f64, y: f64, text: &str, size: f64, anchor: Anchor) {
        self.text_markup(x, y, &esc(text), size, anchor, "");
    }

    /// A legend box with one row per (label, colour, dash) at the top-left corner (x, y).
    pub fn legend(&mut self, x: f64, y: f64, rows: &[(String, &str, Option<&str>)]) {
        if rows.is_empty() {
            return;
        }
        let row_h = 18.0;
        // Rough text width: DejaVu Sans at 12 px averages ~7 px per character.
        let w = rows.iter().map(|(l, _, _)| l.chars().count()).max().unwrap_or(0) as f64 * 7.0 + 46.0;
        let h = rows.len() as f64 * row_h + 8.0;
        self.rect(x, y, w, h, r##"fill="#ffffff" fill-opacity="0.85" stroke="#bbbbbb""##);
        for (i, (label, colour, dash)) in rows.iter().enumerate() {
            let cy = y + 4.0 + row_h * (i as f64 + 0.5);
            self.line((x + 8.0, cy), (x + 32.0, cy), colour, 2.5, *dash);
            self.text(x + 38.0, cy + 4.0, label, 12.0, Anchor::Start);
        }
    }

    /// A plot frame over angles 0–90° (ticks every 15°) and values 0–`ymax`, with grid lines
    /// and axis labels; `frame` is (x0, x1, y0, y1), y0 at the top.
    pub fn angle_axes(&mut self, frame: (f64, f64, f64, f64), ymax: f64, x_label: &str, y_label: &str) {
        let (x0, x1, y0, y1) = frame;
        let px = |theta: f64| x0 + (x1 - x0) * theta / 90.0;
        let py = |v: f64| y1 - (y1 - y0) * v / ymax;
        for t in nice_ticks(0.0, ymax, 6) {
            self.line((x0, py(t)), (x1, py(t)), "#e6e6e6", 1.0, None);
            self.text(x0 - 8.0, py(t) + 4.0, &fmt_tick(t), 11.0, Anchor::End);
        }
        for t in (0..=6).map(|k| f64::from(k) * 15.0) {
            self.line((px(t), y0), (px(t), y1), "#e6e6e6", 1.0, None);
            self.text(px(t), y1 + 18.0, &format!("{}°", fmt_tick(t)), 11.0, Anchor::Middle);
        }
        self.rect(x0, y0, x1 - x0, y1 - y0, r##"fill="none" stroke="#444444" stroke-width="1""##);
        self.text((x0 + x1) / 2.0, y1 + 40.0, x_label, 13.0, Anchor::Middle);
        let mid = (y0 + y1) / 2.0;
        self.text_markup(
            24.0,
            mid,
            &esc(y_label),
            13.0,
            Anchor::Middle,
            &format!(r#"transform="rotate(-90 24 {mid:.1})""#),
        );
    }

    /// The finished document.
    pub fn finish(self) -> String {
        let mut o = String::new();
        let _ = writeln!(
            o,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#,
            w = self.width,
            h = self.height
        );
        if !self.defs.is_empty() {
            let _ = writeln!(o, "<defs>\n{}</defs>", self.defs);
        }
        o.push_str(&self.body);
        o.push_str("</svg>\n");
        o
    }
}

fn path_data(pts: &[(f64, f64)], close: bool) -> String {
    let mut d = String::new();
    let mut pen_down = false;
    for &(x, y) in pts {
        if !(x.is_finite() && y.is_finite()) {
            pen_down = false;
            continue;
        }
        let _ = write!(d, "{}{x:.2},{y:.2} ", if pen_down { 'L' } else { 'M' });
        pen_down = true;
    }
    if close && !d.is_empty() {
        d.push('Z');
    }
    d.trim_end().to_string()
}

/// About `n` round tick values covering [lo, hi] (steps of 1, 2 or 5 × 10^k).
pub fn nice_ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let step = nice_step((hi - lo) / n.max(1) as f64);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// The round step (1, 2 or 5 × 10^k) nearest above `raw`.
pub fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let m = if f <= 1.0 {
        1.0
    } else if f <= 2.0 {
        2.0
    } else if f <= 5.0 {
        5.0
    } else {
        10.0
    };
    m * mag
}

/// The smallest round number (1, 2, 2.5, 5 × 10^k) ≥ `v`, for an axis maximum.
pub fn nice_ceil(v: f64) -> f64 {
    if !(v.is_finite() && v > 0.0) {
        return 1.0;
    }
    let mag = 10f64.powf(v.log10().floor());
    let f = v / mag;
    let m =
        [1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0].into_iter().find(|&m| f <= m + 1e-9).unwrap_or(10.0);
    m * mag
}

/// A tick label without float noise: 0.30000000000000004 → "0.3".
pub fn fmt_tick(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.0e}");
    }
    let s = format!("{v:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(nice_ticks(0.0, 1.0, 5), vec![0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]);
        assert_eq!(nice_step(0.37), 0.5);
        assert_eq!(nice_ceil(0.35), 0.4);
        assert_eq!(nice_ceil(1.0), 1.0);
        assert_eq!(fmt_tick(0.6000000000000001), "0.6");
        assert_eq!(fmt_tick(25.0), "25");
    }

    #[test]
    fn non_finite_points_break_the_line() {
        assert_eq!(
            path_data(&[(0.0, 0.0), (1.0, f64::NAN), (2.0, 2.0), (3.0, 3.0)], false),
            "M0.00,0.00 M2.00,2.00 L3.00,3.00"
        );
        assert_eq!(esc("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}
