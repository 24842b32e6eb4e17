//! Directional albedo a(wo) = ∫ ρ(wi, wo) cos θi dωi against the viewing angle θo (φo = 0),
//! estimated by `brdf::check::albedo` from the model's own sampler, with a ±2 standard-error band.
//!
//! With `--over wo` the other integral, ∫ ρ(wi, wo) cos θo dωo against θi: the fraction of the
//! light arriving from wi that is reflected. The two agree for reciprocal models; for the
//! lecture's raw Phong (ρ ∝ 1/cos θi) only the second shows the energy gain at grazing incidence.

use super::svg::{nice_ceil, series_style, Anchor, Svg};
use super::{Figure, Series};
use crate::cli::Channel;
use brdf::check::{albedo_integral, Integral};
use brdf::Brdf;
use radiometry::{Rgb, Vec3};

/// Viewing angles (degrees) of the albedo curve: every 2.5° and close to grazing.
pub fn thetas() -> Vec<f64> {
    let mut t: Vec<f64> = (0..36).map(|k| k as f64 * 2.5).collect();
    t.extend([89.0, 89.9]);
    t
}

/// One albedo point: θo in degrees, the estimate, and a bound on its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Viewing angle θo, degrees.
    pub theta: f64,
    /// Estimated albedo.
    pub mean: f64,
    /// Standard error of the estimate (for luminance, the weighted sum of channel errors, an upper bound).
    pub se: f64,
}

/// Which direction an albedo integrates over.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Over {
    /// a(wo) = ∫ ρ cos θi dωi, against θo (what `check` bounds).
    Wi,
    /// ∫ ρ cos θo dωo, against θi: the reflected fraction of light from wi.
    Wo,
}

/// The albedo curve of one model.
pub fn curve(brdf: &dyn Brdf, samples: usize, seed: u64, channel: Channel, over: Over) -> Vec<Point> {
    curve_at(brdf, &thetas(), samples, seed, channel, over)
}

/// The albedo curve at the angles `thetas` (degrees).
pub fn curve_at(
    brdf: &dyn Brdf,
    thetas: &[f64],
    samples: usize,
    seed: u64,
    channel: Channel,
    over: Over,
) -> Vec<Point> {
    let which = match over {
        Over::Wi => Integral::OverIncident,
        Over::Wo => Integral::OverOutgoing,
    };
    let rgb = |c: [f64; 3]| Rgb(c.map(|v| v as f32));
    thetas
        .iter()
        .enumerate()
        .map(|(k, &theta)| {
            let t = theta.to_radians();
            let wo = Vec3::new(t.sin() as f32, 0.0, t.cos() as f32);
            let (mean, se) = albedo_integral(brdf, which, wo, samples, seed.wrapping_add(k as u64));
            Point { theta, mean: channel.of(rgb(mean)), se: channel.of(rgb(se)) }
        })
        .collect()
}

/// Draws the albedo curves of `series` on one plot.
pub fn figure(series: &[Series], samples: usize, seed: u64, channel: Channel, over: Over) -> Figure {
    let curves: Vec<Vec<Point>> = series.iter().map(|s| curve(s.brdf.as_ref(), samples, seed, channel, over)).collect();
    let top = curves.iter().flatten().map(|p| p.mean + 2.0 * p.se).filter(|v| v.is_finite()).fold(1.05, f64::max);
    let ymax = nice_ceil(top);

    let (x0, x1, y0, y1) = (80.0, 680.0, 70.0, 450.0);
    let legend_w = series.iter().map(|s| s.label.chars().count()).max().unwrap_or(0) as f64 * 7.0 + 46.0;
    let mut svg = Svg::new((x1 + 30.0 + legend_w + 20.0).max(900.0), 510.0);
    let px = |theta: f64| x0 + (x1 - x0) * theta / 90.0;
    let py = |v: f64| y1 - (y1 - y0) * v / ymax;

    let (title, how, axis) = match over {
        Over::Wi => ("∫ ρ(wi, wo) cos θi dωi against θo (φo = 0", "of each model's sampler", "viewing angle θo"),
        Over::Wo => ("∫ ρ(wi, wo) cos θo dωo against θi (φi = 0", "of each model's sampler", "incident angle θi"),
    };
    svg.text(20.0, 30.0, &format!("Directional albedo {title}, {})", channel.label()), 18.0, Anchor::Start);
    svg.text(20.0, 52.0, &format!("{samples} samples {how} per point; band: ±2 standard errors"), 13.0, Anchor::Start);
    svg.angle_axes((x0, x1, y0, y1), ymax, axis, "albedo");
    svg.line((x0, py(1.0)), (x1, py(1.0)), "#888888", 1.2, Some("6 4"));
    svg.text(x1 - 6.0, py(1.0) - 6.0, "1: energy bound", 11.0, Anchor::End);

    let mut legend = Vec::new();
    for (i, (s, pts)) in series.iter().zip(&curves).enumerate() {
        let (colour, dash) = series_style(i);
        let upper = pts.iter().map(|p| (px(p.theta), py(p.mean + 2.0 * p.se)));
        let lower = pts.iter().rev().map(|p| (px(p.theta), py((p.mean - 2.0 * p.se).max(0.0))));
        svg.polygon(&upper.chain(lower).collect::<Vec<_>>(), colour, 0.18);
        svg.polyline(&pts.iter().map(|p| (px(p.theta), py(p.mean))).collect::<Vec<_>>(), colour, 2.0, dash);
        legend.push((s.label.clone(), colour, dash));
    }
    svg.legend(x1 + 30.0, y0, &legend);
    Figure { svg: svg.finish(), image: None }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_albedo_is_its_parameter_at_every_angle() {
        // Cosine sampling makes every weight exactly the albedo: mean 0.5, standard error 0.
        let l = brdf::build("lambert", &[("albedo", "0.5")]).unwrap();
        for p in curve(l.as_ref(), 256, 1, Channel::Luminance, Over::Wi) {
            assert!((p.mean - 0.5).abs() < 1e-6 && p.se < 1e-6, "{p:?}");
        }
        // Swapped, the weights are ρ·π = 0.5 as well.
        for p in curve(l.as_ref(), 256, 1, Channel::Luminance, Over::Wo) {
            assert!((p.mean - 0.5).abs() < 1e-6 && p.se < 1e-6, "{p:?}");
        }
    }
}
