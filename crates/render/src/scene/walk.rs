//! The single-ray queries through the BVH: closest hit and any hit, their leaf tests written as
//! [`Leaf`] methods so that the whole walk compiles into each instruction set's copy
//! (`simd::dispatch!`). A pack's triangles are tested at once ([`Tri16`](crate::bvh::Tri16)),
//! on eight lanes where the pack holds at most eight (two thirds of matpreview's packs; its
//! any-hit queries 9 % faster, the closest-hit ones at most 2 %), other primitives one by one.

use super::{Scene, HAS_TRIANGLES};
use crate::bvh::{Leaf, Ray16, Visit};
use crate::ray::Ray;
use std::ops::Range;

/// The closest-hit leaf test: keeps the nearest (pack, lane, distance). `AVX`: compiled for
/// AVX2 or AVX-512.
struct Closest<'a, const AVX: bool> {
    scene: &'a Scene,
    ray: &'a Ray,
    best: Option<(usize, usize, f32)>,
}

impl<const AVX: bool> Leaf for Closest<'_, AVX> {
    #[inline(always)]
    fn leaf(&mut self, packs: Range<usize>, t_max: &mut f32) -> Visit {
        let (s, ray) = (self.scene, self.ray);
        // Splatted here, not before the walk: most rays reach few leaves, many none.
        let r16 = Ray16::new(ray.o, ray.d);
        let mixed = !s.others.is_empty();
        for p in packs {
            if !mixed || s.others[p] & HAS_TRIANGLES != 0 {
                if let Some((lane, t)) = s.tri16[p].closest_used::<AVX>(s.bvh.pack(p).len(), &r16, *t_max) {
                    *t_max = t;
                    self.best = Some((p, lane, t));
                }
            }
            if mixed {
                let k0 = s.bvh.pack(p).start;
                let mut lanes = s.others[p] & !HAS_TRIANGLES;
                while lanes != 0 {
                    let lane = lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    if let Some(t) = s.intersect_prim(k0 + lane, ray.o, ray.d, *t_max) {
                        *t_max = t;
                        self.best = Some((p, lane, t));
                    }
                }
            }
        }
        Visit::Continue
    }
}

/// The any-hit leaf test, not counting the analytic primitives of shape `skip`.
struct Any<'a, const AVX: bool> {
    scene: &'a Scene,
    ray: &'a Ray,
    skip: Option<u32>,
}

impl<const AVX: bool> Leaf for Any<'_, AVX> {
    #[inline(always)]
    fn leaf(&mut self, packs: Range<usize>, _: &mut f32) -> Visit {
        let (s, ray) = (self.scene, self.ray);
        let r16 = Ray16::new(ray.o, ray.d);
        let mixed = !s.others.is_empty();
        for p in packs {
            if (!mixed || s.others[p] & HAS_TRIANGLES != 0)
                && s.tri16[p].any_used::<AVX>(s.bvh.pack(p).len(), &r16, ray.t_max)
            {
                return Visit::Stop;
            }
            if mixed {
                let k0 = s.bvh.pack(p).start;
                let mut lanes = s.others[p] & !HAS_TRIANGLES;
                while lanes != 0 {
                    let k = k0 + lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    if self.skip != Some(s.refs[k].0) && s.intersect_prim(k, ray.o, ray.d, ray.t_max).is_some() {
                        return Visit::Stop;
                    }
                }
            }
        }
        Visit::Continue
    }
}

impl Scene {
    /// The closest hit through the BVH as (BVH-ordered primitive, distance).
    #[inline(always)]
    pub(super) fn closest_walk<const AVX: bool>(&self, ray: &Ray) -> Option<(usize, f32)> {
        let mut leaf = Closest::<AVX> { scene: self, ray, best: None };
        let mut t_max = ray.t_max;
        self.bvh.walk::<false, AVX>(ray, &mut t_max, &mut leaf);
        leaf.best.map(|(p, lane, t)| (self.bvh.pack(p).start + lane, t))
    }

    /// True when something other than shape `skip`'s analytic primitives lies along the ray.
    #[inline(always)]
    pub(super) fn any_walk<const AVX: bool>(&self, ray: &Ray, skip: Option<u32>) -> bool {
        let mut t_max = ray.t_max;
        self.bvh.walk::<true, AVX>(ray, &mut t_max, &mut Any::<AVX> { scene: self, ray, skip })
    }
}
