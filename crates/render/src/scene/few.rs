//! Scenes of a few primitives, which rays test without a BVH: the triangles sixteen at a time
//! (a [`Tri16`] per sixteen, filled in BVH order), the spheres four at a time in SIMD lanes,
//! each lane doing the operations of [`Sphere::intersect`] in its order (so the same
//! distances bit for bit), the flat shapes one by one, their tests inlined. On equal distances
//! the primitive tested first stays: triangles before spheres before the rest, and lower BVH
//! order first.

use super::Scene;
use crate::bvh::{Ray16, Tri16};
use crate::ray::Ray;
use crate::shape::{Disk, Rectangle, Sphere};
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
    /// A triangle as a corner and two edges.
    Triangle(Vec3, Vec3, Vec3),
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
#[derive(Clone, Debug, Default)]
pub(super) struct Few {
    /// Each pack with its lanes' BVH-ordered primitives (`u32::MAX` when unused).
    triangles: Vec<(Tri16, [u32; LANES])>,
    spheres: Vec<Sphere4>,
    /// Each with its BVH-ordered primitive.
    flats: Vec<(u32, Flat)>,
}

impl Few {
    /// Whether it holds no triangle: then no BVH query beats testing each primitive, not even
    /// for a packet (a few triangles are still walked as packets, which coherent rays share).
    pub fn analytic_only(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Over `n` BVH-ordered primitives, `prim(k)` giving each.
    pub fn new(n: usize, prim: impl Fn(usize) -> Prim) -> Few {
        let mut few = Few::default();
        let mut spheres: Vec<(u32, Sphere)> = Vec::new();
        let mut lane = LANES;
        for k in 0..n {
            match prim(k) {
                Prim::Triangle(p0, e1, e2) => {
                    if lane == LANES {
                        few.triangles.push((Tri16::default(), [u32::MAX; LANES]));
                        lane = 0;
                    }
                    let (pack, prims) = few.triangles.last_mut().expect("a pack was just pushed");
                    pack.set(lane, p0, e1, e2);
                    prims[lane] = k as u32;
                    lane += 1;
                }
                Prim::Sphere(s) => spheres.push((k as u32, s)),
                Prim::Flat(f) => few.flats.push((k as u32, f)),
            }
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

impl Scene {
    /// [`intersect_t`](Self::intersect_t) in a few-primitive scene.
    #[inline(always)]
    pub(super) fn intersect_t_few<const AVX: bool>(&self, few: &Few, ray: &Ray) -> Option<(usize, f32)> {
        let mut best: Option<(usize, f32)> = None;
        let mut t_max = ray.t_max;
        if !few.triangles.is_empty() {
            let r16 = Ray16::new(ray.o, ray.d);
            for (pack, prims) in &few.triangles {
                if let Some((lane, t)) = pack.closest::<AVX>(&r16, t_max) {
                    t_max = t;
                    best = Some((prims[lane] as usize, t));
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
            let r16 = Ray16::new(ray.o, ray.d);
            // Loops, not `Iterator::any`: a closure's body would not be compiled for the set.
            for (pack, _) in &few.triangles {
                if pack.any::<AVX>(&r16, ray.t_max) {
                    return true;
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
