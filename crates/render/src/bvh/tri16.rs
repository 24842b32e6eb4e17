//! Sixteen triangles in structure-of-arrays lanes, tested against one ray at once by
//! Möller & Trumbore, "Fast, minimum storage ray/triangle intersection", JGT 1997. Each lane
//! performs exactly the operations of the scalar [`intersect_triangle`], in the same order,
//! so both give the same distances bit for bit. Sixteen lanes fill one AVX-512 register (two
//! AVX2 ones): the test's cost is mostly its chain of dependent operations, which a wider
//! register does not lengthen, so a leaf of sixteen triangles costs little more than one of four.
//!
//! [`intersect_triangle`]: crate::shape::mesh::intersect_triangle

use super::RayPacket;
use crate::simd::{cross, dot, min_lanes, F16, LANES, M16};
use glam::Vec3;

/// Triangles per pack.
pub const PACK: usize = LANES;
/// A pack of at most this many triangles is tested on half the lanes: one AVX2 register
/// instead of two (Cornell box, AVX2: 5 % fewer instructions; four lanes came out as poorer
/// code, with more).
const HALF: usize = LANES / 2;

/// Sixteen triangles as a corner and two edges, x/y/z lanes; unused lanes hold a degenerate
/// (all-zero) triangle, which no ray hits.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Tri16 {
    p0: [F16; 3],
    e1: [F16; 3],
    e2: [F16; 3],
}

impl Default for Tri16 {
    fn default() -> Self {
        let z = [F16::splat(0.0); 3];
        Tri16 { p0: z, e1: z, e2: z }
    }
}

/// A ray splatted over the lanes.
#[derive(Clone, Copy, Debug)]
pub struct Ray16 {
    o: [F16; 3],
    d: [F16; 3],
}

impl Ray16 {
    /// The ray `o + t·d` on every lane.
    #[inline(always)]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        let s = F16::splat;
        Ray16 { o: [s(o.x), s(o.y), s(o.z)], d: [s(d.x), s(d.y), s(d.z)] }
    }
}

/// The Möller–Trumbore test on the first `L` lanes (8 or 16): distances, and the lanes hit
/// in (0, `t_max`). Written as one loop over the lanes, which LLVM turns into full-width vector
/// code (of the width `L` and the instruction set ask); a chain of separate lane-array operations
/// came out as four-wide pieces with shuffles between them.
#[inline(always)]
fn hits<const L: usize>(
    o: &[F16; 3],
    d: &[F16; 3],
    p0: &[F16; 3],
    e1: &[F16; 3],
    e2: &[F16; 3],
    t_max: &F16,
) -> ([f32; L], [i32; L]) {
    let (mut t, mut ok) = ([0.0; L], [0; L]);
    for l in 0..L {
        let v3 = |w: &[F16; 3]| [w[0].0[l], w[1].0[l], w[2].0[l]];
        let (o, d, e1, e2) = (v3(o), v3(d), v3(e1), v3(e2));
        let pvec = cross(&d, &e2);
        let det = dot(&e1, &pvec);
        let inv = 1.0 / det;
        let tvec = [o[0] - p0[0].0[l], o[1] - p0[1].0[l], o[2] - p0[2].0[l]];
        let u = dot(&tvec, &pvec) * inv;
        let qvec = cross(&tvec, &e1);
        let v = dot(&d, &qvec) * inv;
        let tl = dot(&e2, &qvec) * inv;
        // Comparisons with a NaN (degenerate lanes: det = 0) are false, so those lanes miss.
        let hit = det != 0.0 && (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 && tl > 0.0 && tl < t_max.0[l];
        t[l] = tl;
        ok[l] = -(hit as i32);
    }
    (t, ok)
}

/// The bit mask (bit i: lane i) of `L` lane flags; `AVX` as for [`M16::bits_in`].
#[inline(always)]
fn lane_bits<const AVX: bool, const L: usize>(ok: &[i32; L]) -> u32 {
    if L == LANES {
        let mut m = M16::NONE;
        m.0[..L].copy_from_slice(ok);
        return m.bits_in::<AVX>();
    }
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        let mut b = 0;
        for c in 0..L / 4 {
            // SAFETY: lanes 4c..4c + 4 lie within `ok`; SSE is part of x86_64.
            b |= (unsafe { _mm_movemask_ps(_mm_loadu_ps(ok.as_ptr().add(4 * c).cast())) } as u32) << (4 * c);
        }
        b
    }
    #[cfg(not(target_arch = "x86_64"))]
    (0..L).fold(0, |b, l| b | ((ok[l] as u32) >> 31) << l)
}

/// The nearest lane hit and its distance (on equal distances the lowest lane), from the lanes'
/// distances `t` and hit mask `mask` (not empty).
#[inline(always)]
fn nearest<const L: usize>(t: &[f32; L], mut mask: u32) -> (usize, f32) {
    let best = if mask & (mask - 1) == 0 {
        t[mask.trailing_zeros() as usize]
    } else {
        min_lanes::<L>(std::array::from_fn(|l| if mask >> l & 1 != 0 { t[l] } else { f32::INFINITY }))
    };
    loop {
        let lane = mask.trailing_zeros() as usize;
        if t[lane] == best {
            return (lane, best);
        }
        mask &= mask - 1;
    }
}

impl Tri16 {
    /// Puts the triangle (corner `p0`, edges `e1`, `e2`) in lane `lane` (< 16).
    pub fn set(&mut self, lane: usize, p0: Vec3, e1: Vec3, e2: Vec3) {
        for a in 0..3 {
            self.p0[a].0[lane] = p0[a];
            self.e1[a].0[lane] = e1[a];
            self.e2[a].0[lane] = e2[a];
        }
    }

    /// The triangle in lane `lane` as (corner, edge 1, edge 2).
    pub fn get(&self, lane: usize) -> (Vec3, Vec3, Vec3) {
        let v = |w: &[F16; 3]| Vec3::new(w[0].0[lane], w[1].0[lane], w[2].0[lane]);
        (v(&self.p0), v(&self.e1), v(&self.e2))
    }

    /// Hit distances on the first `L` lanes and which are hit in (0, `t_max`).
    #[inline(always)]
    fn hits<const L: usize>(&self, r: &Ray16, t_max: f32) -> ([f32; L], [i32; L]) {
        hits::<L>(&r.o, &r.d, &self.p0, &self.e1, &self.e2, &F16::splat(t_max))
    }

    /// The nearest lane hit in (0, `t_max`) and its distance; on equal distances the lowest lane.
    /// `AVX`: in code compiled for AVX2 or AVX-512 ([`M16::bits_in`]).
    #[inline(always)]
    pub fn closest<const AVX: bool>(&self, r: &Ray16, t_max: f32) -> Option<(usize, f32)> {
        self.closest_in::<AVX, LANES>(r, t_max)
    }

    /// [`closest`](Self::closest) among the first `L` lanes (8 or 16), the others unused:
    /// narrower registers for a part-full pack.
    #[inline(always)]
    pub fn closest_in<const AVX: bool, const L: usize>(&self, r: &Ray16, t_max: f32) -> Option<(usize, f32)> {
        let (t, ok) = self.hits::<L>(r, t_max);
        let mask = lane_bits::<AVX, L>(&ok);
        (mask != 0).then(|| nearest(&t, mask))
    }

    /// [`closest`](Self::closest) for a pack whose first `used` lanes hold its triangles.
    #[inline(always)]
    pub fn closest_used<const AVX: bool>(&self, used: usize, r: &Ray16, t_max: f32) -> Option<(usize, f32)> {
        if used <= HALF {
            self.closest_in::<AVX, HALF>(r, t_max)
        } else {
            self.closest_in::<AVX, LANES>(r, t_max)
        }
    }

    /// [`any`](Self::any) for a pack whose first `used` lanes hold its triangles.
    #[inline(always)]
    pub fn any_used<const AVX: bool>(&self, used: usize, r: &Ray16, t_max: f32) -> bool {
        if used <= HALF {
            self.any_in::<AVX, HALF>(r, t_max)
        } else {
            self.any_in::<AVX, LANES>(r, t_max)
        }
    }

    /// True when some lane is hit in (0, `t_max`); `AVX` as for [`closest`](Self::closest).
    #[inline(always)]
    pub fn any<const AVX: bool>(&self, r: &Ray16, t_max: f32) -> bool {
        self.any_in::<AVX, LANES>(r, t_max)
    }

    /// [`any`](Self::any) among the first `L` lanes (8 or 16).
    #[inline(always)]
    pub fn any_in<const AVX: bool, const L: usize>(&self, r: &Ray16, t_max: f32) -> bool {
        lane_bits::<AVX, L>(&self.hits::<L>(r, t_max).1) != 0
    }

    /// The triangle in lane `lane` against the sixteen rays of `p`: hit distances and the
    /// lanes hit in (0, `t_max`), each computed as the scalar test computes it.
    #[inline(always)]
    pub fn hits_packet(&self, lane: usize, p: &RayPacket, t_max: &F16) -> (F16, M16) {
        let s = |w: &[F16; 3]| [F16::splat(w[0].0[lane]), F16::splat(w[1].0[lane]), F16::splat(w[2].0[lane])];
        let (t, ok) = hits::<LANES>(&p.o, &p.d, &s(&self.p0), &s(&self.e1), &s(&self.e2), t_max);
        (F16(t), M16(ok))
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
            let mut pack = Tri16::default();
            let mut tris = [(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO); PACK];
            // Packs are often part full (the padding of a short leaf).
            let used = [PACK, 3, 9, 1][i % 4];
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
            let r = Ray16::new(o, d);
            let (t, ok) = pack.hits::<LANES>(&r, t_max);
            let mask = M16(ok).bits();
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
            assert_eq!(pack.closest::<false>(&r, t_max), best);
            assert_eq!(pack.any::<false>(&r, t_max), best.is_some());
            // A part-full pack tested on half the lanes gives the same.
            assert_eq!(pack.closest_used::<false>(used, &r, t_max), best);
            assert_eq!(pack.any_used::<false>(used, &r, t_max), best.is_some());
        }
        assert!(hits > 2000 && multi > 200, "{hits} packs hit, {multi} more than once");
    }
}
