//! Triangle meshes: shared vertex positions, optional per-vertex normals (smooth shading),
//! ray-triangle intersection by Möller & Trumbore, "Fast, minimum storage ray/triangle
//! intersection", JGT 1997, and uniform area sampling by the square-root warp
//! (Turk, "Generating random points in triangles", Graphics Gems 1990).

use crate::distribution::Distribution1D;
use crate::error::{Error, Result};
use crate::shape::Aabb;
use glam::{Mat4, Vec2, Vec3};

/// An indexed triangle mesh in world space.
#[derive(Clone, Debug)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, when the mesh is smooth-shaded.
    pub normals: Option<Vec<Vec3>>,
    /// Vertex indices, three per triangle, counter-clockwise seen from the front.
    pub indices: Vec<[u32; 3]>,
    /// Triangle areas as a sampling distribution (for area lights).
    area: Distribution1D,
}

impl TriangleMesh {
    /// A mesh from its parts; checks that indices are in range and the data finite.
    /// Zero-area triangles are kept (they are never hit and never sampled).
    pub fn new(positions: Vec<Vec3>, normals: Option<Vec<Vec3>>, indices: Vec<[u32; 3]>) -> Result<Self> {
        if let Some(n) = &normals {
            if n.len() != positions.len() {
                return Err(Error::Invalid(format!("mesh has {} normals for {} vertices", n.len(), positions.len())));
            }
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::Invalid(format!("mesh vertex {i} is not finite: {:?}", positions[i])));
        }
        let nv = positions.len() as u64;
        if let Some((t, tri)) = indices.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i as u64 >= nv)) {
            return Err(Error::Invalid(format!("mesh triangle {t} has index {tri:?} beyond the {nv} vertices")));
        }
        let normals = normals.map(|ns| ns.into_iter().map(|n| n.try_normalize().unwrap_or(Vec3::ZERO)).collect());
        let mut m = TriangleMesh { positions, normals, indices, area: Distribution1D::new(&[]) };
        m.update_areas();
        Ok(m)
    }

    fn update_areas(&mut self) {
        let areas: Vec<f32> = (0..self.indices.len()).map(|i| self.triangle_area(i)).collect();
        self.area = Distribution1D::new(&areas);
    }

    /// Applies `m` to positions and (by its inverse transpose) to normals.
    pub fn transform(&mut self, m: &Mat4) {
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        let nm = m.inverse().transpose();
        if let Some(ns) = &mut self.normals {
            for n in ns {
                *n = nm.transform_vector3(*n).try_normalize().unwrap_or(Vec3::ZERO);
            }
        }
        self.update_areas();
    }

    /// The number of triangles.
    pub fn len(&self) -> usize {
        self.indices.len()
    }

    /// True when the mesh has no triangles.
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    /// The three corners of triangle `i`.
    #[inline]
    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[i];
        [self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]]
    }

    /// The area of triangle `i`.
    pub fn triangle_area(&self, i: usize) -> f32 {
        let [a, b, c] = self.triangle(i);
        0.5 * (b - a).cross(c - a).length()
    }

    /// The total surface area.
    pub fn area(&self) -> f32 {
        self.area.total() as f32
    }

    /// The bounding box of triangle `i`.
    pub fn triangle_bounds(&self, i: usize) -> Aabb {
        let [a, b, c] = self.triangle(i);
        Aabb { min: a.min(b).min(c), max: a.max(b).max(c) }
    }

    /// Geometric normal (unit, by the winding) and shading normal of triangle `i` at
    /// barycentrics (u, v) of corners 1 and 2; the geometric normal is flipped to the
    /// shading normal's side so that "front" means the same thing to both.
    pub fn normals_at(&self, i: usize, u: f32, v: f32) -> (Vec3, Vec3) {
        let [a, b, c] = self.triangle(i);
        let ng = (b - a).cross(c - a).try_normalize().unwrap_or(Vec3::Z);
        let Some(ns) = &self.normals else { return (ng, ng) };
        let [ia, ib, ic] = self.indices[i];
        let n = ns[ia as usize] * (1.0 - u - v) + ns[ib as usize] * u + ns[ic as usize] * v;
        match n.try_normalize() {
            Some(n) if n.dot(ng) < 0.0 => (-ng, n),
            Some(n) => (ng, n),
            None => (ng, ng),
        }
    }

    /// A point uniformly distributed over the mesh surface: (point, geometric normal, area pdf).
    pub fn sample_area(&self, uc: f32, u: Vec2) -> (Vec3, Vec3, f32) {
        let (i, _, _) = self.area.sample(uc);
        let [a, b, c] = self.triangle(i);
        let su = u.x.sqrt();
        let (b1, b2) = (su * (1.0 - u.y), su * u.y);
        let p = a * (1.0 - b1 - b2) + b * b1 + c * b2;
        let (ng, _) = self.normals_at(i, b1, b2);
        (p, ng, 1.0 / self.area().max(f32::MIN_POSITIVE))
    }
}

/// Möller–Trumbore: distance and barycentrics (u, v) of corners 1 and 2 for a hit in
/// (0, `t_max`), or None. Written so that NaNs from degenerate triangles compare as misses.
#[inline]
pub fn intersect_triangle(o: Vec3, d: Vec3, t_max: f32, p0: Vec3, e1: Vec3, e2: Vec3) -> Option<(f32, f32, f32)> {
    let pvec = d.cross(e2);
    let det = e1.dot(pvec);
    if det == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let tvec = o - p0;
    let u = tvec.dot(pvec) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qvec = tvec.cross(e1);
    let v = d.dot(qvec) * inv;
    if !(v >= 0.0 && u + v <= 1.0) {
        return None;
    }
    let t = e2.dot(qvec) * inv;
    (t > 0.0 && t < t_max).then_some((t, u, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hit_and_miss() {
        let (p0, e1, e2) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let (t, u, v) = intersect_triangle(Vec3::new(0.25, 0.5, 2.0), -Vec3::Z, 10.0, p0, e1, e2).unwrap();
        assert!((t - 2.0).abs() < 1e-6 && (u - 0.25).abs() < 1e-6 && (v - 0.5).abs() < 1e-6);
        assert!(intersect_triangle(Vec3::new(0.75, 0.5, 2.0), -Vec3::Z, 10.0, p0, e1, e2).is_none());
        assert!(intersect_triangle(Vec3::new(0.25, 0.5, 2.0), -Vec3::Z, 1.5, p0, e1, e2).is_none());
        assert!(intersect_triangle(Vec3::new(0.25, 0.5, 2.0), Vec3::Z, 10.0, p0, e1, e2).is_none());
        // Degenerate triangle: never a hit, never a NaN.
        assert!(intersect_triangle(Vec3::new(0.0, 0.0, 2.0), -Vec3::Z, 10.0, p0, e1, e1).is_none());
    }

    #[test]
    fn validation_transform_and_sampling() {
        assert!(TriangleMesh::new(vec![Vec3::ZERO; 3], None, vec![[0, 1, 3]]).is_err());
        let mut m = TriangleMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
            Some(vec![Vec3::Z; 4]),
            vec![[0, 1, 2], [1, 3, 2]],
        )
        .unwrap();
        assert!((m.area() - 1.0).abs() < 1e-6);
        m.transform(&Mat4::from_scale(Vec3::new(2.0, 3.0, 1.0)));
        assert!((m.area() - 6.0).abs() < 1e-5);
        let (ng, ns) = m.normals_at(0, 0.2, 0.2);
        assert!((ng - Vec3::Z).length() < 1e-6 && (ns - Vec3::Z).length() < 1e-6);
        let (p, _, pdf) = m.sample_area(0.7, Vec2::new(0.3, 0.6));
        assert!(p.x >= 0.0 && p.x <= 2.0 && p.y >= 0.0 && p.y <= 3.0 && p.z == 0.0);
        assert!((pdf - 1.0 / 6.0).abs() < 1e-6);
    }
}
