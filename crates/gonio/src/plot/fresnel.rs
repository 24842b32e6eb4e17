//! Fresnel reflectance of a model's specular interface against the incident angle θi: the
//! exact s- and p-polarised reflectances Rs and Rp (Born & Wolf, Principles of Optics, §1.5
//! and §14.2 for conductors), unpolarised light's (Rs + Rp)/2, and Schlick's approximation
//! R0 + (1 − R0)(1 − cos θi)⁵ with R0 from the same η and k (Schlick 1994). A model whose
//! term is Schlick's shows that curve alone; one with F = 1 a line at 1.

use super::svg::{series_style, Anchor, Svg};
use super::{Figure, Series};
use crate::cli::Channel;
use brdf::fresnel::{self, Fresnel, Polarized};
use radiometry::Rgb;

/// Incident-angle step of the curves, in degrees.
const STEP_DEG: f64 = 0.25;

/// One curve of the plot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Curve {
    /// s-polarised (perpendicular) reflectance.
    Rs,
    /// p-polarised (parallel) reflectance.
    Rp,
    /// Unpolarised: (Rs + Rp)/2, the exact term.
    Unpolarised,
    /// Schlick's approximation.
    Schlick,
}

impl Curve {
    /// Its name in legends.
    pub fn label(self) -> &'static str {
        match self {
            Curve::Rs => "Rs",
            Curve::Rp => "Rp",
            Curve::Unpolarised => "unpolarised",
            Curve::Schlick => "Schlick",
        }
    }

    fn dash(self) -> Option<&'static str> {
        match self {
            Curve::Rs => Some("7 4"),
            Curve::Rp => Some("2 3"),
            Curve::Unpolarised => None,
            Curve::Schlick => Some("10 3 2 3"),
        }
    }
}

/// The curves a Fresnel term has: all four for an exact term, Schlick's alone for Schlick's.
pub fn curves_of(f: &Fresnel) -> &'static [Curve] {
    match f {
        Fresnel::Dielectric { .. } | Fresnel::Conductor { .. } => {
            &[Curve::Unpolarised, Curve::Rs, Curve::Rp, Curve::Schlick]
        }
        Fresnel::Schlick { .. } => &[Curve::Schlick],
        Fresnel::None => &[Curve::Unpolarised],
    }
}

/// Curve `c` of term `f` at incidence cosine `cos`, reduced to one number by `channel`.
pub fn value(f: &Fresnel, c: Curve, cos: f32, channel: Channel) -> f64 {
    let per_channel = |g: &dyn Fn(f32, f32) -> Polarized, eta: Rgb, k: Rgb| -> Rgb {
        eta.zip(k, |e, k| match c {
            Curve::Rs => g(e, k).s,
            Curve::Rp => g(e, k).p,
            Curve::Unpolarised => g(e, k).mean(),
            Curve::Schlick => fresnel::schlick(cos, fresnel::normal_reflectance(e, k)),
        })
    };
    let rgb = match *f {
        Fresnel::None => Rgb::ONE,
        Fresnel::Schlick { r0 } => r0.map(|r| fresnel::schlick(cos, r)),
        Fresnel::Dielectric { eta } => {
            per_channel(&|e, _| fresnel::dielectric_polarized(cos, e), Rgb::splat(eta), Rgb::ZERO)
        }
        Fresnel::Conductor { eta, k } => per_channel(&|e, k| fresnel::conductor_polarized(cos, e, k), eta, k),
    };
    channel.of(rgb)
}

/// Draws the Fresnel curves of `series`; each must have a Fresnel term.
pub fn figure(series: &[(Series, Fresnel)], channel: Channel) -> Figure {
    let (x0, x1, y0, y1) = (80.0, 680.0, 70.0, 450.0);
    let rows: Vec<String> = series
        .iter()
        .flat_map(|(s, f)| curves_of(f).iter().map(move |c| format!("{}: {}", s.label, c.label())))
        .collect();
    let legend_w = rows.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f64 * 7.0 + 46.0;
    let mut svg = Svg::new((x1 + 30.0 + legend_w + 20.0).max(900.0), 510.0);
    let px = |theta: f64| x0 + (x1 - x0) * theta / 90.0;
    let py = |v: f64| y1 - (y1 - y0) * v;

    svg.text(
        20.0,
        30.0,
        &format!("Fresnel reflectance against the incident angle θi, {}", channel.label()),
        18.0,
        Anchor::Start,
    );
    svg.text(
        20.0,
        52.0,
        "exact Rs, Rp and unpolarised (Rs + Rp)/2; Schlick's R0 + (1 − R0)(1 − cos θi)⁵ with the same R0",
        13.0,
        Anchor::Start,
    );
    svg.angle_axes((x0, x1, y0, y1), 1.0, "incident angle θi", "reflectance");

    let n = (90.0 / STEP_DEG).round() as usize;
    let mut legend = Vec::new();
    for (i, (s, f)) in series.iter().enumerate() {
        let (colour, _) = series_style(i);
        for &c in curves_of(f) {
            let pts: Vec<(f64, f64)> = (0..=n)
                .map(|k| {
                    let t = k as f64 * STEP_DEG;
                    (px(t), py(value(f, c, t.to_radians().cos() as f32, channel).clamp(0.0, 1.0)))
                })
                .collect();
            svg.polyline(&pts, colour, if c == Curve::Unpolarised { 2.2 } else { 1.6 }, c.dash());
            legend.push((format!("{}: {}", s.label, c.label()), colour, c.dash()));
        }
    }
    svg.legend(x1 + 30.0, y0, &legend);
    Figure { svg: svg.finish(), image: None }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(f: &Fresnel, c: Curve, theta_deg: f64) -> f64 {
        value(f, c, theta_deg.to_radians().cos() as f32, Channel::R)
    }

    #[test]
    fn glass_has_its_normal_reflectance_brewster_angle_and_grazing_limit() {
        let glass = Fresnel::Dielectric { eta: 1.5 };
        // Normal incidence: Rs = Rp = Schlick = ((η−1)/(η+1))² = 0.04.
        for c in [Curve::Rs, Curve::Rp, Curve::Unpolarised, Curve::Schlick] {
            assert!((at(&glass, c, 0.0) - 0.04).abs() < 1e-6, "{c:?}");
        }
        // Rp vanishes at Brewster's angle atan η; Rs does not.
        let brewster = 1.5f64.atan().to_degrees();
        assert!(at(&glass, Curve::Rp, brewster) < 1e-6 && at(&glass, Curve::Rs, brewster) > 0.1);
        // The unpolarised curve is the exact term the models use.
        for t in [10.0f64, 45.0, 70.0, 85.0] {
            let exact = f64::from(glass.eval(t.to_radians().cos() as f32).0[0]);
            assert!((at(&glass, Curve::Unpolarised, t) - exact).abs() < 1e-6);
        }
        // Everything reaches 1 at grazing incidence.
        for c in [Curve::Rs, Curve::Rp, Curve::Schlick] {
            assert!(at(&glass, c, 90.0) > 0.999, "{c:?}");
        }
    }

    #[test]
    fn a_conductor_is_per_channel_and_schlick_shares_its_normal_reflectance() {
        let au = fresnel::AU;
        let gold = Fresnel::Conductor { eta: au.eta, k: au.k };
        for (ch, c) in [(Channel::R, 0), (Channel::G, 1), (Channel::B, 2)] {
            let r0 = f64::from(fresnel::normal_reflectance(au.eta.0[c], au.k.0[c]));
            assert!((value(&gold, Curve::Unpolarised, 1.0, ch) - r0).abs() < 1e-5);
            assert!((value(&gold, Curve::Schlick, 1.0, ch) - r0).abs() < 1e-6);
        }
        // Gold reflects red more than blue; its Rp dips below Rs near grazing incidence.
        assert!(at(&gold, Curve::Unpolarised, 0.0) > value(&gold, Curve::Unpolarised, 1.0, Channel::B));
        assert!(at(&gold, Curve::Rp, 80.0) < at(&gold, Curve::Rs, 80.0));
        assert_eq!(curves_of(&Fresnel::Schlick { r0: Rgb::splat(0.04) }), &[Curve::Schlick]);
        assert_eq!(at(&Fresnel::None, Curve::Unpolarised, 30.0), 1.0);
    }
}
