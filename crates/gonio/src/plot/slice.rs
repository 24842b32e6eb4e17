//! The Disney BRDF Explorer's image slice (Burley 2012): ρ over the half-angle θh (x axis) and
//! the difference angle θd (y axis), 0–90° each, at a fixed difference azimuth φd, in the
//! half/difference parametrisation of Rusinkiewicz 1998. Colour: log10 ρ through the magma map.
//!
//! With φh = 0, h = R_y(θh)·z; wi = R_y(θh)·d(θd, φd) and wo = R_y(θh)·d(θd, φd + π), where
//! R_y(θ) tilts +z towards +x, so (wi + wo) ∝ h by construction.

use super::svg::{esc, Anchor, Svg};
use super::{Figure, Image, Series, IMAGE_SLOT};
use crate::cli::Channel;
use brdf::Brdf;
use radiometry::Vec3;
use std::fmt::Write as _;

/// Cells per axis (0.5° each).
pub const CELLS: usize = 180;

/// Colour of cells where wi or wo lies below the horizon.
const BELOW: [u8; 3] = [0x9a, 0x9a, 0x9a];

/// Magma colour map (matplotlib, van der Walt & Smith), sampled at nine points.
const MAGMA: [[u8; 3]; 9] = [
    [0, 0, 4],
    [28, 16, 68],
    [79, 18, 123],
    [129, 37, 129],
    [181, 54, 122],
    [229, 80, 100],
    [251, 135, 97],
    [254, 194, 135],
    [252, 253, 191],
];

/// The colour for t ∈ [0, 1] (clamped).
pub fn magma(t: f64) -> [u8; 3] {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let x = t * (MAGMA.len() - 1) as f64;
    let k = (x.floor() as usize).min(MAGMA.len() - 2);
    let f = x - k as f64;
    std::array::from_fn(|c| (f64::from(MAGMA[k][c]) * (1.0 - f) + f64::from(MAGMA[k + 1][c]) * f).round() as u8)
}

fn rotate_y(v: Vec3, theta: f32) -> Vec3 {
    let (s, c) = theta.sin_cos();
    Vec3::new(v.x * c + v.z * s, v.y, -v.x * s + v.z * c)
}

/// (wi, wo) for half angle θh, difference angle θd and difference azimuth φd, all in radians.
pub fn directions(theta_h: f32, theta_d: f32, phi_d: f32) -> (Vec3, Vec3) {
    let d = radiometry::spherical_direction(theta_d, phi_d);
    let d_opposite = Vec3::new(-d.x, -d.y, d.z);
    (rotate_y(d, theta_h), rotate_y(d_opposite, theta_h))
}

/// ρ over the grid: row 0 is the largest θd, so the image reads with θd increasing upwards.
/// `None` marks cells where wi or wo is below the horizon.
pub fn grid(brdf: &dyn Brdf, phi_d_deg: f64, channel: Channel) -> Vec<Option<f64>> {
    grid_of(brdf, phi_d_deg, channel, CELLS)
}

/// [`grid`] with `cells` × `cells` cells.
pub fn grid_of(brdf: &dyn Brdf, phi_d_deg: f64, channel: Channel, cells: usize) -> Vec<Option<f64>> {
    let cell = std::f32::consts::FRAC_PI_2 / cells as f32;
    let phi_d = phi_d_deg.to_radians() as f32;
    let mut out = Vec::with_capacity(cells * cells);
    for row in 0..cells {
        let theta_d = (cells - 1 - row) as f32 * cell + 0.5 * cell;
        for col in 0..cells {
            let theta_h = col as f32 * cell + 0.5 * cell;
            let (wi, wo) = directions(theta_h, theta_d, phi_d);
            out.push((wi.z > 0.0 && wo.z > 0.0).then(|| channel.of(brdf.eval(wi, wo))));
        }
    }
    out
}

/// A colour range reaching down to the 5th percentile of the positive values: grazing
/// 1/cos blow-ups can sit decades above the lobe, and a fixed range would leave the lobe black.
pub fn auto_decades(values: &[Option<f64>], vmax: f64) -> f64 {
    let mut pos: Vec<f64> = values.iter().flatten().copied().filter(|v| *v > 0.0 && v.is_finite()).collect();
    if pos.is_empty() || vmax <= 0.0 {
        return 1.0;
    }
    pos.sort_by(f64::total_cmp);
    let p5 = pos[pos.len() / 20];
    // Whole half-decades, so the colour bar's ticks stay put under small parameter changes.
    ((vmax / p5).log10() * 2.0).ceil().clamp(2.0, 16.0) / 2.0
}

/// The slice of the first model in `series` (a slice has room for one model); `decades` of
/// colour range below the maximum, or automatic.
pub fn figure(series: &[Series], phi_d_deg: f64, decades: Option<f64>, channel: Channel) -> Figure {
    let s = &series[0];
    let values = grid(s.brdf.as_ref(), phi_d_deg, channel);
    let vmax = values.iter().flatten().copied().filter(|v| v.is_finite()).fold(0.0, f64::max);
    let lmax = if vmax > 0.0 { vmax.log10() } else { 0.0 };
    let decades = decades.unwrap_or_else(|| auto_decades(&values, vmax));
    let lmin = lmax - decades;
    let mut rgba = Vec::with_capacity(values.len() * 4);
    for v in &values {
        let c = match v {
            None => BELOW,
            Some(v) if *v > 0.0 && v.is_finite() => magma((v.log10() - lmin) / decades),
            Some(_) => magma(0.0),
        };
        rgba.extend_from_slice(&[c[0], c[1], c[2], 255]);
    }

    let (x0, y0, side) = (80.0, 80.0, 420.0);
    let (x1, y1) = (x0 + side, y0 + side);
    let mut svg = Svg::new(720.0, 580.0);
    svg.text(
        20.0,
        28.0,
        &format!("θh × θd slice of {}, φd = {}°", s.label, super::svg::fmt_tick(phi_d_deg)),
        18.0,
        Anchor::Start,
    );
    svg.text(
        20.0,
        50.0,
        &format!(
            "colour: log10 ρ ({}, 1/sr) over {} decades below the maximum {vmax:.4}",
            channel.label(),
            super::svg::fmt_tick(decades)
        ),
        13.0,
        Anchor::Start,
    );
    svg.raw(IMAGE_SLOT);
    svg.rect(x0, y0, side, side, r##"fill="none" stroke="#444444" stroke-width="1""##);
    for k in 0..=6 {
        let deg = f64::from(k) * 15.0;
        let x = x0 + side * deg / 90.0;
        let y = y1 - side * deg / 90.0;
        svg.line((x, y1), (x, y1 + 5.0), "#444444", 1.0, None);
        svg.text(x, y1 + 18.0, &format!("{deg}°"), 11.0, Anchor::Middle);
        svg.line((x0 - 5.0, y), (x0, y), "#444444", 1.0, None);
        svg.text(x0 - 8.0, y + 4.0, &format!("{deg}°"), 11.0, Anchor::End);
    }
    svg.text((x0 + x1) / 2.0, y1 + 40.0, "θh: angle between the half vector and the normal", 13.0, Anchor::Middle);
    let mid = (y0 + y1) / 2.0;
    svg.text_markup(
        24.0,
        mid,
        &esc("θd: angle between wi and the half vector"),
        13.0,
        Anchor::Middle,
        &format!(r#"transform="rotate(-90 24 {mid:.1})""#),
    );

    // Colour bar with a tick at each whole decade.
    let (bx, bw) = (x1 + 40.0, 22.0);
    let mut stops = String::new();
    for (k, c) in MAGMA.iter().enumerate() {
        let _ = write!(
            stops,
            r##"<stop offset="{:.4}" stop-color="#{:02x}{:02x}{:02x}"/>"##,
            k as f64 / (MAGMA.len() - 1) as f64,
            c[0],
            c[1],
            c[2]
        );
    }
    svg.def(&format!(r#"<linearGradient id="magma" x1="0" y1="1" x2="0" y2="0">{stops}</linearGradient>"#));
    svg.rect(bx, y0, bw, side, r##"fill="url(#magma)" stroke="#444444" stroke-width="1""##);
    for e in (lmin.ceil() as i64)..=(lmax.floor() as i64) {
        let y = y1 - side * (e as f64 - lmin) / decades;
        svg.line((bx + bw, y), (bx + bw + 5.0, y), "#444444", 1.0, None);
        svg.text_markup(
            bx + bw + 8.0,
            y + 4.0,
            &format!(r#"10<tspan dy="-5" font-size="9">{e}</tspan>"#),
            11.0,
            Anchor::Start,
            "",
        );
    }
    svg.text(bx + bw / 2.0, y0 - 10.0, "ρ (1/sr)", 11.0, Anchor::Middle);
    svg.rect(bx, y1 + 30.0, 14.0, 14.0, r##"fill="#9a9a9a" stroke="#444444" stroke-width="1""##);
    svg.text(bx + 20.0, y1 + 41.0, "wi or wo below", 11.0, Anchor::Start);
    svg.text(bx + 20.0, y1 + 55.0, "the horizon", 11.0, Anchor::Start);

    let image = Image { width: CELLS as u32, height: CELLS as u32, rgba, at: (x0, y0, side, side) };
    Figure { svg: svg.finish(), image: Some(image) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_and_difference_angles_round_trip() {
        for &(th, td, pd) in &[(0.3f32, 0.7f32, 1.2f32), (1.2, 0.2, 0.0), (0.0, 1.0, 2.5)] {
            let (wi, wo) = directions(th, td, pd);
            let h = (wi + wo).normalize();
            assert!((h.z.acos() - th).abs() < 1e-4, "θh");
            assert!((wi.dot(h).clamp(-1.0, 1.0).acos() - td).abs() < 1e-4, "θd");
            assert!(h.y.abs() < 1e-6, "φh = 0");
        }
        assert_eq!(magma(0.0), [0, 0, 4]);
        assert_eq!(magma(1.0), [252, 253, 191]);
        assert_eq!(magma(f64::NAN), [0, 0, 4]);
    }

    #[test]
    fn lambert_slice_is_flat_where_defined() {
        let l = brdf::build("lambert", &[("albedo", "1")]).unwrap();
        let g = grid(l.as_ref(), 90.0, Channel::Luminance);
        // At φd = 90°, wi.z = wo.z = cos θd cos θh > 0: every cell is defined and ρ = 1/π.
        assert!(g.iter().all(|v| v.is_some_and(|v| (v - std::f64::consts::FRAC_1_PI).abs() < 1e-6)));
        let g0 = grid(l.as_ref(), 0.0, Channel::Luminance);
        // At φd = 0, wi.z = cos(θh + θd) and wo.z = cos(θh − θd): the triangle θh + θd > 90° is masked.
        let masked = g0.iter().filter(|v| v.is_none()).count();
        assert!((masked as f64 / g0.len() as f64 - 0.5).abs() < 0.01, "{masked}");
    }
}
