//! Analytic spheres, normals pointing outwards (inwards with `flip_normals`). Intersection
//! uses the form of Haines et al., "Precision improvements for ray/sphere intersection" (Ray
//! Tracing Gems, 2019), which keeps f32 accuracy far from the sphere; sampling from outside
//! draws the cone of directions the sphere subtends (uniform in solid angle), from inside its area.
//!
//! Surface coordinates are Mitsuba 3's: with q the unit point in the sphere's own frame (its
//! `to_world` rotation undone), u = φ/2π (φ = atan2(q_y, q_x) in [0, 2π)), v = θ/π (θ from +z,
//! as atan2(√(q_x² + q_y²), q_z)),
//! ∂p/∂u = 2π R(−q_y, q_x, 0) and ∂p/∂v = π R(q_z cos φ, q_z sin φ, −sin θ), R the linear part of
//! the placement (rotation times radius).

use crate::shape::{Aabb, SurfacePoint};
use glam::{Mat3, Vec2, Vec3};
use radiometry::warp::{uniform_cone, uniform_sphere};
use radiometry::Frame;
use std::f32::consts::{PI, TAU};

/// A sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (> 0).
    pub radius: f32,
    /// The orientation of its own frame (uv and tangents), a rotation.
    pub rotation: Mat3,
    /// Mitsuba's `flip_normals`: the normal points inwards.
    pub flip: bool,
}

/// A point sampled on a shape as seen from a reference point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSample {
    /// The point.
    pub p: Vec3,
    /// The unit geometric normal there.
    pub n: Vec3,
    /// The unit shading normal there (the side an area light emits to).
    pub ns: Vec3,
    /// Its surface coordinates.
    pub uv: Vec2,
    /// Density in solid angle at the reference point.
    pub pdf: f32,
}

impl Sphere {
    /// A sphere in its own orientation (the world's axes), normals outwards.
    pub fn new(center: Vec3, radius: f32) -> Self {
        Sphere { center, radius, rotation: Mat3::IDENTITY, flip: false }
    }

    /// The surface data at `p` (on the sphere).
    pub fn surface(&self, p: Vec3) -> SurfacePoint {
        let (p, n, n0) = self.point(p);
        let q = self.rotation.transpose() * n0;
        let mut phi = crate::atan::atan2(q.y, q.x);
        if phi < 0.0 {
            phi += TAU;
        }
        let rd = (q.x * q.x + q.y * q.y).sqrt();
        // atan2 of sin θ and cos θ is accurate at both poles, as acos is not.
        let theta = crate::atan::atan2(rd, q.z);
        let dv = if rd == 0.0 { Vec3::X } else { Vec3::new(q.z * q.x / rd, q.z * q.y / rd, -rd) };
        let lin = self.rotation * self.radius;
        SurfacePoint {
            p,
            ng: n,
            ns: n,
            uv: Vec2::new(phi / TAU, theta / PI),
            dp_du: lin * Vec3::new(-q.y, q.x, 0.0) * TAU,
            dp_dv: lin * dv * PI,
        }
    }

    /// The point of the sphere at (or nearest) `p`, its unit normal (inwards when flipped) and
    /// the outward one: what [`surface`](Self::surface) finds without the angles of its uv.
    #[inline]
    fn point(&self, p: Vec3) -> (Vec3, Vec3, Vec3) {
        let n0 = self.normal_out(p);
        (self.center + n0 * self.radius, if self.flip { -n0 } else { n0 }, n0)
    }

    /// The outward unit normal at (or near) `p`, whatever `flip`.
    #[inline]
    fn normal_out(&self, p: Vec3) -> Vec3 {
        (p - self.center).try_normalize().unwrap_or(Vec3::Z)
    }

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

    /// The unit normal at (or near) `p`: outwards, or inwards when flipped.
    #[inline]
    pub fn normal(&self, p: Vec3) -> Vec3 {
        let n = self.normal_out(p);
        if self.flip {
            -n
        } else {
            n
        }
    }

    /// `p` moved onto the surface along the normal (removes the rounding of o + t·d).
    #[inline]
    pub fn reproject(&self, p: Vec3) -> Vec3 {
        self.center + self.normal_out(p) * self.radius
    }

    /// A point on the sphere for reference point `r`: from outside, uniform over the
    /// subtended cone (the visible cap); from inside, uniform over the area.
    pub fn sample(&self, r: Vec3, u: Vec2, with_uv: bool) -> Option<ShapeSample> {
        // The point and normal as `surface` finds them, the density from them; the uv (two
        // arctangents) only when asked.
        let at = |p: Vec3, pdf: &dyn Fn(Vec3, Vec3) -> Option<f32>| {
            let (q, n, _) = self.point(p);
            let uv = if with_uv { self.surface(p).uv } else { Vec2::ZERO };
            Some(ShapeSample { p: q, n, ns: n, uv, pdf: pdf(q, n)? })
        };
        let dc = self.center - r;
        let dist2 = dc.length_squared();
        let r2 = self.radius * self.radius;
        if dist2 <= r2 * (1.0 + 1e-4) {
            let p = self.center + uniform_sphere(u) * self.radius;
            return at(p, &|q, n| area_to_solid_angle(1.0 / self.area(), r, q, n));
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
        at(r + d * t, &|_, _| Some(cone_pdf(sin2, cos_max)))
    }

    /// Solid-angle density of `sample` from `r` producing the point `p`.
    pub fn pdf(&self, r: Vec3, p: Vec3) -> f32 {
        let dist2 = (self.center - r).length_squared();
        let r2 = self.radius * self.radius;
        if dist2 <= r2 * (1.0 + 1e-4) {
            return area_to_solid_angle(1.0 / self.area(), r, p, self.normal_out(p)).unwrap_or(0.0);
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
    let (pdf, ok) = solid_angle_pdf(pdf_area, r, p, n);
    ok.then_some(pdf)
}

/// [`area_to_solid_angle`] as the density and whether it is valid (finite and positive), so
/// that loops over many points of it become vector code.
#[inline(always)]
pub fn solid_angle_pdf(pdf_area: f32, r: Vec3, p: Vec3, n: Vec3) -> (f32, bool) {
    let d = p - r;
    let dist2 = d.length_squared();
    let cos = (d.dot(n)).abs() / dist2.sqrt();
    let pdf = pdf_area * dist2 / cos;
    (pdf, pdf.is_finite() & (pdf > 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intersections_from_outside_inside_and_far_away() {
        let s = Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0);
        assert!((s.intersect(Vec3::ZERO, -Vec3::Z, 100.0).unwrap() - 4.0).abs() < 1e-6);
        assert!((s.intersect(Vec3::new(0.0, 0.0, -5.0), -Vec3::Z, 100.0).unwrap() - 1.0).abs() < 1e-6);
        assert!(s.intersect(Vec3::ZERO, Vec3::Z, 100.0).is_none());
        assert!(s.intersect(Vec3::ZERO, -Vec3::Z, 3.9).is_none());
        // 10^4 radii away the naive discriminant loses all digits; this form keeps them.
        let far = Sphere::new(Vec3::new(0.0, 0.0, -1e4), 1.0);
        let t = far.intersect(Vec3::new(0.5, 0.0, 0.0), -Vec3::Z, f32::INFINITY).unwrap();
        let p = Vec3::new(0.5, 0.0, -t);
        assert!(((p - far.center).length() - 1.0).abs() < 2e-3, "{t}");
    }

    #[test]
    fn cone_samples_hit_the_sphere_and_pdf_integrates_to_one() {
        let s = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 0.5);
        let r = Vec3::new(0.0, 0.0, -1.0);
        let mut rng = crate::sampler::Sampler::new(1, 2, 3);
        for _ in 0..1000 {
            let u = rng.next_2d();
            let smp = s.sample(r, u, true).unwrap();
            // The uv of the point before it is projected onto the sphere: within rounding.
            assert!((smp.uv - s.surface(smp.p).uv).abs().max_element() < 1e-6);
            assert_eq!(s.sample(r, u, false).map(|f| (f.p, f.n, f.pdf)), Some((smp.p, smp.n, smp.pdf)));
            assert!(((smp.p - s.center).length() - 0.5).abs() < 1e-5);
            assert!((smp.n.dot(r - smp.p)) >= -1e-4, "the sampled point faces the reference");
            assert_eq!(smp.pdf, s.pdf(r, smp.p));
        }
        // pdf × subtended solid angle = 1.
        let sin2 = 0.25 / (s.center - r).length_squared();
        let omega = 2.0 * PI * (1.0 - (1.0 - sin2).sqrt());
        assert!((s.pdf(r, s.center) * omega - 1.0).abs() < 1e-4);
        // From inside: area sampling, pdf = dist²/(A cos).
        let smp = s.sample(s.center, Vec2::new(0.3, 0.4), false).unwrap();
        assert!((smp.pdf - 0.25 / s.area()).abs() < 1e-5);
    }
}
