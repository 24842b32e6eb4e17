//! Shapes: triangle meshes, spheres, rectangles and disks, their bounding boxes, and the
//! primitive-level interface the BVH and the lights use. Every shape gives a hit its uv and
//! ∂p/∂u, ∂p/∂v exactly as Mitsuba 3 defines them, so that textures, anisotropic models and
//! normal maps line up with Mitsuba's images; the shading frame is then Gram–Schmidt of ∂p/∂u
//! against the shading normal (`SurfacePoint::frame`).

pub mod disk;
pub mod mesh;
pub mod rectangle;
pub mod sphere;

pub use disk::Disk;
pub use mesh::TriangleMesh;
pub use rectangle::Rectangle;
pub use sphere::{ShapeSample, Sphere};

use glam::{Vec2, Vec3};
use radiometry::Frame;

/// The local geometry of a surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The point.
    pub p: Vec3,
    /// Unit geometric normal (a triangle's by its winding; flipped with `flip_normals`).
    pub ng: Vec3,
    /// Unit shading normal (interpolated vertex normals, else `ng`).
    pub ns: Vec3,
    /// Surface coordinates.
    pub uv: Vec2,
    /// ∂p/∂u.
    pub dp_du: Vec3,
    /// ∂p/∂v.
    pub dp_dv: Vec3,
}

impl SurfacePoint {
    /// Mitsuba's shading frame: s = ∂p/∂u made orthogonal to the shading normal, t = n × s;
    /// where ∂p/∂u vanishes (a sphere's poles, a disk's centre) the normal's own basis.
    #[inline]
    pub fn frame(&self) -> Frame {
        let n = self.ns;
        if self.dp_du == Vec3::ZERO {
            return Frame::from_normal(n);
        }
        let s = (self.dp_du - n * n.dot(self.dp_du)).normalize();
        if !s.is_finite() {
            return Frame::from_normal(n);
        }
        Frame { s, t: n.cross(s), n }
    }
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (the identity of `union`).
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    /// The box grown to hold `p`.
    #[inline]
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    /// The smallest box holding both.
    #[inline]
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// The centre.
    #[inline]
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Half the surface area (the SAH only needs ratios); 0 for an empty box.
    #[inline]
    pub fn half_area(&self) -> f32 {
        let e = (self.max - self.min).max(Vec3::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    /// True when the box holds nothing.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }
}

/// The geometry of one shape.
#[derive(Clone, Debug)]
pub enum Geometry {
    /// A triangle mesh (one primitive per triangle).
    Mesh(TriangleMesh),
    /// A sphere (one primitive).
    Sphere(Sphere),
    /// A rectangle (one primitive).
    Rectangle(Rectangle),
    /// A disk (one primitive).
    Disk(Disk),
}

impl Geometry {
    /// The number of BVH primitives.
    pub fn primitive_count(&self) -> usize {
        match self {
            Geometry::Mesh(m) => m.len(),
            _ => 1,
        }
    }

    /// The bounding box of primitive `i`.
    pub fn primitive_bounds(&self, i: usize) -> Aabb {
        match self {
            Geometry::Mesh(m) => m.triangle_bounds(i),
            Geometry::Sphere(s) => s.bounds(),
            Geometry::Rectangle(r) => r.bounds(),
            Geometry::Disk(d) => d.bounds(),
        }
    }

    /// The surface area.
    pub fn area(&self) -> f32 {
        match self {
            Geometry::Mesh(m) => m.area(),
            Geometry::Sphere(s) => s.area(),
            Geometry::Rectangle(r) => r.area(),
            Geometry::Disk(d) => d.area(),
        }
    }

    /// A point on the shape seen from `r`, with its solid-angle density at `r`; its uv may be
    /// left zero on a sphere unless `with_uv`.
    pub fn sample(&self, r: Vec3, uc: f32, u: Vec2, with_uv: bool) -> Option<ShapeSample> {
        let (point, pdf_area) = match self {
            Geometry::Sphere(s) => return s.sample(r, u, with_uv),
            Geometry::Mesh(m) => m.sample_area(uc, u),
            Geometry::Rectangle(q) => q.sample_area(u),
            Geometry::Disk(d) => d.sample_area(u),
        };
        let pdf = sphere::area_to_solid_angle(pdf_area, r, point.p, point.ng)?;
        Some(ShapeSample { p: point.p, n: point.ng, ns: point.ns, uv: point.uv, pdf })
    }

    /// The solid-angle density of `sample` from `r` giving point `p` with normal `n`.
    pub fn pdf(&self, r: Vec3, p: Vec3, n: Vec3) -> f32 {
        match self {
            Geometry::Sphere(s) => s.pdf(r, p),
            _ => sphere::area_to_solid_angle(1.0 / self.area(), r, p, n).unwrap_or(0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aabb_algebra() {
        let b = Aabb::EMPTY.grow(Vec3::ZERO).grow(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(b.center(), Vec3::new(0.5, 1.0, 1.5));
        assert_eq!(b.half_area(), 2.0 + 6.0 + 3.0);
        assert!(Aabb::EMPTY.is_empty() && !b.is_empty());
        assert_eq!(Aabb::EMPTY.half_area(), 0.0);
        assert_eq!(Aabb::EMPTY.union(b), b);
    }
}
