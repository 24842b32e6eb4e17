//! Eight-wide nodes and the ray's test against their eight child boxes at once: the slab
//! test (Kay & Kajiya 1986) on SIMD lanes, the near and far planes chosen once per ray by
//! the direction's signs (Williams et al., "An efficient and robust ray-box intersection
//! algorithm", JGT 2005), with the far distances enlarged by 2γ₃ so that rounding never
//! loses a box the ray touches (Pharr, Jakob & Humphreys, pbrt-v4, §6.8.2).

use crate::ray::Ray;
use crate::simd::Bits;
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

/// Children per node: eight boxes fill one AVX register (two SSE ones), and the tree is
/// shallower than a four-wide one.
pub(crate) const WIDTH: usize = 8;

/// A node: its child boxes as structure-of-arrays lanes, and the children. Four cache lines.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct Node {
    /// `b[0]` lower and `b[1]` upper corners, by axis, one child per lane; an unused lane
    /// holds the empty box (lower +∞, upper −∞), which no ray meets.
    pub b: [[[f32; WIDTH]; 3]; 2],
    /// Child references (node index, or [`LEAF`]-tagged pack range); unused lanes are 0.
    pub child: [u32; WIDTH],
}

impl Node {
    /// A node with no children yet.
    pub const EMPTY: Node =
        Node { b: [[[f32::INFINITY; WIDTH]; 3], [[f32::NEG_INFINITY; WIDTH]; 3]], child: [0; WIDTH] };
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

/// A ray prepared for box tests: origin and inverse direction, and where a node's near and
/// far planes on each axis lie among its box rows.
#[derive(Clone, Copy)]
pub(crate) struct RayBox {
    o: [f32; 3],
    inv: [f32; 3],
    inv_far: [f32; 3],
    /// Per axis, the first value of the near planes' row in [`Node::b`] read flat: the lower
    /// corners' row where the direction is positive, else the upper ones'. Found once per ray,
    /// so that the walk's loop does not select the rows again at every node.
    near: [usize; 3],
    /// The same for the far planes.
    far: [usize; 3],
}

impl RayBox {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let (inv, far) = inverse_direction(ray.d);
        let neg = inv.is_negative_bitmask() as usize;
        let row = |corner: usize, a: usize| (corner * 3 + a) * WIDTH;
        RayBox {
            o: ray.o.to_array(),
            inv: inv.to_array(),
            inv_far: far.to_array(),
            near: std::array::from_fn(|a| row(neg >> a & 1, a)),
            far: std::array::from_fn(|a| row(!neg >> a & 1, a)),
        }
    }

    /// Row `start` (a `near` or `far` entry) of node `n`'s boxes.
    #[inline(always)]
    fn row(n: &Node, start: usize) -> &[f32; WIDTH] {
        n.b.as_flattened().as_flattened()[start..start + WIDTH].try_into().expect("a row of WIDTH values")
    }

    /// Entry distances into the child boxes, and the mask (bit i for lane i) of those the ray
    /// meets within [0, `t_max`]. `AVX`: in one AVX register, which only code compiled for
    /// AVX2 or AVX-512 may ask for (see `dispatch!`'s `::<AVX>` form); otherwise in two SSE
    /// halves (plain lanes off x86_64). Every form does the same IEEE operations per lane.
    #[inline(always)]
    pub fn hit<const AVX: bool>(&self, n: &Node, t_max: f32) -> ([f32; WIDTH], u32) {
        #[cfg(target_arch = "x86_64")]
        {
            if AVX {
                // SAFETY: `AVX` is set only in walks compiled for AVX2 or AVX-512, which
                // `dispatch!` runs after checking that the CPU has them.
                return unsafe { self.hit_avx(n, t_max) };
            }
            self.hit_halves(n, t_max)
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.hit_halves(n, t_max)
    }

    /// [`hit`](Self::hit) in four-lane halves (SSE2 on x86_64, NEON on aarch64).
    #[inline(always)]
    fn hit_halves(&self, n: &Node, t_max: f32) -> ([f32; WIDTH], u32) {
        let mut out = [0.0; WIDTH];
        let mut mask = 0;
        for h in 0..WIDTH / 4 {
            let lanes = |v: &[f32; WIDTH]| Vec4::from_slice(&v[4 * h..4 * h + 4]);
            let mut t_near = Vec4::ZERO;
            let mut t_far = Vec4::splat(t_max);
            for a in 0..3 {
                let o = Vec4::splat(self.o[a]);
                t_near = t_near.max((lanes(Self::row(n, self.near[a])) - o) * Vec4::splat(self.inv[a]));
                t_far = t_far.min((lanes(Self::row(n, self.far[a])) - o) * Vec4::splat(self.inv_far[a]));
            }
            t_near.write_to_slice(&mut out[4 * h..4 * h + 4]);
            mask |= t_near.cmple(t_far).bitmask() << (4 * h);
        }
        (out, mask)
    }

    /// [`hit`](Self::hit) in one AVX register. LLVM does not vectorise the lane loops of the
    /// halves to eight lanes (the mask's bit packing splits them), hence the intrinsics.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    #[inline]
    unsafe fn hit_avx(&self, n: &Node, t_max: f32) -> ([f32; WIDTH], u32) {
        use std::arch::x86_64::*;
        let mut t_near = _mm256_setzero_ps();
        let mut t_far = _mm256_set1_ps(t_max);
        let rows = n.b.as_ptr().cast::<f32>();
        for a in 0..3 {
            let o = _mm256_set1_ps(self.o[a]);
            // SAFETY: `near` and `far` hold starts of rows of `WIDTH` = 8 floats within the
            // node's 48 box values (set in `new`).
            let (near, far) =
                unsafe { (_mm256_loadu_ps(rows.add(self.near[a])), _mm256_loadu_ps(rows.add(self.far[a]))) };
            // max/min with the running value first, as SSE's `Vec4::max`/`min` order them.
            t_near = _mm256_max_ps(t_near, _mm256_mul_ps(_mm256_sub_ps(near, o), _mm256_set1_ps(self.inv[a])));
            t_far = _mm256_min_ps(t_far, _mm256_mul_ps(_mm256_sub_ps(far, o), _mm256_set1_ps(self.inv_far[a])));
        }
        let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t_near, t_far)) as u32;
        let mut out = [0.0f32; WIDTH];
        // SAFETY: `out` holds 8 floats.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), t_near) };
        (out, mask)
    }
}

/// Pushes the children of `mask` (two or more) onto `stack` from `sp`, farthest first, so
/// that the nearest is popped next (of equal distances the higher lane nearer the top), and
/// returns the stack pointer with that nearest child popped, and the child. `AVX` as for
/// [`RayBox::hit`]: each child's place counted at once from the children nearer than it, without
/// the data-dependent branches of the insertion sort the other instruction sets run (random rays
/// through the torus, `cargo bench -p render --bench bvh`: about 13 % more per second).
#[inline(always)]
pub(super) fn push_sorted<const AVX: bool>(
    stack: &mut [(u32, f32)],
    sp: usize,
    child: &[u32; WIDTH],
    t: &[f32; WIDTH],
    mask: u32,
) -> (usize, u32) {
    #[cfg(target_arch = "x86_64")]
    if AVX {
        // SAFETY: `AVX` is set only in walks compiled for AVX2 or AVX-512, which `dispatch!`
        // runs after checking that the CPU has them.
        return unsafe { push_ranked_avx(stack, sp, child, t, mask) };
    }
    // An insertion sort of at most eight entries onto the stack top.
    let (base, mut sp) = (sp, sp);
    for i in Bits(mask) {
        let e = (child[i], t[i]);
        let mut j = sp;
        while j > base && stack[j - 1].1 < e.1 {
            stack[j] = stack[j - 1];
            j -= 1;
        }
        stack[j] = e;
        sp += 1;
    }
    (sp - 1, stack[sp - 1].0)
}

/// [`push_sorted`] by ranks: a child's place from the top is the number of children nearer than
/// it, or as near and in a higher lane.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn push_ranked_avx(
    stack: &mut [(u32, f32)],
    sp: usize,
    child: &[u32; WIDTH],
    t: &[f32; WIDTH],
    mask: u32,
) -> (usize, u32) {
    use std::arch::x86_64::*;
    // SAFETY: `t` holds 8 floats.
    let tv = unsafe { _mm256_loadu_ps(t.as_ptr()) };
    let top = sp + mask.count_ones() as usize - 1;
    let mut nearest = 0;
    for i in Bits(mask) {
        let ti = _mm256_set1_ps(t[i]);
        let lt = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(tv, ti)) as u32;
        let eq = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_EQ_OQ>(tv, ti)) as u32;
        let above = (lt | eq & !((2u32 << i) - 1)) & mask;
        stack[top - above.count_ones() as usize] = (child[i], t[i]);
        if above == 0 {
            nearest = child[i];
        }
    }
    (top, nearest)
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
        let mut n = Node::EMPTY;
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
        let (t, m) = r.hit::<false>(&n, f32::INFINITY);
        assert_eq!(m, 0b101);
        assert_eq!((t[0], t[2]), (2.0, 4.0));
        // t_max before the box: missed.
        assert_eq!(r.hit::<false>(&n, 1.5).1, 0);
        // Negative direction meets lane 1 only.
        let (t, m) = RayBox::new(&Ray::new(Vec3::ZERO, -Vec3::X)).hit::<false>(&n, f32::INFINITY);
        assert_eq!((m, t[1]), (0b10, 2.0));
        // An origin inside a box enters it at 0.
        let (t, m) = RayBox::new(&Ray::new(Vec3::new(2.5, 0.0, 0.0), Vec3::Y)).hit::<false>(&n, f32::INFINITY);
        assert_eq!((m, t[0]), (1, 0.0));
        // The upper half of the lanes is tested too.
        for a in 0..3 {
            (n.b[0][a][6], n.b[1][a][6]) = (n.b[0][a][0], n.b[1][a][0]);
        }
        assert_eq!(r.hit::<false>(&n, f32::INFINITY).1, 0b100_0101);
    }

    #[test]
    #[cfg(target_arch = "x86_64")]
    fn ranked_and_sorted_pushes_give_the_same_stack() {
        if !std::arch::is_x86_feature_detected!("avx") {
            eprintln!("no AVX on this CPU: the ranked push is never run");
            return;
        }
        let mut s = crate::sampler::Sampler::new(3, 0, 0);
        for _ in 0..20_000 {
            // Few distinct distances, so that ties are common (a ray starting inside boxes).
            let t: [f32; WIDTH] = std::array::from_fn(|_| (s.next_1d() * 4.0).floor());
            let child: [u32; WIDTH] = std::array::from_fn(|i| 100 + i as u32);
            let mask = (s.next_u32() & 0xff) | 3;
            let sp = (s.next_u32() % 5) as usize;
            let (mut a, mut b) = ([(7u32, -1.0f32); 16], [(7u32, -1.0f32); 16]);
            let ra = push_sorted::<false>(&mut a, sp, &child, &t, mask);
            // SAFETY: checked above that the CPU has AVX.
            let rb = unsafe { push_ranked_avx(&mut b, sp, &child, &t, mask) };
            assert_eq!(ra, rb);
            assert_eq!(a[..ra.0], b[..rb.0], "t {t:?} mask {mask:#b}");
        }
    }

    #[test]
    fn the_avx_and_the_sse_test_agree_on_every_lane() {
        #[cfg(target_arch = "x86_64")]
        {
            if !std::arch::is_x86_feature_detected!("avx") {
                eprintln!("no AVX on this CPU: only the SSE form is tested");
                return;
            }
            let mut s = crate::sampler::Sampler::new(9, 0, 0);
            let mut v =
                |scale: f32| Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 2.0 * scale - Vec3::splat(scale);
            let mut hits = 0;
            for i in 0..20_000 {
                let mut n = Node::EMPTY;
                // Lanes past `used` stay empty, as in a node of fewer children.
                let used = 1 + i % WIDTH;
                for lane in 0..used {
                    let (c, h) = (v(3.0), v(1.0).abs());
                    for a in 0..3 {
                        (n.b[0][a][lane], n.b[1][a][lane]) = (c[a] - h[a], c[a] + h[a]);
                    }
                }
                // Half the rays aimed near the first box, so that hits are common.
                let o = v(4.0);
                let centre =
                    Vec3::new(n.b[0][0][0] + n.b[1][0][0], n.b[0][1][0] + n.b[1][1][0], n.b[0][2][0] + n.b[1][2][0])
                        * 0.5;
                let mut d = if i % 2 == 0 { centre + v(0.5) - o } else { v(1.0) };
                if i % 5 == 0 {
                    d[i % 3] = 0.0; // a zero component: the MIN_DIRECTION guard
                }
                let r = RayBox::new(&Ray::new(o, d));
                let t_max = if i % 3 == 0 { 4.0 } else { f32::INFINITY };
                let (ts, ms) = r.hit::<false>(&n, t_max);
                // SAFETY: the CPU has AVX (checked above).
                let (ta, ma) = unsafe { r.hit_avx(&n, t_max) };
                assert_eq!(ms, ma, "ray {i}");
                assert_eq!(ts.map(f32::to_bits), ta.map(f32::to_bits), "ray {i}");
                hits += ms.count_ones();
            }
            assert!(hits > 5_000, "the test must exercise hits: {hits}");
        }
    }
}
