//! Tabulated gonio-reflectometer data: a plain text table any measurement setup can export.
//!
//! The format (UTF-8 text, one measurement per line):
//!
//! ```text
//! # gonio tabulated BRDF v1
//! # angles in degrees: θ from the normal, φ from the surface's x (tangent) towards y;
//! # i = towards the light, o = towards the viewer; r g b = BRDF in 1/sr (negative: not measured)
//! theta_i,phi_i,theta_o,phi_o,r,g,b
//! 0,0,0,0,0.2546,0.2546,0.2546
//! ```
//!
//! Lines starting with `#` and blank lines are ignored; the column-name line is optional; fields
//! are separated by commas or whitespace. The rows must form a full grid: every combination of
//! the distinct θi, φi, θo and φo values present exactly once, in any order (values equal to
//! 1e-6° are the same value). θ lies in [0, 90]; φ is taken modulo 360.
//!
//! Lookup is multilinear on the grid: θ axes are held at their end values beyond the measured
//! range; a φ axis with several values wraps around 360°; a single φi value means the data
//! was measured in one plane of incidence, and lookups rotate both directions about the normal
//! to it (valid for isotropic surfaces). Unmeasured corners are left out and the remaining
//! weights renormalised.

use super::error::MeasuredError;
use crate::Brdf;
use radiometry::{Rgb, Vec3};
use std::fmt::Write as _;
use std::path::Path;

/// The first line `to_text` writes.
pub const HEADER: &str = "# gonio tabulated BRDF v1";
const COLUMNS: &str = "theta_i,phi_i,theta_o,phi_o,r,g,b";

/// A BRDF measured on a θi × φi × θo × φo grid (degrees).
#[derive(Clone, Debug, PartialEq)]
pub struct Tabulated {
    /// Incident polar angles, ascending.
    pub theta_i: Vec<f64>,
    /// Incident azimuths in [0, 360), ascending.
    pub phi_i: Vec<f64>,
    /// Outgoing polar angles, ascending.
    pub theta_o: Vec<f64>,
    /// Outgoing azimuths in [0, 360), ascending.
    pub phi_o: Vec<f64>,
    /// ρ in 1/sr at index ((iθi · nφi + iφi) · nθo + iθo) · nφo + iφo; negative = not measured.
    pub values: Vec<[f32; 3]>,
}

/// `n` polar angles j · 90/n, j = 0..n (the horizon itself sees nothing).
pub fn uniform_theta(n: usize) -> Vec<f64> {
    (0..n).map(|j| j as f64 * 90.0 / n as f64).collect()
}

/// `n` azimuths j · 360/n, j = 0..n.
pub fn uniform_phi(n: usize) -> Vec<f64> {
    (0..n).map(|j| j as f64 * 360.0 / n as f64).collect()
}

fn direction(theta_deg: f64, phi_deg: f64) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new((t.sin() * p.cos()) as f32, (t.sin() * p.sin()) as f32, t.cos() as f32)
}

fn angles(w: Vec3) -> (f64, f64) {
    let w = w.as_dvec3();
    let t = w.z.clamp(-1.0, 1.0).acos().to_degrees();
    let p = w.y.atan2(w.x).to_degrees();
    (t, if p < 0.0 { p + 360.0 } else { p })
}

/// Bracketing indices and the weight of the upper one along a sorted axis.
fn bracket(axis: &[f64], x: f64, periodic: bool) -> ([usize; 2], f64) {
    let n = axis.len();
    if n == 1 {
        return ([0, 0], 0.0);
    }
    if periodic {
        // Between the last value and the first one + 360 the axis wraps.
        let x = x.rem_euclid(360.0);
        let hi = axis.partition_point(|&v| v <= x);
        let (i0, i1) = if hi == 0 || hi == n { (n - 1, 0) } else { (hi - 1, hi) };
        let lo_v = axis[i0];
        let mut span = axis[i1] - lo_v;
        let mut off = x - lo_v;
        if span <= 0.0 {
            span += 360.0;
        }
        if off < 0.0 {
            off += 360.0;
        }
        return ([i0, i1], (off / span).clamp(0.0, 1.0));
    }
    if x <= axis[0] {
        return ([0, 0], 0.0);
    }
    if x >= axis[n - 1] {
        return ([n - 1, n - 1], 0.0);
    }
    let hi = axis.partition_point(|&v| v <= x).min(n - 1);
    let lo = hi - 1;
    ([lo, hi], ((x - axis[lo]) / (axis[hi] - axis[lo])).clamp(0.0, 1.0))
}

impl Tabulated {
    /// Measures `brdf` at every grid point (directions on or below the horizon read 0).
    pub fn from_brdf(brdf: &dyn Brdf, theta_i: Vec<f64>, phi_i: Vec<f64>, theta_o: Vec<f64>, phi_o: Vec<f64>) -> Self {
        let mut values = Vec::with_capacity(theta_i.len() * phi_i.len() * theta_o.len() * phi_o.len());
        for &ti in &theta_i {
            for &pi in &phi_i {
                let wi = direction(ti, pi);
                for &to in &theta_o {
                    for &po in &phi_o {
                        let c = brdf.eval(wi, direction(to, po));
                        values.push(c.0.map(|v| if v.is_finite() { v.max(0.0) } else { -1.0 }));
                    }
                }
            }
        }
        Tabulated { theta_i, phi_i, theta_o, phi_o, values }
    }

    fn index(&self, a: usize, b: usize, c: usize, d: usize) -> usize {
        ((a * self.phi_i.len() + b) * self.theta_o.len() + c) * self.phi_o.len() + d
    }

    /// ρ at (wi, wo) by multilinear interpolation on the grid.
    pub fn lookup(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 || self.values.is_empty() {
            return Rgb::ZERO;
        }
        let (ti, mut pi) = angles(wi);
        let (to, mut po) = angles(wo);
        if self.phi_i.len() == 1 {
            // One plane of incidence: rotate both directions so wi lies in it.
            po = (po - pi + self.phi_i[0]).rem_euclid(360.0);
            pi = self.phi_i[0];
        }
        let axes = [
            bracket(&self.theta_i, ti, false),
            bracket(&self.phi_i, pi, true),
            bracket(&self.theta_o, to, false),
            bracket(&self.phi_o, po, true),
        ];
        let mut sum = [0.0f64; 3];
        let mut wsum = [0.0f64; 3];
        for corner in 0..16 {
            let mut w = 1.0;
            let mut idx = [0usize; 4];
            for (k, (ix, f)) in axes.iter().enumerate() {
                let up = (corner >> k) & 1 == 1;
                w *= if up { *f } else { 1.0 - *f };
                idx[k] = ix[usize::from(up)];
            }
            if w <= 0.0 {
                continue;
            }
            let v = self.values[self.index(idx[0], idx[1], idx[2], idx[3])];
            for c in 0..3 {
                if v[c] >= 0.0 {
                    sum[c] += w * f64::from(v[c]);
                    wsum[c] += w;
                }
            }
        }
        let ch = |c: usize| if wsum[c] > 1e-9 { (sum[c] / wsum[c]) as f32 } else { 0.0 };
        Rgb::new(ch(0), ch(1), ch(2))
    }

    /// The table as text in the documented format.
    pub fn to_text(&self) -> String {
        let mut s = String::with_capacity(64 * self.values.len() + 256);
        s.push_str(HEADER);
        s.push('\n');
        s.push_str("# angles in degrees: theta from the normal, phi from the surface's x (tangent) towards y;\n");
        s.push_str("# i = towards the light, o = towards the viewer; r g b = BRDF in 1/sr (negative: not measured)\n");
        s.push_str(COLUMNS);
        s.push('\n');
        for (a, &ti) in self.theta_i.iter().enumerate() {
            for (b, &pi) in self.phi_i.iter().enumerate() {
                for (c, &to) in self.theta_o.iter().enumerate() {
                    for (d, &po) in self.phi_o.iter().enumerate() {
                        let v = self.values[self.index(a, b, c, d)];
                        // `{}` prints the shortest text that reads back to the same f32.
                        let _ = writeln!(s, "{ti},{pi},{to},{po},{},{},{}", v[0], v[1], v[2]);
                    }
                }
            }
        }
        s
    }

    /// Writes the table to `path` (temporary file, then rename).
    pub fn write(&self, path: &Path) -> Result<(), MeasuredError> {
        super::write_atomic(path, self.to_text().as_bytes())
    }

    /// Reads a table from `path`.
    pub fn read(path: &Path) -> Result<Self, MeasuredError> {
        let bytes = std::fs::read(path).map_err(|e| MeasuredError::io(path, e))?;
        let text = String::from_utf8(bytes).map_err(|e| MeasuredError::Parse {
            path: path.to_path_buf(),
            line: 0,
            message: format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        })?;
        Self::parse(&text, path)
    }

    /// Parses the text format; `path` names the file in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Self, MeasuredError> {
        let err = |line: usize, message: String| MeasuredError::Parse { path: path.to_path_buf(), line, message };
        let mut rows: Vec<([f64; 4], [f32; 3], usize)> = Vec::new();
        for (n, raw) in text.lines().enumerate() {
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> =
                line.split(|c: char| c == ',' || c.is_whitespace()).filter(|f| !f.is_empty()).collect();
            if rows.is_empty() && fields.first().is_some_and(|f| f.starts_with(|c: char| c.is_ascii_alphabetic())) {
                if fields.len() != 7 {
                    return Err(err(n + 1, format!("the column line must name 7 columns ({COLUMNS})")));
                }
                continue;
            }
            if fields.len() != 7 {
                return Err(err(n + 1, format!("{} fields; expected 7: {COLUMNS}", fields.len())));
            }
            let mut v = [0.0f64; 7];
            for (k, f) in fields.iter().enumerate() {
                v[k] = f.parse().map_err(|_| err(n + 1, format!("'{f}' is not a number")))?;
                if !v[k].is_finite() {
                    return Err(err(n + 1, format!("'{f}' is not a finite number")));
                }
            }
            for (k, name) in [(0, "theta_i"), (2, "theta_o")] {
                if !(0.0..=90.0).contains(&v[k]) {
                    return Err(err(n + 1, format!("{name} = {} is outside [0, 90] degrees", v[k])));
                }
            }
            let rgb = [v[4] as f32, v[5] as f32, v[6] as f32];
            if rgb.iter().any(|c| !c.is_finite()) {
                return Err(err(n + 1, "a value overflows single precision".into()));
            }
            // Snap to 1e-6° so values written with rounding noise fall on one grid line.
            let snap = |x: f64| (x * 1e6).round() / 1e6;
            let key =
                [snap(v[0]), snap(v[1].rem_euclid(360.0)) % 360.0, snap(v[2]), snap(v[3].rem_euclid(360.0)) % 360.0];
            rows.push((key, rgb, n + 1));
        }
        if rows.is_empty() {
            return Err(err(0, "no measurements".into()));
        }
        let axis = |k: usize| {
            let mut a: Vec<f64> = rows.iter().map(|r| r.0[k]).collect();
            a.sort_by(f64::total_cmp);
            a.dedup();
            a
        };
        let t = Tabulated { theta_i: axis(0), phi_i: axis(1), theta_o: axis(2), phi_o: axis(3), values: Vec::new() };
        let dims = [t.theta_i.len(), t.phi_i.len(), t.theta_o.len(), t.phi_o.len()];
        let total: usize = dims.iter().product();
        let mut values = vec![[f32::NAN; 3]; total];
        let pos = |a: &[f64], x: f64| a.binary_search_by(|v| v.total_cmp(&x)).expect("value from this axis");
        for (key, rgb, line) in &rows {
            let i =
                t.index(pos(&t.theta_i, key[0]), pos(&t.phi_i, key[1]), pos(&t.theta_o, key[2]), pos(&t.phi_o, key[3]));
            if !values[i][0].is_nan() {
                return Err(err(*line, format!("a second measurement at {:?}", key)));
            }
            values[i] = *rgb;
        }
        if let Some(missing) = values.iter().position(|v| v[0].is_nan()) {
            let d = missing % dims[3];
            let c = (missing / dims[3]) % dims[2];
            let b = (missing / dims[3] / dims[2]) % dims[1];
            let a = missing / dims[3] / dims[2] / dims[1];
            return Err(err(
                0,
                format!(
                    "not a full grid: {} rows for {} θi × {} φi × {} θo × {} φo = {total} combinations; none at \
                     (θi, φi, θo, φo) = ({}, {}, {}, {})",
                    rows.len(),
                    dims[0],
                    dims[1],
                    dims[2],
                    dims[3],
                    t.theta_i[a],
                    t.phi_i[b],
                    t.theta_o[c],
                    t.phi_o[d]
                ),
            ));
        }
        Ok(Tabulated { values, ..t })
    }
}
