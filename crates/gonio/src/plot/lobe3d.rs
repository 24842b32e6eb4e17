//! The 3D lobe: for light arriving from wi (θi in the xz-plane, on the −x side, as in the
//! polar plot), the surface r(wo)·wo over the hemisphere of viewing directions, r the reflected
//! quantity (ρ or ρ·cos θo), seen in perspective-free oblique projection and drawn back to
//! front with flat shading. Delta lobes have no extent and are not drawn.

use super::polar::{incident_at, lobe_value};
use super::svg::{series_style, Anchor, Svg};
use super::{Figure, Series};
use crate::cli::{Channel, Quantity};
use radiometry::Vec3;

/// Polar steps of the grid over θo in [0°, 90°].
const THETA_STEPS: usize = 45;
/// Azimuth steps of the grid over φo in [0°, 360°).
const PHI_STEPS: usize = 72;
/// The view: azimuth and elevation of the viewer, degrees.
const VIEW: (f64, f64) = (-65.0, 28.0);

/// The lobe's vertices r(wo)·wo on the (θo, φo) grid, row by row from the pole.
pub fn surface(
    brdf: &dyn brdf::Brdf,
    (theta_i_deg, phi_i_deg): (f64, f64),
    quantity: Quantity,
    channel: Channel,
) -> Vec<Vec3> {
    let wi = incident_at(theta_i_deg, phi_i_deg);
    let mut out = Vec::with_capacity((THETA_STEPS + 1) * PHI_STEPS);
    for i in 0..=THETA_STEPS {
        let t = (i as f64 * 90.0 / THETA_STEPS as f64).to_radians();
        for j in 0..PHI_STEPS {
            let p = (j as f64 * 360.0 / PHI_STEPS as f64).to_radians();
            let wo = Vec3::new((t.sin() * p.cos()) as f32, (t.sin() * p.sin()) as f32, t.cos() as f32);
            let r = lobe_value(brdf, wi, wo, quantity, channel);
            out.push(wo * if r.is_finite() { r as f32 } else { 0.0 });
        }
    }
    out
}

/// One quadrilateral of a lobe, projected: its depth towards the viewer, corners and fill.
struct Facet {
    depth: f32,
    corners: [(f64, f64); 4],
    fill: String,
}

/// A colour `#rrggbb` scaled by `shade`.
fn shaded(hex: &str, shade: f64) -> String {
    let c = |k: usize| u8::from_str_radix(&hex[1 + 2 * k..3 + 2 * k], 16).unwrap_or(0);
    let s = |v: u8| ((f64::from(v) * shade).round().clamp(0.0, 255.0)) as u8;
    format!("#{:02x}{:02x}{:02x}", s(c(0)), s(c(1)), s(c(2)))
}

/// Draws the 3D lobes of `series`; `normalize` scales each to its own peak.
pub fn figure(
    series: &[Series],
    (theta_i_deg, phi_i_deg): (f64, f64),
    quantity: Quantity,
    channel: Channel,
    normalize: bool,
) -> Figure {
    let mut surfaces: Vec<Vec<Vec3>> =
        series.iter().map(|s| surface(s.brdf.as_ref(), (theta_i_deg, phi_i_deg), quantity, channel)).collect();
    let peaks: Vec<f32> = surfaces.iter().map(|v| v.iter().map(|p| p.length()).fold(0.0, f32::max)).collect();
    if normalize {
        for (v, &m) in surfaces.iter_mut().zip(&peaks) {
            if m > 0.0 {
                v.iter_mut().for_each(|p| *p /= m);
            }
        }
    }
    let rmax = if normalize { 1.0 } else { peaks.iter().copied().fold(0.0, f32::max) };
    let scale = if rmax > 0.0 { 300.0 / f64::from(rmax) } else { 1.0 };

    let (az, el) = (VIEW.0.to_radians(), VIEW.1.to_radians());
    let toward_viewer = Vec3::new((el.cos() * az.cos()) as f32, (el.cos() * az.sin()) as f32, el.sin() as f32);
    let right = Vec3::Z.cross(toward_viewer).normalize();
    let up = toward_viewer.cross(right);
    let light = (toward_viewer + up + right * 0.5).normalize();
    let (cx, cy) = (420.0, 470.0);
    let project = |p: Vec3| (cx + scale * f64::from(p.dot(right)), cy - scale * f64::from(p.dot(up)));

    let legend_w = series.iter().map(|s| s.label.chars().count()).max().unwrap_or(0) as f64 * 7.0 + 46.0;
    let mut svg = Svg::new((880.0 + legend_w).max(1000.0), 640.0);
    let what = match quantity {
        Quantity::Brdf => "ρ (1/sr)",
        Quantity::Intensity => "ρ·cos θo (1/sr)",
    };
    let scale_note = if normalize { "each scaled to its own peak".to_string() } else { format!("peak {rmax:.4}") };
    svg.text(
        20.0,
        30.0,
        &format!("3D lobe of {what} for θi = {theta_i_deg}°, {}", channel.label()),
        18.0,
        Anchor::Start,
    );
    svg.text(
        20.0,
        52.0,
        &format!("radius ∝ {what}, {scale_note}; arrows: light (solid) and mirror direction (dashed)"),
        13.0,
        Anchor::Start,
    );

    // The surface plane: a disk of the peak radius, and the normal.
    let disk: Vec<(f64, f64)> = (0..=96)
        .map(|k| {
            let a = k as f32 / 96.0 * std::f32::consts::TAU;
            project(Vec3::new(a.cos(), a.sin(), 0.0) * rmax)
        })
        .collect();
    svg.polygon(&disk, "#dddddd", 0.6);
    svg.polyline(&disk, "#999999", 1.0, None);
    svg.line(project(Vec3::ZERO), project(Vec3::Z * rmax * 1.1), "#999999", 1.0, Some("3 3"));

    // Every facet of every lobe, back to front.
    let mut facets = Vec::new();
    for (k, v) in surfaces.iter().enumerate() {
        let (colour, _) = series_style(k);
        let at = |i: usize, j: usize| v[i * PHI_STEPS + j % PHI_STEPS];
        for i in 0..THETA_STEPS {
            for j in 0..PHI_STEPS {
                let q = [at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)];
                let n = (q[2] - q[0]).cross(q[3] - q[1]);
                if n.length_squared() < 1e-20 {
                    continue;
                }
                let shade = 0.35 + 0.65 * f64::from(n.normalize().dot(light).abs());
                let depth = q.iter().map(|p| p.dot(toward_viewer)).sum::<f32>() / 4.0;
                facets.push(Facet { depth, corners: q.map(project), fill: shaded(colour, shade) });
            }
        }
    }
    facets.sort_by(|a, b| a.depth.total_cmp(&b.depth));
    for f in &facets {
        let d: Vec<String> = f.corners.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
        let fill = &f.fill;
        svg.raw(&format!(r#"<polygon points="{}" fill="{fill}" stroke="{fill}" stroke-width="0.4"/>"#, d.join(" ")));
    }

    let wi = incident_at(theta_i_deg, phi_i_deg);
    let reach = rmax * 1.25;
    svg.line(project(Vec3::ZERO), project(wi * reach), "#222222", 2.0, None);
    svg.line(project(Vec3::ZERO), project(Vec3::new(-wi.x, -wi.y, wi.z) * reach), "#222222", 1.5, Some("6 4"));
    let (lx, ly) = project(wi * reach);
    svg.text(lx, ly - 8.0, "wi", 13.0, Anchor::Middle);

    let mut legend = Vec::new();
    for (i, s) in series.iter().enumerate() {
        let (colour, dash) = series_style(i);
        let delta = if s.brdf.has_delta() { " (delta lobe not drawn)" } else { "" };
        legend.push((format!("{}{delta}", s.label), colour, dash));
    }
    svg.legend(860.0, 80.0, &legend);
    Figure { svg: svg.finish(), image: None }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lambert_lobe_in_intensity_is_a_sphere_touching_the_surface() {
        // ρ·cos θo = (a/π) cos θo: r = c cos θo is a sphere of diameter c through the origin.
        let l = brdf::build("lambert", &[("albedo", "1")]).unwrap();
        let c = 1.0 / std::f32::consts::PI;
        for p in surface(l.as_ref(), (30.0, 0.0), Quantity::Intensity, Channel::Luminance) {
            assert!(((p - Vec3::Z * (c / 2.0)).length() - c / 2.0).abs() < 1e-6, "{p}");
        }
    }

    #[test]
    fn a_glossy_lobe_peaks_near_the_mirror_direction() {
        let g = brdf::build("ward", &[("alpha", "0.1"), ("ks", "0.5")]).unwrap();
        let v = surface(g.as_ref(), (40.0, 0.0), Quantity::Brdf, Channel::Luminance);
        let peak = v.iter().copied().max_by(|a, b| a.length().total_cmp(&b.length())).unwrap();
        let mirror = Vec3::new((40f32).to_radians().sin(), 0.0, (40f32).to_radians().cos());
        assert!(peak.normalize().dot(mirror) > (4f32).to_radians().cos(), "peak at {peak}");
    }
}
