//! Scenes of a few primitives, which rays test without a BVH: the triangles in packs of up
//! to sixteen ([`Tri16`]), the spheres four at a time in SIMD lanes, each lane doing the
//! operations of [`Sphere::intersect`] in its order (so the same distances bit for bit), the
//! flat shapes one by one, their tests inlined. The triangle packs' boxes are tested first, all
//! at once, and a ray tests only the packs whose box it enters before its closest hit so far,
//! nearest first; the triangles are grouped so that rays leaving the scene's surfaces test few
//! packs (a room's walls alone, an object alone). On equal distances the primitive tested first
//! stays: triangles before spheres before the rest.

use super::Scene;
use crate::bvh::{Node, Ray16, RayBox, Tri16, NODE_WIDTH};
use crate::ray::Ray;
use crate::shape::{Aabb, Disk, Rectangle, Sphere};
use crate::simd::{dot, LANES};
use glam::{BVec4A, Vec3, Vec4};

/// Four spheres as centre and squared-radius lanes; an unused lane has r² = −1, which no ray
/// meets.
#[derive(Clone, Copy, Debug)]
struct Sphere4 {
    c: [Vec4; 3],
    r2: Vec4,
    /// The BVH-ordered primitive of each lane (`u32::MAX` when unused).
    prim: [u32; 4],
}

impl Sphere4 {
    /// Hit distances in (0, `t_max`) on every lane, and which lanes hit.
    #[inline(always)]
    fn hits(&self, ray: &Ray, t_max: f32) -> (Vec4, BVec4A) {
        let s = Vec4::splat;
        let (o, d) = ([s(ray.o.x), s(ray.o.y), s(ray.o.z)], [s(ray.d.x), s(ray.d.y), s(ray.d.z)]);
        let f = [o[0] - self.c[0], o[1] - self.c[1], o[2] - self.c[2]];
        let b = -dot(&f, &d);
        let l = [f[0] + b * d[0], f[1] + b * d[1], f[2] + b * d[2]];
        let disc = self.r2 - dot(&l, &l);
        let c = dot(&f, &f) - self.r2;
        let q = b + Vec4::from_array(disc.to_array().map(f32::sqrt)).copysign(b);
        let zero_q = q.cmpeq(Vec4::ZERO);
        let t0 = Vec4::select(zero_q, Vec4::ZERO, c / q);
        let t1 = Vec4::select(zero_q, Vec4::ZERO, q);
        let swap = t0.cmpgt(t1);
        let (t0, t1) = (Vec4::select(swap, t1, t0), Vec4::select(swap, t0, t1));
        let tm = s(t_max);
        let ok0 = t0.cmpgt(Vec4::ZERO) & t0.cmplt(tm);
        let ok1 = t1.cmpgt(Vec4::ZERO) & t1.cmplt(tm);
        // disc ≥ 0 is false for NaN, as the scalar test's `disc.is_nan() || disc < 0` rejects.
        (Vec4::select(ok0, t0, t1), disc.cmpge(Vec4::ZERO) & (ok0 | ok1))
    }
}

/// A primitive of a few-primitive scene, as [`Few::new`] is handed it.
pub(super) enum Prim {
    /// A triangle of shape `.0` as a corner and two edges.
    Triangle(u32, Vec3, Vec3, Vec3),
    Sphere(Sphere),
    Flat(Flat),
}

/// A shape tested on its own.
#[derive(Clone, Copy, Debug)]
pub(super) enum Flat {
    Rectangle(Rectangle),
    Disk(Disk),
}

impl Flat {
    #[inline(always)]
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        match self {
            Flat::Rectangle(r) => r.intersect(ray.o, ray.d, t_max),
            Flat::Disk(d) => d.intersect(ray.o, ray.d, t_max),
        }
    }
}

/// The triangles of a few-primitive scene in packs of sixteen, its spheres in packs of four,
/// and its flat shapes.
#[derive(Clone, Debug)]
pub(super) struct Few {
    /// Each pack with its lanes' BVH-ordered primitives (`u32::MAX` when unused) and the
    /// number of lanes used (the first ones).
    triangles: Vec<(Tri16, [u32; LANES], usize)>,
    /// The triangle packs' boxes, pack `i` in lane `i`: a ray tests only the packs whose box it
    /// enters before its closest hit so far.
    boxes: Node,
    spheres: Vec<Sphere4>,
    /// Each with its BVH-ordered primitive.
    flats: Vec<(u32, Flat)>,
}

impl Few {
    /// Over `n` BVH-ordered primitives, `prim(k)` giving each.
    pub fn new(n: usize, prim: impl Fn(usize) -> Prim) -> Few {
        let mut few = Few { triangles: Vec::new(), boxes: Node::EMPTY, spheres: Vec::new(), flats: Vec::new() };
        let mut spheres: Vec<(u32, Sphere)> = Vec::new();
        // (shape, primitive, corner, edges, box)
        let mut triangles = Vec::new();
        for k in 0..n {
            match prim(k) {
                Prim::Triangle(shape, p0, e1, e2) => {
                    // The box widened by a little more than the rounding of p0 + e: the test
                    // meets the triangle of p0 and its exact edges.
                    let bounds = [p0, p0 + e1, p0 + e2].iter().fold(Aabb::EMPTY, |b, &c| {
                        let pad = c.abs() * 2.0 * f32::EPSILON;
                        b.grow(c - pad).grow(c + pad)
                    });
                    triangles.push((shape, k as u32, p0, e1, e2, bounds));
                }
                Prim::Sphere(s) => spheres.push((k as u32, s)),
                Prim::Flat(f) => few.flats.push((k as u32, f)),
            }
        }
        // Packs of consecutive triangles in shape order (BVH order within a shape), cut where
        // rays leaving the surfaces test the fewest packs.
        triangles.sort_by_key(|t| (t.0, t.1));
        let bounds: Vec<Aabb> = triangles.iter().map(|t| t.5).collect();
        let cuts = cheapest_cuts(&triangles.iter().map(|t| (t.2, t.3, t.4)).collect::<Vec<_>>(), &bounds, NODE_WIDTH);
        for (i, pack_range) in cuts.windows(2).enumerate() {
            let mut pack = (Tri16::default(), [u32::MAX; LANES], pack_range[1] - pack_range[0]);
            let mut bounds = Aabb::EMPTY;
            for (lane, &(_, k, p0, e1, e2, b)) in triangles[pack_range[0]..pack_range[1]].iter().enumerate() {
                pack.0.set(lane, p0, e1, e2);
                pack.1[lane] = k;
                bounds = bounds.union(b);
            }
            for a in 0..3 {
                few.boxes.b[0][a][i] = bounds.min[a];
                few.boxes.b[1][a][i] = bounds.max[a];
            }
            few.triangles.push(pack);
        }
        for chunk in spheres.chunks(4) {
            let mut pack = Sphere4 { c: [Vec4::ZERO; 3], r2: Vec4::splat(-1.0), prim: [u32::MAX; 4] };
            for (lane, (k, s)) in chunk.iter().enumerate() {
                for a in 0..3 {
                    pack.c[a][lane] = s.center[a];
                }
                pack.r2[lane] = s.radius * s.radius;
                pack.prim[lane] = *k;
            }
            few.spheres.push(pack);
        }
        few
    }
}

/// Rays that score a grouping of triangles into packs.
const SCORE_RAYS: u64 = 512;
/// Where a scoring shadow ray ends, as a fraction of the distance to the surface it aims at.
const SHADOW_END: f32 = 0.999;

/// Where to cut a run of triangles (corner, edges; `bounds` their boxes) into at most
/// `max_packs` packs of consecutive triangles, at most [`LANES`] each: the cut points, from 0 to
/// the count. The cost of a grouping is how many packs rays leaving the surfaces would test,
/// nearest first: a ray tests a pack when it enters its box before its first hit, and so does
/// a shadow ray stopping short of that hit. The rays start at points spread over the triangles
/// by area, in directions uniform over the sphere (a fixed seed); the least cost is found by
/// dynamic programming over (packs used, triangles covered).
///
/// # Panics
/// When `max_packs` packs cannot hold them all.
fn cheapest_cuts(tris: &[(Vec3, Vec3, Vec3)], bounds: &[Aabb], max_packs: usize) -> Vec<usize> {
    let n = tris.len();
    assert!(n <= max_packs * LANES, "{n} triangles do not fit {max_packs} packs");
    if n == 0 {
        return vec![0];
    }
    let area: Vec<f32> = tris.iter().map(|(_, e1, e2)| e1.cross(*e2).length()).collect();
    let choose = radiometry::distribution::Distribution1D::new(&area);
    let mut sampler = crate::sampler::Sampler::new(0, 0, 0);
    let mut rays = Vec::new();
    for _ in 0..SCORE_RAYS {
        let (k, u, w) = (choose.cell(sampler.next_1d()), sampler.next_2d(), sampler.next_2d());
        let (p0, e1, e2) = tris[k];
        let b = radiometry::warp::uniform_triangle(u);
        let o = p0 + e1 * b.x + e2 * b.y;
        let d = radiometry::warp::uniform_sphere(w);
        let end = (0..n)
            .filter(|&j| j != k)
            .filter_map(|j| {
                crate::shape::mesh::intersect_triangle(o, d, f32::INFINITY, tris[j].0, tris[j].1, tris[j].2)
            })
            .fold(f32::INFINITY, |t, h| t.min(h.0));
        rays.push((o, d.recip(), end));
    }
    let enters = |b: &Aabb| {
        let mut count = 0;
        for (o, inv, end) in &rays {
            let (t0, t1) = ((b.min - *o) * *inv, (b.max - *o) * *inv);
            let near = t0.min(t1).max_element().max(0.0);
            if near <= t0.max(t1).min_element() {
                count += (near <= *end) as u32 + (near < *end * SHADOW_END) as u32;
            }
        }
        count as f32
    };
    // best[c][j]: the least cost of c packs holding the first j triangles, and the last cut.
    let mut best = vec![vec![(f32::INFINITY, 0usize); n + 1]; max_packs + 1];
    best[0][0] = (0.0, 0);
    let mut cost = vec![[0.0f32; LANES + 1]; n + 1];
    for j in 1..=n {
        let mut b = Aabb::EMPTY;
        for i in (j.saturating_sub(LANES)..j).rev() {
            b = b.union(bounds[i]);
            cost[j][j - i] = enters(&b);
        }
    }
    for c in 1..=max_packs {
        for j in 1..=n {
            for i in j.saturating_sub(LANES)..j {
                let total = best[c - 1][i].0 + cost[j][j - i];
                if total < best[c][j].0 {
                    best[c][j] = (total, i);
                }
            }
        }
    }
    let packs = (1..=max_packs).min_by(|&a, &b| best[a][n].0.total_cmp(&best[b][n].0)).unwrap_or(0);
    let mut cuts = vec![n];
    let mut j = n;
    for c in (1..=packs).rev() {
        j = best[c][j].1;
        cuts.push(j);
    }
    cuts.reverse();
    cuts
}

impl Scene {
    /// [`intersect_t`](Self::intersect_t) in a few-primitive scene.
    #[inline(always)]
    pub(super) fn intersect_t_few<const AVX: bool>(&self, few: &Few, ray: &Ray) -> Option<(usize, f32)> {
        let mut best: Option<(usize, f32)> = None;
        let mut t_max = ray.t_max;
        if !few.triangles.is_empty() {
            let (entry, mut packs) = RayBox::new(ray).hit::<AVX>(&few.boxes, t_max);
            if packs != 0 {
                let r16 = Ray16::new(ray.o, ray.d);
                while packs != 0 {
                    let mut i = packs.trailing_zeros() as usize;
                    let mut rest = packs & (packs - 1);
                    while rest != 0 {
                        let j = rest.trailing_zeros() as usize;
                        rest &= rest - 1;
                        if entry[j] < entry[i] {
                            i = j;
                        }
                    }
                    packs &= !(1 << i);
                    if entry[i] > t_max {
                        break;
                    }
                    let (pack, prims, used) = &few.triangles[i];
                    if let Some((lane, t)) = pack.closest_used::<AVX>(*used, &r16, t_max) {
                        t_max = t;
                        best = Some((prims[lane] as usize, t));
                    }
                }
            }
        }
        for pack in &few.spheres {
            let (t, ok) = pack.hits(ray, t_max);
            let mut mask = ok.bitmask();
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if t[lane] < t_max {
                    t_max = t[lane];
                    best = Some((pack.prim[lane] as usize, t_max));
                }
            }
        }
        for (k, flat) in &few.flats {
            if let Some(t) = flat.intersect(ray, t_max) {
                t_max = t;
                best = Some((*k as usize, t));
            }
        }
        best
    }

    /// [`occluded_but`](Self::occluded_but) in a few-primitive scene (triangles always count).
    #[inline(always)]
    pub(super) fn occluded_few<const AVX: bool>(&self, few: &Few, ray: &Ray, skip: Option<u32>) -> bool {
        if !few.triangles.is_empty() {
            let mut packs = RayBox::new(ray).hit::<AVX>(&few.boxes, ray.t_max).1;
            if packs != 0 {
                let r16 = Ray16::new(ray.o, ray.d);
                // Loops, not `Iterator::any`: a closure's body would not be compiled for the set.
                while packs != 0 {
                    let i = packs.trailing_zeros() as usize;
                    packs &= packs - 1;
                    let (pack, _, used) = &few.triangles[i];
                    if pack.any_used::<AVX>(*used, &r16, ray.t_max) {
                        return true;
                    }
                }
            }
        }
        let counts = |k: usize| skip != Some(self.refs[k].0);
        for pack in &few.spheres {
            let mut mask = pack.hits(ray, ray.t_max).1.bitmask();
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if counts(pack.prim[lane] as usize) {
                    return true;
                }
            }
        }
        for (k, flat) in &few.flats {
            if counts(*k as usize) && flat.intersect(ray, ray.t_max).is_some() {
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bounds(tris: &[(Vec3, Vec3, Vec3)]) -> Vec<Aabb> {
        tris.iter().map(|&(p0, e1, e2)| Aabb::EMPTY.grow(p0).grow(p0 + e1).grow(p0 + e2)).collect()
    }

    /// The twelve triangles of the box from `lo` to `hi`.
    fn cube(lo: Vec3, hi: Vec3) -> Vec<(Vec3, Vec3, Vec3)> {
        let mut out = Vec::new();
        for a in 0..3 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            for side in [lo[a], hi[a]] {
                let mut p0 = lo;
                p0[a] = side;
                let (mut eb, mut ec) = (Vec3::ZERO, Vec3::ZERO);
                eb[b] = hi[b] - lo[b];
                ec[c] = hi[c] - lo[c];
                out.push((p0, eb, ec));
                out.push((p0 + eb + ec, -eb, -ec));
            }
        }
        out
    }

    #[test]
    fn the_boxes_in_a_room_never_share_a_pack() {
        // A Cornell-box-like room and two boxes standing in it, in shape order: a pack holding
        // both boxes would be tested by every ray passing between them.
        let mut tris = cube(Vec3::ZERO, Vec3::splat(10.0));
        tris.extend(cube(Vec3::new(1.0, 0.0, 1.0), Vec3::new(4.0, 6.0, 4.0)));
        tris.extend(cube(Vec3::new(6.0, 0.0, 5.0), Vec3::new(9.0, 3.0, 8.0)));
        let cuts = cheapest_cuts(&tris, &bounds(&tris), NODE_WIDTH);
        assert!(cuts.windows(2).all(|w| w[0] >= 24 || w[1] <= 24), "{cuts:?}");
        // Without the room, the two boxes are the two packs.
        let boxes = &tris[12..];
        assert_eq!(cheapest_cuts(boxes, &bounds(boxes), NODE_WIDTH), vec![0, 12, 24]);
    }

    #[test]
    fn cuts_cover_every_triangle_in_packs_that_fit() {
        let mut s = crate::sampler::Sampler::new(3, 0, 0);
        let mut v = |scale: f32| (Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) - 0.5) * scale;
        for n in [0, 1, 16, 17, 40, 64] {
            let tris: Vec<_> = (0..n).map(|_| (v(10.0), v(2.0), v(2.0))).collect();
            let cuts = cheapest_cuts(&tris, &bounds(&tris), 4);
            assert_eq!((cuts[0], *cuts.last().unwrap()), (0, n), "{cuts:?}");
            assert!(cuts.len() - 1 <= 4 && cuts.windows(2).all(|w| w[0] < w[1] && w[1] - w[0] <= LANES) || n == 0);
        }
    }
}
