//! Four triangles in structure-of-arrays lanes, tested against one ray at once by
//! Möller & Trumbore, "Fast, minimum storage ray/triangle intersection", JGT 1997. Each lane
//! performs exactly the operations of the scalar [`intersect_triangle`], in the same order,
//! so both give the same distances bit for bit.
//!
//! [`intersect_triangle`]: crate::shape::mesh::intersect_triangle

use super::RayPacket;
use crate::simd::{cross, dot, F16, M16};
use glam::{BVec4A, Vec3, Vec4};

/// Four triangles as a corner and two edges, x/y/z lanes; unused lanes hold a degenerate
/// (all-zero) triangle, which no ray hits.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Tri4 {
    p0: [Vec4; 3],
    e1: [Vec4; 3],
    e2: [Vec4; 3],
}

/// A ray splatted over four lanes.
#[derive(Clone, Copy, Debug)]
pub struct Ray4 {
    o: [Vec4; 3],
    d: [Vec4; 3],
}

impl Ray4 {
    /// The ray `o + t·d` on every lane.
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        let s = Vec4::splat;
        Ray4 { o: [s(o.x), s(o.y), s(o.z)], d: [s(d.x), s(d.y), s(d.z)] }
    }
}

impl Tri4 {
    /// Puts the triangle (corner `p0`, edges `e1`, `e2`) in lane `lane` (< 4).
    pub fn set(&mut self, lane: usize, p0: Vec3, e1: Vec3, e2: Vec3) {
        for a in 0..3 {
            self.p0[a][lane] = p0[a];
            self.e1[a][lane] = e1[a];
            self.e2[a][lane] = e2[a];
        }
    }

    /// The triangle in lane `lane` as (corner, edge 1, edge 2).
    pub fn get(&self, lane: usize) -> (Vec3, Vec3, Vec3) {
        let v = |w: &[Vec4; 3]| Vec3::new(w[0][lane], w[1][lane], w[2][lane]);
        (v(&self.p0), v(&self.e1), v(&self.e2))
    }

    /// Hit distances on every lane and which lanes are hit in (0, `t_max`).
    #[inline(always)]
    fn hits(&self, r: &Ray4, t_max: f32) -> (Vec4, BVec4A) {
        let pvec = cross(&r.d, &self.e2);
        let det = dot(&self.e1, &pvec);
        let inv = Vec4::ONE / det;
        let tvec = [r.o[0] - self.p0[0], r.o[1] - self.p0[1], r.o[2] - self.p0[2]];
        let u = dot(&tvec, &pvec) * inv;
        let qvec = cross(&tvec, &self.e1);
        let v = dot(&r.d, &qvec) * inv;
        let t = dot(&self.e2, &qvec) * inv;
        // Comparisons with a NaN (degenerate lanes: det = 0) are false, so those lanes miss.
        let ok = det.cmpne(Vec4::ZERO)
            & u.cmpge(Vec4::ZERO)
            & u.cmple(Vec4::ONE)
            & v.cmpge(Vec4::ZERO)
            & (u + v).cmple(Vec4::ONE)
            & t.cmpgt(Vec4::ZERO)
            & t.cmplt(Vec4::splat(t_max));
        (t, ok)
    }

    /// The nearest lane hit in (0, `t_max`) and its distance; on equal distances the lowest lane.
    #[inline(always)]
    pub fn closest(&self, r: &Ray4, t_max: f32) -> Option<(usize, f32)> {
        let (t, ok) = self.hits(r, t_max);
        let mask = ok.bitmask();
        if mask == 0 {
            return None;
        }
        if mask & (mask - 1) == 0 {
            let lane = mask.trailing_zeros() as usize;
            return Some((lane, t[lane]));
        }
        let masked = Vec4::select(ok, t, Vec4::INFINITY);
        let best = masked.min_element();
        let lane = (masked.cmpeq(Vec4::splat(best)).bitmask() & mask).trailing_zeros() as usize;
        Some((lane, best))
    }

    /// True when some lane is hit in (0, `t_max`).
    #[inline(always)]
    pub fn any(&self, r: &Ray4, t_max: f32) -> bool {
        self.hits(r, t_max).1.any()
    }
}

impl Tri4 {
    /// The triangle in lane `lane` against the sixteen rays of `p`: hit distances and the
    /// lanes hit in (0, `t_max`), each computed as the scalar test computes it.
    #[inline(always)]
    pub fn hits_packet(&self, lane: usize, p: &RayPacket, t_max: &F16) -> (F16, M16) {
        let s = |w: &[Vec4; 3]| [F16::splat(w[0][lane]), F16::splat(w[1][lane]), F16::splat(w[2][lane])];
        let (p0, e1, e2) = (s(&self.p0), s(&self.e1), s(&self.e2));
        let pvec = cross(&p.d, &e2);
        let det = dot(&e1, &pvec);
        let inv = F16::splat(1.0) / det;
        let tvec = [p.o[0] - p0[0], p.o[1] - p0[1], p.o[2] - p0[2]];
        let u = dot(&tvec, &pvec) * inv;
        let qvec = cross(&tvec, &e1);
        let v = dot(&p.d, &qvec) * inv;
        let t = dot(&e2, &qvec) * inv;
        let (zero, one) = (F16::splat(0.0), F16::splat(1.0));
        let ok = det.ne(zero).and(u.ge(zero)).and(u.le(one)).and(v.ge(zero)).and((u + v).le(one));
        let ok = ok.and(t.gt(zero)).and(t.lt(*t_max));
        (t, ok)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::Sampler;
    use crate::shape::mesh::intersect_triangle;

    #[test]
    fn lanes_agree_bit_for_bit_with_the_scalar_test() {
        let mut s = Sampler::new(5, 0, 0);
        let mut v = |scale: f32| Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 2.0 * scale - Vec3::splat(scale);
        let (mut hits, mut multi) = (0, 0);
        for i in 0..20_000 {
            let mut pack = Tri4::default();
            let mut tris = [(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO); 4];
            // Every 7th pack leaves lane 3 empty (the padding of a short leaf).
            let used = if i % 7 == 0 { 3 } else { 4 };
            for (lane, tri) in tris.iter_mut().enumerate().take(used) {
                *tri = (v(1.0), v(1.5), v(1.5));
                if i % 11 == 0 && lane == 1 {
                    tri.2 = tri.1 * 2.0; // degenerate: collinear edges
                }
                pack.set(lane, tri.0, tri.1, tri.2);
                assert_eq!(pack.get(lane), *tri);
            }
            // Rays aimed near the first triangle, so that hits and multiple hits are common.
            let o = v(4.0);
            let d = tris[0].0 + (tris[0].1 + tris[0].2) * 0.3 + v(0.5) - o;
            let t_max = if i % 3 == 0 { 3.0 } else { f32::INFINITY };
            let r = Ray4::new(o, d);
            let (t, ok) = pack.hits(&r, t_max);
            let mask = ok.bitmask();
            let mut best: Option<(usize, f32)> = None;
            for (lane, &(p0, e1, e2)) in tris.iter().enumerate() {
                let scalar = intersect_triangle(o, d, t_max, p0, e1, e2).map(|h| h.0);
                assert_eq!(scalar.is_some(), mask & (1 << lane) != 0, "lane {lane} of pack {i}");
                if let Some(ts) = scalar {
                    assert_eq!(ts.to_bits(), t[lane].to_bits());
                    if best.is_none_or(|b| ts < b.1) {
                        best = Some((lane, ts));
                    }
                }
            }
            hits += (mask != 0) as usize;
            multi += (mask.count_ones() > 1) as usize;
            assert_eq!(pack.closest(&r, t_max), best);
            assert_eq!(pack.any(&r, t_max), best.is_some());
        }
        assert!(hits > 2000 && multi > 200, "{hits} packs hit, {multi} more than once");
    }
}
