//! Four-wide nodes and the ray's test against their four child boxes at once: the slab
//! test (Kay & Kajiya 1986) on SIMD lanes, the near and far planes chosen once per ray by
//! the direction's signs (Williams et al., "An efficient and robust ray-box intersection
//! algorithm", JGT 2005), with the far distances enlarged by 2γ₃ so that rounding never
//! loses a box the ray touches (Pharr, Jakob & Humphreys, pbrt-v4, §6.8.2).

use crate::ray::Ray;
use glam::{Vec3A, Vec4};

/// A child reference with this bit set is a leaf: its low bits give the first pack and the
/// pack count minus one (see [`leaf_ref`]); otherwise it is a node index.
pub(super) const LEAF: u32 = 1 << 31;
/// Bits of a leaf reference that hold its pack count minus one.
const COUNT_BITS: u32 = 3;
/// The most packs one leaf reference can name.
pub(super) const MAX_LEAF_PACKS: usize = 1 << COUNT_BITS;
/// The most packs a hierarchy can hold.
pub(super) const MAX_PACKS: usize = 1 << (31 - COUNT_BITS);

/// The reference of a leaf holding packs `first..first + count` (1 ≤ count ≤ [`MAX_LEAF_PACKS`]).
#[inline]
pub(super) fn leaf_ref(first: usize, count: usize) -> u32 {
    debug_assert!(first < MAX_PACKS && (1..=MAX_LEAF_PACKS).contains(&count));
    LEAF | (first as u32) << COUNT_BITS | (count as u32 - 1)
}

/// The pack range a leaf reference names.
#[inline]
pub(super) fn leaf_packs(r: u32) -> std::ops::Range<usize> {
    let first = ((r & !LEAF) >> COUNT_BITS) as usize;
    first..first + (r & (MAX_LEAF_PACKS as u32 - 1)) as usize + 1
}

/// A node: four child boxes as structure-of-arrays lanes, and the four children. Two
/// cache lines.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Node4 {
    /// `b[0]` lower and `b[1]` upper corners, by axis, one child per lane; an unused lane
    /// holds the empty box (lower +∞, upper −∞), which no ray meets.
    pub b: [[Vec4; 3]; 2],
    /// Child references (node index, or [`LEAF`]-tagged pack range); unused lanes are 0.
    pub child: [u32; 4],
}

impl Node4 {
    /// A node with no children yet.
    pub const EMPTY: Node4 = Node4 { b: [[Vec4::INFINITY; 3], [Vec4::NEG_INFINITY; 3]], child: [0; 4] };
}

/// Direction components smaller than this are replaced by it (keeping the sign), so that
/// 1/d stays finite and the slab test never computes 0·∞. The ray then drifts by at most
/// 1e-20 per unit length, far below any box's rounding.
const MIN_DIRECTION: f32 = 1e-20;
/// pbrt's γ₃ = 3ε/(1 − 3ε) with ε = 2⁻²⁴, the bound on the relative error of the slab
/// distances; far distances are scaled by 1 + 2γ₃.
const FAR_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// The slab test's inverse direction, each component at least [`MIN_DIRECTION`] in size, and
/// the same scaled for far distances; single rays and packets share it.
#[inline(always)]
pub(super) fn inverse_direction(d: glam::Vec3) -> (Vec3A, Vec3A) {
    let d = Vec3A::from(d);
    let inv = d.abs().max(Vec3A::splat(MIN_DIRECTION)).copysign(d).recip();
    (inv, inv * FAR_SCALE)
}

/// A ray prepared for box tests: origin and inverse direction splatted over the lanes, and
/// which corner (0 lower, 1 upper) is the near one on each axis.
#[derive(Clone, Copy)]
pub(super) struct RayBox {
    o: [Vec4; 3],
    inv: [Vec4; 3],
    inv_far: [Vec4; 3],
    /// Bit a set when the direction's axis a is negative.
    neg: u32,
}

impl RayBox {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let (inv, far) = inverse_direction(ray.d);
        let s = Vec4::splat;
        RayBox {
            o: [s(ray.o.x), s(ray.o.y), s(ray.o.z)],
            inv: [s(inv.x), s(inv.y), s(inv.z)],
            inv_far: [s(far.x), s(far.y), s(far.z)],
            neg: inv.is_negative_bitmask(),
        }
    }

    /// Entry distances into the four child boxes, and the mask (bit i for lane i) of those
    /// the ray meets within [0, `t_max`].
    #[inline(always)]
    pub fn hit(&self, n: &Node4, t_max: f32) -> (Vec4, u32) {
        let mut t_near = Vec4::ZERO;
        let mut t_far = Vec4::splat(t_max);
        for a in 0..3 {
            let s = (self.neg >> a) as usize & 1;
            t_near = t_near.max((n.b[s][a] - self.o[a]) * self.inv[a]);
            t_far = t_far.min((n.b[s ^ 1][a] - self.o[a]) * self.inv_far[a]);
        }
        (t_near, t_near.cmple(t_far).bitmask())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn leaf_refs_round_trip() {
        for (first, count) in [(0, 1), (5, 8), (MAX_PACKS - 1, 3)] {
            let r = leaf_ref(first, count);
            assert!(r & LEAF != 0);
            assert_eq!(leaf_packs(r), first..first + count);
        }
    }

    #[test]
    fn slab_test_lanes() {
        let mut n = Node4::EMPTY;
        // Lane 0: unit box at x ∈ [2, 3]; lane 1: box behind the origin; lane 2: a box whose
        // lower y face holds the ray (d.y = +0 counts as inside); lane 3 stays empty.
        let boxes = [
            (Vec3::new(2.0, -0.5, -0.5), Vec3::new(3.0, 0.5, 0.5)),
            (Vec3::new(-3.0, -0.5, -0.5), Vec3::new(-2.0, 0.5, 0.5)),
            (Vec3::new(4.0, 0.0, -1.0), Vec3::new(5.0, 1.0, 1.0)),
        ];
        for (lane, (lo, hi)) in boxes.into_iter().enumerate() {
            for a in 0..3 {
                n.b[0][a][lane] = lo[a];
                n.b[1][a][lane] = hi[a];
            }
        }
        let r = RayBox::new(&Ray::new(Vec3::new(0.0, 0.0, 0.0), Vec3::X));
        let (t, m) = r.hit(&n, f32::INFINITY);
        assert_eq!(m, 0b101);
        assert_eq!((t[0], t[2]), (2.0, 4.0));
        // t_max before the box: missed.
        assert_eq!(r.hit(&n, 1.5).1, 0);
        // Negative direction meets lane 1 only.
        let (t, m) = RayBox::new(&Ray::new(Vec3::ZERO, -Vec3::X)).hit(&n, f32::INFINITY);
        assert_eq!((m, t[1]), (0b10, 2.0));
        // An origin inside a box enters it at 0.
        let (t, m) = RayBox::new(&Ray::new(Vec3::new(2.5, 0.0, 0.0), Vec3::Y)).hit(&n, f32::INFINITY);
        assert_eq!((m, t[0]), (1, 0.0));
    }
}
