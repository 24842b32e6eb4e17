//! Rectangles: the square [−1, 1]² in the local XY plane with normal +Z, placed by a 4×4
//! to-world matrix (Mitsuba's `rectangle`). In world space this is the parallelogram
//! c + x·a + y·b, |x|, |y| ≤ 1, whose shading normal is the local +Z under the inverse
//! transpose; its geometric normal is a × b, the winding of Mitsuba's two triangles, so the
//! two point apart under a mirroring matrix, as in Mitsuba. uv = ((x + 1)/2, (y + 1)/2),
//! ∂p/∂u = 2a, ∂p/∂v = 2b.

use crate::shape::{Aabb, SurfacePoint};
use glam::{Mat4, Vec2, Vec3};

/// A parallelogram from the unit square under an affine map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rectangle {
    /// Centre (the image of the local origin).
    pub center: Vec3,
    /// Half-edge along local x.
    pub a: Vec3,
    /// Half-edge along local y.
    pub b: Vec3,
    /// Unit shading normal (the image of local +Z as a normal).
    pub n: Vec3,
    /// Unit geometric normal, along a × b.
    pub ng: Vec3,
    /// Mitsuba's `flip_normals`: both normals point the other way.
    pub flip: bool,
    /// Dual vectors: (p − c)·da = x and (p − c)·db = y for points in the plane.
    da: Vec3,
    db: Vec3,
}

impl Rectangle {
    /// The rectangle placed by `to_world` (None when it is degenerate: zero area).
    pub fn new(to_world: &Mat4) -> Option<Self> {
        let center = to_world.transform_point3(Vec3::ZERO);
        let a = to_world.transform_vector3(Vec3::X);
        let b = to_world.transform_vector3(Vec3::Y);
        let axb = a.cross(b);
        let plane_n = axb.try_normalize()?;
        // Normals transform by the inverse transpose: L⁻ᵀ e_z = (a × b)/det L.
        let det = glam::Mat3::from_mat4(*to_world).determinant();
        let n = if det < 0.0 { -plane_n } else { plane_n };
        let bn = b.cross(plane_n);
        let na = plane_n.cross(a);
        Some(Rectangle { center, a, b, n, ng: plane_n, flip: false, da: bn / a.dot(bn), db: na / b.dot(na) })
    }

    /// The bounding box of the four corners.
    pub fn bounds(&self) -> Aabb {
        let mut bb = Aabb::EMPTY;
        for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            bb = bb.grow(self.center + self.a * sx + self.b * sy);
        }
        bb
    }

    /// Area 4·|a × b|.
    pub fn area(&self) -> f32 {
        4.0 * self.a.cross(self.b).length()
    }

    /// Hit distance in (0, `t_max`).
    #[inline]
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        let denom = d.dot(self.n);
        let t = (self.center - o).dot(self.n) / denom;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let q = o + d * t - self.center;
        (q.dot(self.da).abs() <= 1.0 && q.dot(self.db).abs() <= 1.0).then_some(t)
    }

    /// The local coordinates (x, y) in [−1, 1]² of a point in the plane.
    pub fn local(&self, p: Vec3) -> Vec2 {
        let q = p - self.center;
        Vec2::new(q.dot(self.da), q.dot(self.db))
    }

    /// The surface data at `p` (in the plane).
    pub fn surface(&self, p: Vec3) -> SurfacePoint {
        let q = self.local(p);
        let s = if self.flip { -1.0 } else { 1.0 };
        SurfacePoint {
            p,
            ng: self.ng * s,
            ns: self.n * s,
            uv: (q + Vec2::ONE) * 0.5,
            dp_du: 2.0 * self.a,
            dp_dv: 2.0 * self.b,
        }
    }

    /// A point uniform over the area, with its area pdf.
    pub fn sample_area(&self, u: Vec2) -> (SurfacePoint, f32) {
        let p = self.center + self.a * (2.0 * u.x - 1.0) + self.b * (2.0 * u.y - 1.0);
        let mut s = self.surface(p);
        // The uv of the sample itself, free of the plane-projection rounding.
        s.uv = u;
        (s, 1.0 / self.area())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mitsuba_floor_matrix_faces_up() {
        // The peer scene's floor: row-major "10 0 0 0  0 0 10 0  0 -10 0 0  0 0 0 1".
        let m =
            Mat4::from_cols_array(&[10., 0., 0., 0., 0., 0., 10., 0., 0., -10., 0., 0., 0., 0., 0., 1.]).transpose();
        let r = Rectangle::new(&m).unwrap();
        assert!((r.n - Vec3::Y).length() < 1e-6, "{:?}", r.n);
        assert!((r.area() - 400.0).abs() < 1e-3);
        let t = r.intersect(Vec3::new(9.0, 5.0, -9.0), -Vec3::Y, 100.0).unwrap();
        assert!((t - 5.0).abs() < 1e-6);
        assert!(r.intersect(Vec3::new(10.5, 5.0, 0.0), -Vec3::Y, 100.0).is_none());
        assert!(r.intersect(Vec3::new(0.0, 5.0, 0.0), Vec3::X, 100.0).is_none(), "parallel ray");
        let (s, pdf) = r.sample_area(Vec2::new(1.0, 0.0));
        let p = s.p;
        assert!((p - Vec3::new(10.0, 0.0, 10.0)).length() < 1e-5, "{p:?}");
        assert!((pdf * 400.0 - 1.0).abs() < 1e-6);
        assert!((r.local(Vec3::new(5.0, 0.0, -2.5)) - Vec2::new(0.5, 0.25)).length() < 1e-6);
        // A mirroring transform flips the normal, as Mitsuba's inverse transpose does.
        let flipped = Rectangle::new(&Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0))).unwrap();
        assert!((flipped.n + Vec3::Z).length() < 1e-6);
        assert!(Rectangle::new(&Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
    }
}
