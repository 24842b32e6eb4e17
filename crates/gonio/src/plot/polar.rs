//! The in-plane polar lobe: for light arriving at θi in the xz-plane, the reflected quantity
//! for every viewing direction wo in the plane of incidence, θo from −90° (the light's side)
//! to +90° (the mirror side), drawn as a radius.

use super::svg::{esc, fmt_tick, nice_ceil, nice_ticks, series_style, Anchor, Svg};
use super::{Figure, Series};
use crate::cli::{Channel, Quantity};
use brdf::Brdf;
use radiometry::{Vec2, Vec3};

/// Viewing-angle step of the curves, in degrees.
const STEP_DEG: f64 = 0.25;

/// Direction towards the light at polar angle θi (degrees), on the −x side of the plane of incidence.
pub fn incident(theta_i_deg: f64) -> Vec3 {
    let t = theta_i_deg.to_radians();
    Vec3::new(-t.sin() as f32, 0.0, t.cos() as f32)
}

/// `v` turned by `deg` degrees about the normal.
pub fn rotate_z(v: Vec3, deg: f64) -> Vec3 {
    let (s, c) = deg.to_radians().sin_cos();
    let (s, c) = (s as f32, c as f32);
    Vec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}

/// [`incident`] with the plane of incidence turned by φi (degrees) about the normal.
pub fn incident_at(theta_i_deg: f64, phi_i_deg: f64) -> Vec3 {
    rotate_z(incident(theta_i_deg), phi_i_deg)
}

/// Viewing direction at signed angle θo (degrees) in the plane of incidence; θo > 0 on the mirror side.
pub fn outgoing(theta_o_deg: f64) -> Vec3 {
    let t = theta_o_deg.to_radians();
    Vec3::new(t.sin() as f32, 0.0, t.cos() as f32)
}

/// The plotted quantity at (wi, wo): ρ or ρ·cos θo, non-negative, NaN where not finite.
pub fn lobe_value(brdf: &dyn Brdf, wi: Vec3, wo: Vec3, quantity: Quantity, channel: Channel) -> f64 {
    let rho = channel.of(brdf.eval(wi, wo));
    let v = match quantity {
        Quantity::Brdf => rho,
        Quantity::Intensity => rho * f64::from(wo.z.max(0.0)),
    };
    // A negative value is a model bug that `check` reports; the plot shows the non-negative part.
    if v.is_finite() {
        v.max(0.0)
    } else {
        f64::NAN
    }
}

/// The lobe as (θo in degrees, value) pairs.
pub fn lobe(
    brdf: &dyn Brdf,
    theta_i_deg: f64,
    phi_i_deg: f64,
    quantity: Quantity,
    channel: Channel,
) -> Vec<(f64, f64)> {
    let wi = incident_at(theta_i_deg, phi_i_deg);
    let n = (180.0 / STEP_DEG).round() as usize;
    (0..=n)
        .map(|k| {
            let t = -90.0 + k as f64 * STEP_DEG;
            (t, lobe_value(brdf, wi, rotate_z(outgoing(t), phi_i_deg), quantity, channel))
        })
        .collect()
}

/// The reflectance of a model's delta lobe towards the mirror direction of `wi`, if it has one.
fn delta_reflectance(brdf: &dyn Brdf, wi: Vec3, channel: Channel) -> Option<f64> {
    if !brdf.has_delta() {
        return None;
    }
    let wo = Vec3::new(-wi.x, -wi.y, wi.z);
    // The lobe choice depends on `uc` only; scan it to find the delta lobe.
    (0..64).find_map(|k| {
        let s = brdf.sample(wo, (k as f32 + 0.5) / 64.0, Vec2::new(0.5, 0.5))?;
        // weight = ρ·cos/pdf, and for a delta lobe pdf is the lobe's choice probability.
        s.delta.then(|| channel.of(s.weight) * f64::from(s.pdf))
    })
}

fn peak(lobe: &[(f64, f64)]) -> f64 {
    lobe.iter().map(|&(_, v)| v).filter(|v| v.is_finite()).fold(0.0, f64::max)
}

/// Draws the lobes of `series` on one polar plot; `normalize` scales each to its own peak.
pub fn figure(
    series: &[Series],
    (theta_i_deg, phi_i_deg): (f64, f64),
    quantity: Quantity,
    channel: Channel,
    normalize: bool,
) -> Figure {
    let mut lobes: Vec<Vec<(f64, f64)>> =
        series.iter().map(|s| lobe(s.brdf.as_ref(), theta_i_deg, phi_i_deg, quantity, channel)).collect();
    let peaks: Vec<f64> = lobes.iter().map(|l| peak(l)).collect();
    if normalize {
        for (l, &p) in lobes.iter_mut().zip(&peaks) {
            if p > 0.0 {
                l.iter_mut().for_each(|(_, v)| *v /= p);
            }
        }
    }
    let rmax = if normalize { 1.0 } else { nice_ceil(peaks.iter().copied().fold(0.0, f64::max)) };

    let (cx, cy, r) = (400.0, 440.0, 350.0);
    let legend_x = cx + r + 50.0;
    let wi = incident_at(theta_i_deg, phi_i_deg);
    let deltas: Vec<Option<f64>> = series.iter().map(|s| delta_reflectance(s.brdf.as_ref(), wi, channel)).collect();
    let labels: Vec<String> = series
        .iter()
        .zip(&peaks)
        .zip(&deltas)
        .map(|((s, &p), d)| match (p > 0.0, d) {
            (_, None) => format!("{}, peak {}", s.label, sig(p)),
            (true, Some(_)) => format!("{}, peak {} + δ lobe", s.label, sig(p)),
            (false, Some(_)) => format!("{}, δ lobe", s.label),
        })
        .collect();
    let legend_w = labels.iter().map(|l| l.chars().count() + 4).max().unwrap_or(0) as f64 * 7.0 + 46.0;
    let mut svg = Svg::new((legend_x + legend_w + 20.0).max(980.0), 520.0);
    svg.def(r##"<marker id="arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="9" markerHeight="9" orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="#444444"/></marker>"##);
    let at = |theta_deg: f64, radius_px: f64| {
        let t = theta_deg.to_radians();
        (cx + radius_px * t.sin(), cy - radius_px * t.cos())
    };

    let what = match quantity {
        Quantity::Intensity => "ρ·cos θo",
        Quantity::Brdf => "ρ",
    };
    let scale = if normalize { ", each lobe scaled to its peak" } else { "" };
    svg.text(
        20.0,
        30.0,
        &format!("In-plane lobe, θi = {}°: radius = {what} ({}, 1/sr){scale}", fmt_tick(theta_i_deg), channel.label()),
        18.0,
        Anchor::Start,
    );
    svg.text(
        20.0,
        52.0,
        "wo in the plane of incidence; θo < 0 on the light's side, θo > 0 on the mirror side",
        13.0,
        Anchor::Start,
    );

    // Grid: arcs at round radii, spokes every 30°.
    let mut ticks: Vec<f64> = nice_ticks(0.0, rmax, 4).into_iter().filter(|&t| t > 0.0).collect();
    // The rim is always a labelled arc, even where rmax is not a tick.
    if ticks.last().is_none_or(|&t| t < rmax * 0.999) {
        ticks.push(rmax);
    }
    for &t in &ticks {
        let rp = r * t / rmax;
        svg.raw(&format!(
            r##"<path d="M{:.2},{cy:.2} A{rp:.2},{rp:.2} 0 0 1 {:.2},{cy:.2}" fill="none" stroke="#dddddd" stroke-width="1"/>"##,
            cx - rp,
            cx + rp
        ));
        svg.text(cx + rp, cy + 18.0, &fmt_tick(t), 11.0, Anchor::Middle);
        svg.text(cx - rp, cy + 18.0, &fmt_tick(t), 11.0, Anchor::Middle);
    }
    for k in -3i32..=3 {
        let deg = f64::from(k) * 30.0;
        svg.line((cx, cy), at(deg, r), "#e6e6e6", 1.0, None);
        let (lx, ly) = at(deg, r + 16.0);
        // ±90° lie on the surface line: lift their labels above it.
        let ly = if k.abs() == 3 { ly - 8.0 } else { ly };
        svg.text(lx, ly + 4.0, &format!("{}°", fmt_tick(deg)).replace('-', "−"), 11.0, Anchor::Middle);
    }
    svg.line((cx - r - 10.0, cy), (cx + r + 10.0, cy), "#444444", 1.5, None);
    svg.text(cx + r + 10.0, cy + 34.0, "surface", 11.0, Anchor::End);
    svg.text(cx, cy + 34.0, "0", 11.0, Anchor::Middle);

    // Incident direction: an arrow from the light's side to the point of incidence.
    let tip = at(-theta_i_deg, r);
    svg.raw(&format!(
        r##"<line x1="{:.2}" y1="{:.2}" x2="{cx:.2}" y2="{cy:.2}" stroke="#444444" stroke-width="1.5" marker-end="url(#arrow)"/>"##,
        tip.0, tip.1
    ));
    svg.text(tip.0 - 6.0, tip.1 - 8.0, &format!("light, θi = {}°", fmt_tick(theta_i_deg)), 12.0, Anchor::End);
    let mirror = at(theta_i_deg, r);
    svg.line((cx, cy), mirror, "#999999", 1.0, Some("2 4"));
    svg.text(mirror.0 + 6.0, mirror.1 - 6.0, "mirror", 11.0, Anchor::Start);

    let mut legend = Vec::new();
    for (i, pts) in lobes.iter().enumerate() {
        let (colour, dash) = series_style(i);
        let xy: Vec<(f64, f64)> = pts.iter().map(|&(t, v)| at(t, r * v / rmax)).collect();
        svg.polyline(&xy, colour, 2.0, dash);
        if let Some(refl) = deltas[i] {
            // A delta lobe has no finite ρ: a spike to the rim, not to scale, with its reflectance.
            let tip = at(theta_i_deg, r * (1.0 - 0.04 * i as f64));
            svg.line((cx, cy), tip, colour, 3.0, Some("6 3"));
            svg.text(tip.0 + 6.0, tip.1 + 12.0, &format!("δ lobe, reflectance {refl:.3}"), 11.0, Anchor::Start);
        }
        legend.push((labels[i].clone(), colour, dash));
    }
    svg.legend(legend_x, 80.0, &legend);
    svg.text_markup(
        20.0,
        508.0,
        &esc("radius scale linear; δ lobes drawn as dashed spikes to the rim (not to scale)"),
        11.0,
        Anchor::Start,
        r#"fill-opacity="0.7""#,
    );
    Figure { svg: svg.finish(), image: None }
}

/// Four significant digits, for legends.
fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.digits$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_lobe_is_a_circle_through_the_origin() {
        // ρ cos θo with constant ρ = 1/π: in the plot's Cartesian frame r = cos θo / π is a circle.
        let l = brdf::build("lambert", &[("albedo", "1")]).unwrap();
        let pts = lobe(l.as_ref(), 45.0, 0.0, Quantity::Intensity, Channel::Luminance);
        assert_eq!(pts.len(), 721);
        for (t, v) in pts {
            let expect = t.to_radians().cos().max(0.0) / std::f64::consts::PI;
            assert!((v - expect).abs() < 1e-6, "θo {t}: {v} vs {expect}");
        }
        let f = figure(
            &[Series { label: "lambert".into(), brdf: l }],
            (45.0, 0.0),
            Quantity::Intensity,
            Channel::Luminance,
            false,
        );
        assert!(f.svg.contains("lambert, peak 0.3183"), "the legend gives the peak 1/π");
        assert!(f.svg.starts_with("<svg") && f.svg.contains("<path d=\"M"));
    }

    /// Width of the part of a lobe above half its peak, in degrees.
    fn width_at_half_peak(pts: &[(f64, f64)]) -> f64 {
        let p = peak(pts);
        pts.iter().filter(|&&(_, v)| v >= 0.5 * p).count() as f64 * STEP_DEG
    }

    #[test]
    fn phong_lobe_sits_at_the_mirror_and_narrows_as_ke_grows() {
        // In the plane of incidence R·V = cos(θo − θi), so the raw Phong lobe is
        // ρ cos θo = ks cos^ke(θo − θi) cos θo / cos θi (zero once the cosine turns negative).
        let mut widths = Vec::new();
        for ke in [5.0f64, 20.0, 100.0] {
            let m = brdf::build("phong", &[("ks", "0.5"), ("ke", &ke.to_string())]).unwrap();
            let pts = lobe(m.as_ref(), 30.0, 0.0, Quantity::Intensity, Channel::Luminance);
            for &(t, v) in &pts {
                let c = (t - 30.0).to_radians().cos().max(0.0);
                let expect = 0.5 * c.powf(ke) * t.to_radians().cos().max(0.0) / 30f64.to_radians().cos();
                assert!((v - expect).abs() < 1e-4 * (1.0 + expect), "ke {ke}, θo {t}: {v} vs {expect}");
            }
            widths.push(width_at_half_peak(&pts));
        }
        assert!(widths[0] > widths[1] && widths[1] > widths[2], "{widths:?}");
    }
}
