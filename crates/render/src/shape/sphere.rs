//! Analytic spheres, normals pointing outwards. Intersection uses the form of Haines et al.,
//! "Precision improvements for ray/sphere intersection" (Ray Tracing Gems, 2019), which
//! keeps f32 accuracy far from the sphere; sampling from outside draws the cone of
//! directions the sphere subtends (uniform in solid angle), from inside its area.

use crate::shape::Aabb;
use glam::{Vec2, Vec3};
use radiometry::warp::{uniform_cone, uniform_sphere};
use radiometry::Frame;
use std::f32::consts::PI;

/// A sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (> 0).
    pub radius: f32,
}

/// A point sampled on a shape as seen from a reference point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSample {
    /// The point.
    pub p: Vec3,
    /// The unit surface normal there.
    pub n: Vec3,
    /// Density in solid angle at the reference point.
    pub pdf: f32,
}

impl Sphere {
    /// The bounding box.
    pub fn bounds(&self) -> Aabb {
        Aabb { min: self.center - Vec3::splat(self.radius), max: self.center + Vec3::splat(self.radius) }
    }

    /// Surface area 4πr².
    pub fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    /// The nearest hit distance in (0, `t_max`) for unit `d`.
    #[inline]
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        let f = o - self.center;
        let b = -f.dot(d);
        // Distance² from the centre to the line, from the perpendicular vector (not b² − |f|²).
        let l = f + b * d;
        let r2 = self.radius * self.radius;
        let disc = r2 - l.length_squared();
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let c = f.length_squared() - r2;
        let q = b + disc.sqrt().copysign(b);
        // Roots c/q and q; q = 0 only when b = 0 and disc = 0 (tangent through the centre's foot).
        let (mut t0, mut t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q) };
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        if t0 > 0.0 && t0 < t_max {
            Some(t0)
        } else if t1 > 0.0 && t1 < t_max {
            Some(t1)
        } else {
            None
        }
    }

    /// The outward unit normal at (or near) `p`.
    #[inline]
    pub fn normal(&self, p: Vec3) -> Vec3 {
        (p - self.center).try_normalize().unwrap_or(Vec3::Z)
    }

    /// `p` moved onto the surface along the normal (removes the rounding of o + t·d).
    #[inline]
    pub fn reproject(&self, p: Vec3) -> Vec3 {
        self.center + self.normal(p) * self.radius
    }

    /// A point on the sphere for reference point `r`: from outside, uniform over the
    /// subtended cone (the visible cap); from inside, uniform over the area.
    pub fn sample(&self, r: Vec3, u: Vec2) -> Option<ShapeSample> {
        let dc = self.center - r;
        let dist2 = dc.length_squared();
        let r2 = self.radius * self.radius;
        if dist2 <= r2 * (1.0 + 1e-4) {
            let n = uniform_sphere(u);
            let p = self.center + n * self.radius;
            let pdf = area_to_solid_angle(1.0 / self.area(), r, p, n)?;
            return Some(ShapeSample { p, n, pdf });
        }
        let dist = dist2.sqrt();
        // cos θmax from sin²θmax = r²/d², computed without cancellation near 1.
        let sin2 = r2 / dist2;
        let cos_max = (1.0 - sin2).max(0.0).sqrt();
        let w = dc / dist;
        let local = uniform_cone(u, cos_max);
        let d = Frame::from_normal(w).to_world(local);
        // Nearest intersection; at the rim, rounding may miss: take the closest approach.
        let t = self.intersect(r, d, f32::INFINITY).unwrap_or_else(|| dc.dot(d));
        let p = self.reproject(r + d * t);
        Some(ShapeSample { p, n: self.normal(p), pdf: cone_pdf(sin2, cos_max) })
    }

    /// Solid-angle density of `sample` from `r` producing the point `p`.
    pub fn pdf(&self, r: Vec3, p: Vec3) -> f32 {
        let dist2 = (self.center - r).length_squared();
        let r2 = self.radius * self.radius;
        if dist2 <= r2 * (1.0 + 1e-4) {
            return area_to_solid_angle(1.0 / self.area(), r, p, self.normal(p)).unwrap_or(0.0);
        }
        let sin2 = r2 / dist2;
        cone_pdf(sin2, (1.0 - sin2).max(0.0).sqrt())
    }
}

/// 1 / (2π(1 − cos θmax)), with 1 − cos θmax = sin² / (1 + cos) to avoid cancellation.
#[inline]
fn cone_pdf(sin2: f32, cos_max: f32) -> f32 {
    let one_minus_cos = sin2 / (1.0 + cos_max);
    1.0 / (2.0 * PI * one_minus_cos).max(f32::MIN_POSITIVE)
}

/// Converts an area density at `p` (normal `n`) to solid angle at `r`: pdf·dist²/|cos|.
/// None when the point is seen exactly edge-on or coincides with `r`.
#[inline]
pub fn area_to_solid_angle(pdf_area: f32, r: Vec3, p: Vec3, n: Vec3) -> Option<f32> {
    let d = p - r;
    let dist2 = d.length_squared();
    let cos = (d.dot(n)).abs() / dist2.sqrt();
    let pdf = pdf_area * dist2 / cos;
    (pdf.is_finite() && pdf > 0.0).then_some(pdf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intersections_from_outside_inside_and_far_away() {
        let s = Sphere { center: Vec3::new(0.0, 0.0, -5.0), radius: 1.0 };
        assert!((s.intersect(Vec3::ZERO, -Vec3::Z, 100.0).unwrap() - 4.0).abs() < 1e-6);
        assert!((s.intersect(Vec3::new(0.0, 0.0, -5.0), -Vec3::Z, 100.0).unwrap() - 1.0).abs() < 1e-6);
        assert!(s.intersect(Vec3::ZERO, Vec3::Z, 100.0).is_none());
        assert!(s.intersect(Vec3::ZERO, -Vec3::Z, 3.9).is_none());
        // 10^4 radii away the naive discriminant loses all digits; this form keeps them.
        let far = Sphere { center: Vec3::new(0.0, 0.0, -1e4), radius: 1.0 };
        let t = far.intersect(Vec3::new(0.5, 0.0, 0.0), -Vec3::Z, f32::INFINITY).unwrap();
        let p = Vec3::new(0.5, 0.0, -t);
        assert!(((p - far.center).length() - 1.0).abs() < 2e-3, "{t}");
    }

    #[test]
    fn cone_samples_hit_the_sphere_and_pdf_integrates_to_one() {
        let s = Sphere { center: Vec3::new(1.0, 2.0, 3.0), radius: 0.5 };
        let r = Vec3::new(0.0, 0.0, -1.0);
        let mut rng = crate::sampler::Sampler::new(1, 2, 3);
        for _ in 0..1000 {
            let smp = s.sample(r, rng.next_2d()).unwrap();
            assert!(((smp.p - s.center).length() - 0.5).abs() < 1e-5);
            assert!((smp.n.dot(r - smp.p)) >= -1e-4, "the sampled point faces the reference");
            assert_eq!(smp.pdf, s.pdf(r, smp.p));
        }
        // pdf × subtended solid angle = 1.
        let sin2 = 0.25 / (s.center - r).length_squared();
        let omega = 2.0 * PI * (1.0 - (1.0 - sin2).sqrt());
        assert!((s.pdf(r, s.center) * omega - 1.0).abs() < 1e-4);
        // From inside: area sampling, pdf = dist²/(A cos).
        let smp = s.sample(s.center, Vec2::new(0.3, 0.4)).unwrap();
        assert!((smp.pdf - 0.25 / s.area()).abs() < 1e-5);
    }
}
