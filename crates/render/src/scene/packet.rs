//! Ray queries sixteen at a time: closest hits and shadow tests of a packet walk the BVH
//! together ([`Bvh::walk_packet`](crate::bvh::Bvh)), triangles tested against all live rays at
//! once; other primitives, and scenes without a BVH, are tested ray by ray. Each ray gets the
//! answer the single-ray query gives it: the same distances bit for bit, and on exactly equal
//! distances possibly another of the tied primitives.

use super::Scene;
use crate::bvh::{PacketLeaf, Ray16, RayPacket};
use crate::ray::Ray;
use crate::simd::{dispatch, for_bits, Simd, F16, LANES, M16};
use std::ops::Range;

/// The closest hit of each lane, as (BVH-ordered primitive, distance).
pub type PacketHits = [Option<(usize, f32)>; LANES];

/// Fewer rays than this are traced one by one even when they are coherent: a packet's walk
/// costs about as much for a few rays as for sixteen. (The sixteen-lane tracer's camera
/// refills as packets took the packet walk's share of the Cornell box from 4 % to 11 % (perf);
/// the shadow tests a packet of paths leaves at its end, four to six, went as packets too.)
pub(crate) const PACKET_MIN: u32 = 8;

/// One to sixteen rays as a packet query's lanes and active mask (unused lanes copy the first).
///
/// # Panics
/// With no ray, or more than sixteen.
pub fn lanes_of(rays: &[Ray]) -> ([Ray; LANES], u32) {
    assert!((1..=LANES).contains(&rays.len()), "{} rays for a packet of {LANES}", rays.len());
    let mut lanes = [rays[0]; LANES];
    lanes[..rays.len()].copy_from_slice(rays);
    (lanes, (1u32 << rays.len()) - 1)
}

impl Scene {
    /// The closest hits of the rays `active` selects, as [`intersect_t`](Self::intersect_t)
    /// finds them: as a packet on the instruction set `simd` when the rays are coherent (they
    /// point into at most two octants) in a scene with a BVH, else one at a time.
    pub fn intersect_t_packet(&self, rays: &[Ray; LANES], active: u32, simd: Simd) -> PacketHits {
        if self.few.is_some() || !coherent(rays, active) {
            return self.intersect_t_packet_as(rays, active, Simd::Scalar);
        }
        self.intersect_t_packet_as(rays, active, simd)
    }

    /// [`intersect_t_packet`](Self::intersect_t_packet) as a packet even when the rays are
    /// incoherent (one at a time only for `Scalar` and scenes of a few primitives, whose single
    /// tests skip the packs a ray does not reach: Cornell box, fewer instructions and less time
    /// than the packet walk).
    pub(crate) fn intersect_t_packet_as(&self, rays: &[Ray; LANES], active: u32, simd: Simd) -> PacketHits {
        if simd == Simd::Scalar || self.few.is_some() {
            return std::array::from_fn(|i| if active >> i & 1 != 0 { self.intersect_t(&rays[i]) } else { None });
        }
        dispatch!(simd, self: Scene, closest_packet::<AVX>(rays: &[Ray; LANES], active: u32) -> PacketHits)
    }

    /// The lanes of `active` whose rays are blocked, as [`occluded_but`](Self::occluded_but)
    /// with `skip[i]` for lane i says; a packet when the rays are coherent, as above.
    pub fn occluded_packet(&self, rays: &[Ray; LANES], skip: &[Option<u32>; LANES], active: u32, simd: Simd) -> u32 {
        if self.few.is_some() || !coherent(rays, active) {
            return self.occluded_packet_as(rays, skip, active, Simd::Scalar);
        }
        self.occluded_packet_as(rays, skip, active, simd)
    }

    /// [`occluded_packet`](Self::occluded_packet) as a packet even when the rays are incoherent.
    pub(crate) fn occluded_packet_as(
        &self,
        rays: &[Ray; LANES],
        skip: &[Option<u32>; LANES],
        active: u32,
        simd: Simd,
    ) -> u32 {
        if simd == Simd::Scalar || self.few.is_some() {
            let mut m = 0;
            for_bits(active, |i| m |= (self.occluded_but(&rays[i], skip[i]) as u32) << i);
            return m;
        }
        dispatch!(simd, self: Scene, any_packet::<AVX>(rays: &[Ray; LANES], skip: &[Option<u32>; LANES], active: u32) -> u32)
    }

    #[inline(always)]
    fn closest_packet<const AVX: bool>(&self, rays: &[Ray; LANES], active: u32) -> PacketHits {
        let p = RayPacket::new(rays, active);
        let mut t_max = p.t_max;
        let mut leaf = Closest::<AVX> { scene: self, p: &p, rays, best: [u32::MAX; LANES] };
        self.bvh.walk_packet::<false>(&p, &mut t_max, M16::from_bits(active), &mut leaf);
        std::array::from_fn(|i| (leaf.best[i] != u32::MAX).then(|| (leaf.best[i] as usize, t_max.0[i])))
    }

    #[inline(always)]
    fn any_packet<const AVX: bool>(&self, rays: &[Ray; LANES], skip: &[Option<u32>; LANES], active: u32) -> u32 {
        let p = RayPacket::new(rays, active);
        let mut t_max = p.t_max;
        self.bvh
            .walk_packet::<true>(
                &p,
                &mut t_max,
                M16::from_bits(active),
                &mut Any::<AVX> { scene: self, p: &p, rays, skip },
            )
            .bits_in::<AVX>()
    }
}

/// Whether the rays of `active` are at least [`PACKET_MIN`] and point into at most two
/// octants: the cheap sign of rays coherent enough to share their nodes (a pixel's camera
/// samples, shadow rays from nearby points to one or two lights). Incoherent packets (random
/// bounces) would visit the union of their rays' nodes at sixteen lanes each, slower than one
/// ray at a time (`cargo bench -p render --bench bvh`: 1.9 against 3.5 Mrays/s for random
/// rays), so they are traced singly.
#[inline]
fn coherent(rays: &[Ray; LANES], active: u32) -> bool {
    if active.count_ones() < PACKET_MIN {
        return false;
    }
    let mut octants = 0u8;
    for_bits(active, |i| {
        let d = rays[i].d;
        octants |= 1 << ((d.x < 0.0) as u8 | ((d.y < 0.0) as u8) << 1 | ((d.z < 0.0) as u8) << 2);
    });
    octants.count_ones() <= 2
}

/// Whether a pack of `triangles` is tested faster ray by ray, all its triangles at once, than
/// triangle by triangle against the live rays `live` at once: when the rays are fewer. Both give
/// every (ray, triangle) pair the same operations, and the same nearest hit on ties (lowest lane).
#[inline(always)]
fn fewer_rays<const AVX: bool>(live: M16, triangles: usize) -> bool {
    (live.bits_in::<AVX>().count_ones() as usize) < triangles
}

/// The closest-hit leaf test: the BVH-ordered primitive each lane hits nearest so far. `AVX`:
/// compiled for AVX2 or AVX-512.
struct Closest<'a, const AVX: bool> {
    scene: &'a Scene,
    p: &'a RayPacket,
    rays: &'a [Ray; LANES],
    best: [u32; LANES],
}

impl<const AVX: bool> PacketLeaf for Closest<'_, AVX> {
    #[inline(always)]
    fn leaf(&mut self, packs: Range<usize>, lanes: M16, t_max: &mut F16) -> M16 {
        let s = self.scene;
        for pk in packs {
            let others = if s.others.is_empty() { 0 } else { s.others[pk] };
            let ks = s.bvh.pack(pk);
            if others == 0 && fewer_rays::<AVX>(lanes, ks.len()) {
                // A loop, not `for_bits`: a closure's body would not be compiled for the set.
                let mut m = lanes.bits_in::<AVX>();
                while m != 0 {
                    let i = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let r = &self.rays[i];
                    if let Some((lane, t)) = s.tri16[pk].closest::<AVX>(&Ray16::new(r.o, r.d), t_max.0[i]) {
                        t_max.0[i] = t;
                        self.best[i] = (ks.start + lane) as u32;
                    }
                }
                continue;
            }
            for (lane, k) in ks.enumerate() {
                if others & (1 << lane) == 0 {
                    let (t, hit) = s.tri16[pk].hits_packet(lane, self.p, t_max);
                    let hit = hit.and(lanes);
                    *t_max = t_max.blend(hit, t);
                    self.best = hit.select_u32([k as u32; LANES], self.best);
                } else {
                    for_bits(lanes.bits_in::<AVX>(), |i| {
                        let r = &self.rays[i];
                        if let Some(t) = s.intersect_prim(k, r.o, r.d, t_max.0[i]) {
                            t_max.0[i] = t;
                            self.best[i] = k as u32;
                        }
                    });
                }
            }
        }
        M16::NONE
    }
}

/// The any-hit leaf test; lane i does not count the analytic primitives of shape `skip[i]`.
struct Any<'a, const AVX: bool> {
    scene: &'a Scene,
    p: &'a RayPacket,
    rays: &'a [Ray; LANES],
    skip: &'a [Option<u32>; LANES],
}

impl<const AVX: bool> PacketLeaf for Any<'_, AVX> {
    #[inline(always)]
    fn leaf(&mut self, packs: Range<usize>, lanes: M16, t_max: &mut F16) -> M16 {
        let s = self.scene;
        let mut blocked = M16::NONE;
        for pk in packs {
            let others = if s.others.is_empty() { 0 } else { s.others[pk] };
            let ks = s.bvh.pack(pk);
            if others == 0 && fewer_rays::<AVX>(lanes.and_not(blocked), ks.len()) {
                let (mut b, mut m) = (blocked.bits_in::<AVX>(), lanes.and_not(blocked).bits_in::<AVX>());
                while m != 0 {
                    let i = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let r = &self.rays[i];
                    b |= (s.tri16[pk].any::<AVX>(&Ray16::new(r.o, r.d), t_max.0[i]) as u32) << i;
                }
                blocked = M16::from_bits(b);
                if !lanes.and_not(blocked).any_in::<AVX>() {
                    return blocked;
                }
                continue;
            }
            for (lane, k) in ks.enumerate() {
                if others & (1 << lane) == 0 {
                    blocked = blocked.or(s.tri16[pk].hits_packet(lane, self.p, t_max).1.and(lanes));
                } else {
                    let shape = s.refs[k].0;
                    let mut b = blocked.bits_in::<AVX>();
                    for_bits(lanes.and_not(blocked).bits_in::<AVX>(), |i| {
                        if self.skip[i] != Some(shape) {
                            let r = &self.rays[i];
                            b |= (s.intersect_prim(k, r.o, r.d, t_max.0[i]).is_some() as u32) << i;
                        }
                    });
                    blocked = M16::from_bits(b);
                }
                if !lanes.and_not(blocked).any_in::<AVX>() {
                    return blocked;
                }
            }
        }
        blocked
    }
}
