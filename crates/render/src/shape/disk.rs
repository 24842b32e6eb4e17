//! Disks: the unit disk x² + y² ≤ 1 in the local XY plane with normal +Z, placed by a 4×4
//! to-world matrix (Mitsuba's `disk`). In world space this is the ellipse c + x·a + y·b,
//! x² + y² ≤ 1, in the plane of the rectangle with the same matrix, whose machinery (plane,
//! normal, local coordinates) it reuses. Mitsuba's polar coordinates: uv = (r, φ/2π) with
//! φ in [0, 2π), ∂p/∂u = a cos φ + b sin φ, ∂p/∂v = 2π(−y a + x b); both vanish at the centre.

use crate::shape::{Aabb, Rectangle, SurfacePoint};
use glam::{Mat4, Vec2, Vec3};
use radiometry::warp::concentric_disk;
use std::f32::consts::{PI, TAU};

/// An ellipse from the unit disk under an affine map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    /// The plane, centre, half-axes and normal (those of the enclosing rectangle).
    pub frame: Rectangle,
}

impl Disk {
    /// The disk placed by `to_world` (None when it is degenerate: zero area).
    pub fn new(to_world: &Mat4) -> Option<Self> {
        Rectangle::new(to_world).map(|frame| Disk { frame })
    }

    /// The unit normal.
    #[inline]
    pub fn normal(&self) -> Vec3 {
        self.frame.n
    }

    /// The bounding box: c ± √(a_i² + b_i²) per axis (the extent of c + a cos φ + b sin φ).
    pub fn bounds(&self) -> Aabb {
        let (a, b) = (self.frame.a, self.frame.b);
        let e = (a * a + b * b).max(Vec3::ZERO);
        let e = Vec3::new(e.x.sqrt(), e.y.sqrt(), e.z.sqrt());
        Aabb { min: self.frame.center - e, max: self.frame.center + e }
    }

    /// Area π·|a × b|.
    pub fn area(&self) -> f32 {
        PI * self.frame.a.cross(self.frame.b).length()
    }

    /// Hit distance in (0, `t_max`).
    #[inline]
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        let n = self.frame.n;
        let t = (self.frame.center - o).dot(n) / d.dot(n);
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        (self.frame.local(o + d * t).length_squared() <= 1.0).then_some(t)
    }

    /// The surface data at local point `q` of the unit disk.
    fn surface_local(&self, q: Vec2) -> SurfacePoint {
        let (a, b) = (self.frame.a, self.frame.b);
        let r = q.length();
        let mut phi = crate::atan::atan2(q.y, q.x);
        if phi < 0.0 {
            phi += TAU;
        }
        let dp_du = if r > 0.0 { (a * q.x + b * q.y) / r } else { Vec3::ZERO };
        let n = if self.frame.flip { -self.frame.n } else { self.frame.n };
        SurfacePoint {
            p: self.frame.center + a * q.x + b * q.y,
            ng: n,
            ns: n,
            uv: Vec2::new(r, phi / TAU),
            dp_du,
            dp_dv: (b * q.x - a * q.y) * TAU,
        }
    }

    /// The surface data at `p` (in the disk's plane).
    pub fn surface(&self, p: Vec3) -> SurfacePoint {
        SurfacePoint { p, ..self.surface_local(self.frame.local(p)) }
    }

    /// A point uniform over the area, with its area pdf. The affine map scales all areas by
    /// the same factor, so a uniform point on the unit disk stays uniform.
    pub fn sample_area(&self, u: Vec2) -> (SurfacePoint, f32) {
        (self.surface_local(concentric_disk(u)), 1.0 / self.area())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaled_disk_hits_bounds_and_samples() {
        let m = Mat4::from_translation(Vec3::new(0.0, 0.0, -2.0)) * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
        let d = Disk::new(&m).unwrap();
        assert!((d.area() - 2.0 * PI).abs() < 1e-5);
        assert!((d.normal() - Vec3::Z).length() < 1e-6);
        let b = d.bounds();
        assert!(
            (b.min - Vec3::new(-2.0, -1.0, -2.0)).length() < 1e-6
                && (b.max - Vec3::new(2.0, 1.0, -2.0)).length() < 1e-6
        );
        let t = d.intersect(Vec3::new(1.9, 0.0, 0.0), -Vec3::Z, 10.0).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
        // Inside the bounding rectangle's corner but outside the ellipse.
        assert!(d.intersect(Vec3::new(1.5, 0.8, 0.0), -Vec3::Z, 10.0).is_none());
        assert!(d.intersect(Vec3::new(0.0, 0.0, 0.0), -Vec3::Z, 1.0).is_none(), "beyond t_max");
        for k in 0..100 {
            let u = Vec2::new((k % 10) as f32 / 10.0 + 0.05, (k / 10) as f32 / 10.0 + 0.05);
            let (s, pdf) = d.sample_area(u);
            let p = s.p;
            assert!(d.frame.local(p).length() <= 1.0 + 1e-5 && (p.z + 2.0).abs() < 1e-6);
            assert!((pdf * 2.0 * PI - 1.0).abs() < 1e-5);
        }
    }
}
