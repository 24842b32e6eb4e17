//! Triangle meshes: shared vertex positions, optional per-vertex normals (smooth shading) and
//! uvs, ray-triangle intersection by Möller & Trumbore, "Fast, minimum storage ray/triangle
//! intersection", JGT 1997, and uniform area sampling by the square-root warp (Turk,
//! "Generating random points in triangles", Graphics Gems 1990).
//!
//! At barycentrics (b1, b2) of corners 1 and 2 (Mitsuba 3's `Mesh`): the geometric normal
//! follows the winding, (p1 − p0) × (p2 − p0); with uvs, uv is interpolated and ∂p/∂u, ∂p/∂v
//! solve dp = ∂p/∂u du + ∂p/∂v dv on the two edges (the normal's basis when the uv triangle is
//! degenerate); without uvs, uv = (b1, b2), ∂p/∂u = p1 − p0 and ∂p/∂v = p2 − p0.

use crate::error::{Error, Result};
use crate::shape::{Aabb, SurfacePoint};
use glam::{Mat4, Vec2, Vec3};
use radiometry::distribution::Distribution1D;
use radiometry::Frame;

/// An indexed triangle mesh in world space.
#[derive(Clone, Debug)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, when the mesh is smooth-shaded.
    pub normals: Option<Vec<Vec3>>,
    /// Vertex uvs, when the mesh has them.
    pub uvs: Option<Vec<Vec2>>,
    /// Vertex indices, three per triangle, counter-clockwise seen from the front.
    pub indices: Vec<[u32; 3]>,
    /// Mitsuba's `flip_normals`: both normals point the other way (uvs and ∂p/∂u do not change).
    pub flip: bool,
    /// Triangle areas as a sampling distribution (for area lights).
    area: Distribution1D,
}

impl TriangleMesh {
    /// A mesh from its parts; checks that indices are in range and the data finite.
    /// Zero-area triangles are kept (they are never hit and never sampled).
    pub fn new(positions: Vec<Vec3>, normals: Option<Vec<Vec3>>, indices: Vec<[u32; 3]>) -> Result<Self> {
        Self::with_uvs(positions, normals, None, indices)
    }

    /// A mesh with vertex uvs as well.
    pub fn with_uvs(
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
        indices: Vec<[u32; 3]>,
    ) -> Result<Self> {
        let nv = positions.len();
        if let Some(n) = &normals {
            if n.len() != nv {
                return Err(Error::Invalid(format!("mesh has {} normals for {nv} vertices", n.len())));
            }
            if let Some(i) = n.iter().position(|n| !n.is_finite()) {
                return Err(Error::Invalid(format!("mesh normal {i} is not finite: {:?}", n[i])));
            }
        }
        if let Some(t) = &uvs {
            if t.len() != nv {
                return Err(Error::Invalid(format!("mesh has {} uvs for {nv} vertices", t.len())));
            }
            if let Some(i) = t.iter().position(|t| !t.is_finite()) {
                return Err(Error::Invalid(format!("mesh uv {i} is not finite: {:?}", t[i])));
            }
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::Invalid(format!("mesh vertex {i} is not finite: {:?}", positions[i])));
        }
        if let Some((t, tri)) = indices.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i as usize >= nv)) {
            return Err(Error::Invalid(format!("mesh triangle {t} has index {tri:?} beyond the {nv} vertices")));
        }
        let normals = normals.map(|ns| ns.into_iter().map(|n| n.try_normalize().unwrap_or(Vec3::ZERO)).collect());
        let mut m = TriangleMesh { positions, normals, uvs, indices, flip: false, area: Distribution1D::new(&[]) };
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

    /// Smooth vertex normals where the file gave none (Mitsuba's default): each face's unit
    /// normal added to its corners weighted by the corner's angle; (1, 0, 0) for a vertex that
    /// no face with area touches.
    pub fn compute_vertex_normals(&mut self) {
        let mut acc = vec![Vec3::ZERO; self.positions.len()];
        for tri in &self.indices {
            let p = tri.map(|i| self.positions[i as usize]);
            let Some(n) = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize() else { continue };
            for k in 0..3 {
                let (a, b) = ((p[(k + 1) % 3] - p[k]).normalize_or_zero(), (p[(k + 2) % 3] - p[k]).normalize_or_zero());
                acc[tri[k] as usize] += n * unit_angle(a, b);
            }
        }
        self.normals = Some(acc.into_iter().map(|n| n.try_normalize().unwrap_or(Vec3::X)).collect());
    }

    /// Smooth normals with a crease angle: a corner's normal averages (weighted by corner
    /// angle) the normals of the faces around its position that turn at most `max_angle`
    /// radians from its own face, so edges sharper than that stay sharp. A vertex whose
    /// corners get different normals is split (its uv copied), the triangles keep their order.
    pub fn compute_smooth_normals(&mut self, max_angle: f32) {
        let cos_max = max_angle.clamp(0.0, std::f32::consts::PI).cos();
        let faces: Vec<(Option<Vec3>, [f32; 3])> = self
            .indices
            .iter()
            .map(|tri| {
                let p = tri.map(|i| self.positions[i as usize]);
                let n = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize();
                let angle = std::array::from_fn(|k| {
                    let (a, b) =
                        ((p[(k + 1) % 3] - p[k]).normalize_or_zero(), (p[(k + 2) % 3] - p[k]).normalize_or_zero());
                    unit_angle(a, b)
                });
                (n, angle)
            })
            .collect();
        // The faces around each position, as (face, corner): by position, since a file that
        // splits vertices at uv seams (or everywhere, as many OBJ exporters do) still means
        // one surface there.
        let mut at = std::collections::HashMap::new();
        let place: Vec<usize> = self
            .positions
            .iter()
            .map(|p| {
                let n = at.len();
                *at.entry(p.to_array().map(f32::to_bits)).or_insert(n)
            })
            .collect();
        let mut around: Vec<Vec<(u32, u8)>> = vec![Vec::new(); at.len()];
        for (f, tri) in self.indices.iter().enumerate() {
            for (k, &v) in tri.iter().enumerate() {
                around[place[v as usize]].push((f as u32, k as u8));
            }
        }
        let (mut positions, mut uvs, mut normals) = (Vec::new(), self.uvs.as_ref().map(|_| Vec::new()), Vec::new());
        let mut split = std::collections::HashMap::new();
        let mut indices = self.indices.clone();
        for (f, tri) in self.indices.iter().enumerate() {
            for (k, &v) in tri.iter().enumerate() {
                let own = faces[f].0;
                let mut sum = Vec3::ZERO;
                for &(g, c) in &around[place[v as usize]] {
                    if let (Some(n), Some(m)) = (faces[g as usize].0, own) {
                        if n.dot(m) >= cos_max {
                            sum += n * faces[g as usize].1[c as usize];
                        }
                    }
                }
                let n = sum.try_normalize().or(own).unwrap_or(Vec3::X);
                let key = (v, n.to_array().map(f32::to_bits));
                indices[f][k] = *split.entry(key).or_insert_with(|| {
                    positions.push(self.positions[v as usize]);
                    if let (Some(out), Some(src)) = (&mut uvs, &self.uvs) {
                        out.push(src[v as usize]);
                    }
                    normals.push(n);
                    (positions.len() - 1) as u32
                });
            }
        }
        (self.positions, self.uvs, self.normals, self.indices) = (positions, uvs, Some(normals), indices);
    }

    /// Phong tessellation (Boubekeur & Alexa 2008, "Phong Tessellation", SIGGRAPH Asia): each
    /// triangle is split in four at its edge midpoints, and a midpoint m of an edge (i, j)
    /// moves to (1 − α) m + α ½ (π_i(m) + π_j(m)), π_k projecting onto the tangent plane of
    /// vertex k, with the paper's α = 3/4; its normal is the normalised mean of the two. The
    /// silhouette and the shadow terminator of a coarse smooth-shaded mesh round off this way.
    /// An edge whose ends have other normals in another triangle (a crease) is split at its
    /// midpoint, so that the two sides still meet. Does nothing to a mesh without normals.
    pub fn phong_tessellate(&mut self) {
        const ALPHA: f32 = 0.75;
        let Some(normals) = self.normals.take() else { return };
        let key = |p: Vec3| p.to_array().map(f32::to_bits);
        let edge_of = |a: u32, b: u32| {
            let (ka, kb) = (key(self.positions[a as usize]), key(self.positions[b as usize]));
            let na = normals[a as usize].to_array().map(f32::to_bits);
            let nb = normals[b as usize].to_array().map(f32::to_bits);
            if ka <= kb {
                ((ka, kb), (na, nb))
            } else {
                ((kb, ka), (nb, na))
            }
        };
        // The normals each geometric edge is seen with: one pair for a smooth edge.
        let mut seen: std::collections::HashMap<_, Vec<_>> = std::collections::HashMap::new();
        for tri in &self.indices {
            for k in 0..3 {
                let (e, n) = edge_of(tri[k], tri[(k + 1) % 3]);
                let v = seen.entry(e).or_default();
                if !v.contains(&n) {
                    v.push(n);
                }
            }
        }
        let (mut positions, mut uvs, mut ns) = (self.positions.clone(), self.uvs.clone(), normals.clone());
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (pa, pb, na, nb) =
                    (self.positions[a as usize], self.positions[b as usize], normals[a as usize], normals[b as usize]);
                let m = 0.5 * (pa + pb);
                let smooth = seen.get(&edge_of(a, b).0).is_some_and(|v| v.len() == 1);
                let p = if smooth {
                    let project = |q: Vec3, p: Vec3, n: Vec3| q - (q - p).dot(n) * n;
                    (1.0 - ALPHA) * m + ALPHA * 0.5 * (project(m, pa, na) + project(m, pb, nb))
                } else {
                    m
                };
                positions.push(p);
                ns.push((na + nb).try_normalize().unwrap_or(na));
                if let Some(t) = &mut uvs {
                    t.push(0.5 * (t[a as usize] + t[b as usize]));
                }
                (positions.len() - 1) as u32
            })
        };
        let mut indices = Vec::with_capacity(4 * self.indices.len());
        for &[a, b, c] in &self.indices {
            let (ab, bc, ca) = (midpoint(a, b), midpoint(b, c), midpoint(c, a));
            indices.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        (self.positions, self.uvs, self.normals, self.indices) = (positions, uvs, Some(ns), indices);
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

    /// Starts loading triangle `i`'s vertex indices, the first read of [`surface`](Self::surface)
    /// (a hint; it changes no result).
    #[inline]
    pub fn prefetch_indices(&self, i: usize) {
        radiometry::prefetch::prefetch(&self.indices[i]);
    }

    /// Once its indices are loaded, starts loading what [`surface`](Self::surface) reads of
    /// triangle `i` next: its corners, vertex normals and uvs (a hint).
    #[inline]
    pub fn prefetch_vertices(&self, i: usize) {
        for v in self.indices[i].map(|k| k as usize) {
            radiometry::prefetch::prefetch(&self.positions[v]);
            if let Some(n) = &self.normals {
                radiometry::prefetch::prefetch(&n[v]);
            }
            if let Some(t) = &self.uvs {
                radiometry::prefetch::prefetch(&t[v]);
            }
        }
    }

    /// The surface at barycentrics (b1, b2) of corners 1 and 2 of triangle `i`.
    pub fn surface(&self, i: usize, b1: f32, b2: f32) -> SurfacePoint {
        let idx = self.indices[i].map(|k| k as usize);
        let [p0, p1, p2] = idx.map(|k| self.positions[k]);
        let b0 = 1.0 - b1 - b2;
        let p = p0 * b0 + p1 * b1 + p2 * b2;
        let (dp0, dp1) = (p1 - p0, p2 - p0);
        let ng = dp0.cross(dp1).try_normalize().unwrap_or(Vec3::Z);
        let (uv, dp_du, dp_dv) = match &self.uvs {
            Some(t) => {
                let [t0, t1, t2] = idx.map(|k| t[k]);
                let (duv0, duv1) = (t1 - t0, t2 - t0);
                let det = duv0.x * duv1.y - duv0.y * duv1.x;
                let (du, dv) = if det != 0.0 {
                    let inv = 1.0 / det;
                    ((dp0 * duv1.y - dp1 * duv0.y) * inv, (dp1 * duv0.x - dp0 * duv1.x) * inv)
                } else {
                    let f = Frame::from_normal(ng);
                    (f.s, f.t)
                };
                (t0 * b0 + t1 * b1 + t2 * b2, du, dv)
            }
            None => (Vec2::new(b1, b2), dp0, dp1),
        };
        let ns = match &self.normals {
            Some(n) => (n[idx[0]] * b0 + n[idx[1]] * b1 + n[idx[2]] * b2).try_normalize().unwrap_or(ng),
            None => ng,
        };
        let s = if self.flip { -1.0 } else { 1.0 };
        SurfacePoint { p, ng: ng * s, ns: ns * s, uv, dp_du, dp_dv }
    }

    /// The triangle `sample_area(uc, _)` places its point on: chosen in proportion to area.
    #[inline]
    pub fn sampled_triangle(&self, uc: f32) -> usize {
        self.area.cell(uc)
    }

    /// A point uniformly distributed over the mesh surface, with its area pdf.
    pub fn sample_area(&self, uc: f32, u: Vec2) -> (SurfacePoint, f32) {
        let i = self.sampled_triangle(uc);
        let b = radiometry::warp::uniform_triangle(u);
        (self.surface(i, b.x, b.y), 1.0 / self.area().max(f32::MIN_POSITIVE))
    }
}

/// The angle between unit vectors, accurate near 0 and π (Mitsuba's `unit_angle`).
fn unit_angle(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) < 0.0 {
        std::f32::consts::PI - 2.0 * (0.5 * (a + b).length()).min(1.0).asin()
    } else {
        2.0 * (0.5 * (b - a).length()).min(1.0).asin()
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

    /// The unit cube [−1, 1]³ as 12 outward triangles on 8 shared vertices.
    fn cube() -> TriangleMesh {
        let p: Vec<Vec3> = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                )
            })
            .collect();
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let tris = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        TriangleMesh::new(p, None, tris).unwrap()
    }

    #[test]
    fn smooth_normals_keep_edges_sharper_than_the_crease_angle() {
        let mut sharp = cube();
        sharp.compute_smooth_normals(60f32.to_radians());
        // Every corner keeps its face's normal: 6 faces × 4 corners.
        assert_eq!((sharp.positions.len(), sharp.len()), (24, 12));
        for f in 0..sharp.len() {
            let [a, b, c] = sharp.triangle(f);
            let face = (b - a).cross(c - a).normalize();
            for &i in &sharp.indices[f] {
                assert!((sharp.normals.as_ref().unwrap()[i as usize] - face).length() < 1e-6);
            }
        }
        // Past 90°: one normal per vertex, along the diagonal.
        let mut round = cube();
        round.compute_smooth_normals(100f32.to_radians());
        assert_eq!(round.positions.len(), 8);
        for (p, n) in round.positions.iter().zip(round.normals.as_ref().unwrap()) {
            assert!((*n - p.normalize()).length() < 1e-5, "{p} {n}");
        }
        assert!((round.area() - 24.0).abs() < 1e-4);
        // Tessellated, the smooth cube rounds towards its circumscribed sphere (radius √3): the
        // midpoints of its face diagonals, at radius 1 when split straight, move out to 1.5 and
        // its edges' from √2 to 1.77; the sharp cube keeps its faces flat.
        let mut rounder = round.clone();
        rounder.phong_tessellate();
        assert_eq!(rounder.len(), 48);
        let r = |m: &TriangleMesh| m.positions.iter().map(|p| p.length()).fold(f32::INFINITY, f32::min);
        assert!((r(&rounder) - 1.5).abs() < 1e-5, "{}", r(&rounder));
        let mut flat = sharp.clone();
        flat.phong_tessellate();
        assert_eq!(flat.len(), 48);
        assert!(flat.positions.iter().all(|p| (p.abs().max_element() - 1.0).abs() < 1e-6), "creases split straight");
        assert!((flat.area() - 24.0).abs() < 1e-3);
        // The same cube with no vertex shared between triangles smooths the same way.
        let c = cube();
        let positions = c.indices.iter().flatten().map(|&i| c.positions[i as usize]).collect();
        let indices = (0..12u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        let mut soup = TriangleMesh::new(positions, None, indices).unwrap();
        soup.compute_smooth_normals(100f32.to_radians());
        for (p, n) in soup.positions.iter().zip(soup.normals.as_ref().unwrap()) {
            assert!((*n - p.normalize()).length() < 1e-5, "{p} {n}");
        }
    }

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
        let s = m.surface(0, 0.2, 0.2);
        assert!((s.ng - Vec3::Z).length() < 1e-6 && (s.ns - Vec3::Z).length() < 1e-6);
        let (s, pdf) = m.sample_area(0.7, Vec2::new(0.3, 0.6));
        assert!(s.p.x >= 0.0 && s.p.x <= 2.0 && s.p.y >= 0.0 && s.p.y <= 3.0 && s.p.z == 0.0);
        assert!((pdf - 1.0 / 6.0).abs() < 1e-6);
    }
}
