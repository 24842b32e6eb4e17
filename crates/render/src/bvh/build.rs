//! The binary tree the wide hierarchy is collapsed from: binned SAH (Wald, "On fast
//! construction of SAH-based bounding volume hierarchies", 2007), the three axes binned in
//! one pass over the primitives. A leaf's triangles cost one test per pack of up to sixteen,
//! since they are tested a pack at a time; other primitives (spheres, rectangles, disks) are
//! tested one by one, and each costs a test of its own.

use super::PACK;
use crate::shape::Aabb;
use glam::Vec3A;

/// SAH bins per axis.
const BINS: usize = 16;
/// Leaves hold at most this many primitives, fewer than a pack's sixteen: one ray tests a leaf
/// at once whatever its size, but a packet of coherent rays tests it triangle by triangle, and
/// then smaller leaves waste fewer tests (measured, paired: against 16, hello 10 % faster, mesh
/// and matpreview 3 % slower; against 8, matpreview and mesh 7–12 % faster).
pub(super) const MAX_LEAF: usize = 12;
/// Below this depth splits follow the SAH; deeper ones halve by index, which bounds the
/// depth by this plus log₂ of the primitive count even for pathological inputs.
const SAH_DEPTH: usize = 64;
/// Cost of one node visit.
const TRAVERSAL_COST: f32 = 1.0;
/// Cost of one test of a pack of primitives, relative to a node visit.
const PACK_TEST_COST: f32 = 2.0;
/// Cost of testing one primitive that is tested alone (not in a pack), relative to a node
/// visit: a sphere's quadratic, reached through the primitive's reference and its shape, is
/// about twice the work of a node's eight boxes (225 spheres on a floor, 2 spp, one thread:
/// 1 853 → 1 810 M instructions against a cost of 1; 3 built the same tree). Counted as a
/// pack's lanes, twelve small spheres in a ring made one leaf as wide as the ring, which
/// most rays under it entered and tested sphere by sphere.
const ALONE_TEST_COST: f32 = 2.0;

/// A binary node: its box, and either two children or a range of primitives.
#[derive(Clone, Copy, Debug)]
pub(super) struct BinaryNode {
    pub bounds: Aabb,
    /// Leaf: first primitive; interior: index of the second child (the first is this + 1).
    pub offset: u32,
    /// Leaf: primitive count (> 0); interior: 0.
    pub count: u32,
}

/// A box in SIMD registers, for the build's inner loops.
#[derive(Clone, Copy)]
struct Box3 {
    min: Vec3A,
    max: Vec3A,
}

impl Box3 {
    const EMPTY: Box3 = Box3 { min: Vec3A::INFINITY, max: Vec3A::NEG_INFINITY };

    #[inline]
    fn union(self, o: Box3) -> Box3 {
        Box3 { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// Half the surface area; 0 for an empty box.
    #[inline]
    fn half_area(&self) -> f32 {
        let e = (self.max - self.min).max(Vec3A::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }
}

/// Subtrees of more primitives than this are built on another rayon task (both halves of a
/// split at once); smaller ones on the calling thread.
const PARALLEL_MIN: usize = 1 << 15;

/// The binary tree over `bounds` (non-empty) and the permutation of the primitives it
/// sorts into leaf order. Large subtrees are built in parallel; the tree is the same
/// whatever the thread count.
/// `alone[k]` (or false past its end) marks primitive k as one tested alone, not in a pack.
pub(super) fn build_binary(bounds: &[Aabb], alone: &[bool]) -> (Vec<BinaryNode>, Vec<u32>) {
    let boxes: Vec<Box3> = bounds.iter().map(|b| Box3 { min: b.min.into(), max: b.max.into() }).collect();
    let centroids: Vec<Vec3A> = boxes.iter().map(|b| 0.5 * (b.min + b.max)).collect();
    let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
    let nodes = Prims { boxes: &boxes, centroids: &centroids, alone }.subtree(&mut order, 0, 0);
    (nodes, order)
}

/// Primitives counted for a leaf's cost: all of them, and those tested alone.
#[derive(Clone, Copy, Default)]
struct Count {
    all: usize,
    alone: usize,
}

impl Count {
    #[inline]
    fn add(&mut self, o: Count) {
        self.all += o.all;
        self.alone += o.alone;
    }
}

/// The SAH cost of testing the primitives `c` in one leaf, in node visits.
#[inline]
fn leaf_cost(c: Count) -> f32 {
    (c.all - c.alone).div_ceil(PACK) as f32 * PACK_TEST_COST + c.alone as f32 * ALONE_TEST_COST
}

/// The primitives' boxes and centroids, by original index.
#[derive(Clone, Copy)]
struct Prims<'a> {
    boxes: &'a [Box3],
    centroids: &'a [Vec3A],
    alone: &'a [bool],
}

impl Prims<'_> {
    /// The subtree over `order` (primitives `first..` of the leaf order), its nodes in
    /// depth-first order with child indices relative to its root.
    fn subtree(self, order: &mut [u32], first: usize, depth: usize) -> Vec<BinaryNode> {
        let n = order.len();
        if n <= PARALLEL_MIN {
            let mut b = Builder { prims: self, order, first, nodes: Vec::with_capacity(n / 2 + 1) };
            b.build(0, n, depth);
            return b.nodes;
        }
        let (bb, cb) = self.bounds(order);
        let bounds = Aabb { min: bb.min.into(), max: bb.max.into() };
        let split = if depth < SAH_DEPTH { self.find_split(order, &bb, &cb) } else { None };
        let mid = split.unwrap_or(n / 2);
        let (lo, hi) = order.split_at_mut(mid);
        let (left, right) =
            rayon::join(|| self.subtree(lo, first, depth + 1), || self.subtree(hi, first + mid, depth + 1));
        // Root, then the left subtree, then the right one: indices shifted to their places.
        let mut nodes = Vec::with_capacity(1 + left.len() + right.len());
        nodes.push(BinaryNode { bounds, offset: (1 + left.len()) as u32, count: 0 });
        for (sub, base) in [(&left, 1), (&right, 1 + left.len())] {
            nodes.extend(sub.iter().map(|&nd| {
                if nd.count == 0 {
                    BinaryNode { offset: nd.offset + base as u32, ..nd }
                } else {
                    nd
                }
            }));
        }
        nodes
    }

    /// The box of the primitives in `order` and the box of their centroids.
    fn bounds(&self, order: &[u32]) -> (Box3, Box3) {
        let mut bb = Box3::EMPTY;
        let mut cb = Box3::EMPTY;
        for &p in order {
            bb = bb.union(self.boxes[p as usize]);
            let c = self.centroids[p as usize];
            cb = cb.union(Box3 { min: c, max: c });
        }
        (bb, cb)
    }

    /// The SAH-best binned split of `order`, partitioned in place (the index of the first
    /// primitive on the right); None when a leaf is cheaper (and allowed) or the centroids
    /// cannot be separated.
    fn find_split(&self, order: &mut [u32], bb: &Box3, cb: &Box3) -> Option<usize> {
        let n = order.len();
        let extent = cb.max - cb.min;
        // Axes of zero (or NaN) extent get scale 0: everything in bin 0, never a split.
        let scale = Vec3A::select(extent.cmpgt(Vec3A::ZERO), BINS as f32 / extent, Vec3A::ZERO);
        let mut bins = [[Box3::EMPTY; BINS]; 3];
        let mut counts = [[Count::default(); BINS]; 3];
        let mut total = Count::default();
        for &p in order.iter() {
            let b = bins_of(self.centroids[p as usize], cb.min, scale);
            let pb = self.boxes[p as usize];
            let one = Count { all: 1, alone: usize::from(self.alone.get(p as usize).copied().unwrap_or(false)) };
            total.add(one);
            for axis in 0..3 {
                counts[axis][b[axis]].add(one);
                bins[axis][b[axis]] = bins[axis][b[axis]].union(pb);
            }
        }
        let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, first bin on the right)
        for axis in 0..3 {
            if scale[axis] == 0.0 {
                continue;
            }
            let (bins, counts) = (&bins[axis], &counts[axis]);
            // Right-to-left sweep gives the cost of every right side.
            let mut right_cost = [0.0f32; BINS];
            let mut right_count = [0usize; BINS];
            let (mut acc, mut cnt) = (Box3::EMPTY, Count::default());
            for i in (1..BINS).rev() {
                acc = acc.union(bins[i]);
                cnt.add(counts[i]);
                right_cost[i] = acc.half_area() * leaf_cost(cnt);
                right_count[i] = cnt.all;
            }
            let (mut acc, mut cnt) = (Box3::EMPTY, Count::default());
            for i in 1..BINS {
                acc = acc.union(bins[i - 1]);
                cnt.add(counts[i - 1]);
                if cnt.all == 0 || right_count[i] == 0 {
                    continue;
                }
                let cost = acc.half_area() * leaf_cost(cnt) + right_cost[i];
                if !matches!(best, Some((c, _, _)) if c <= cost) {
                    best = Some((cost, axis, i));
                }
            }
        }
        let (cost, axis, split) = best?;
        let split_cost = TRAVERSAL_COST + cost / bb.half_area().max(f32::MIN_POSITIVE);
        if n <= MAX_LEAF && split_cost >= leaf_cost(total) {
            return None;
        }
        let (lo, centroids) = (cb.min, self.centroids);
        // In-place partition: primitives in bins below `split` go left.
        let mut i = 0;
        let mut j = n;
        while i < j {
            if bins_of(centroids[order[i] as usize], lo, scale)[axis] < split {
                i += 1;
            } else {
                j -= 1;
                order.swap(i, j);
            }
        }
        (i > 0 && i < n).then_some(i)
    }
}

/// The sequential build of one subtree into one node list.
struct Builder<'a> {
    prims: Prims<'a>,
    order: &'a mut [u32],
    /// Leaf-order index of `order[0]`.
    first: usize,
    nodes: Vec<BinaryNode>,
}

impl Builder<'_> {
    /// Builds the subtree over order[start..end]; returns its node index.
    fn build(&mut self, start: usize, end: usize, depth: usize) -> usize {
        let idx = self.nodes.len();
        let (bb, cb) = self.prims.bounds(&self.order[start..end]);
        let bounds = Aabb { min: bb.min.into(), max: bb.max.into() };
        self.nodes.push(BinaryNode { bounds, offset: (self.first + start) as u32, count: (end - start) as u32 });
        let n = end - start;
        if n <= 1 {
            return idx;
        }
        let split = if depth < SAH_DEPTH {
            self.prims.find_split(&mut self.order[start..end], &bb, &cb).map(|m| start + m)
        } else {
            None
        };
        let mid = match split {
            Some(m) => m,
            None if n <= MAX_LEAF => return idx,
            // Inseparable by centroid, too deep, or SAH says leaf but too many: halve by index.
            None => start + n / 2,
        };
        let left = self.build(start, mid, depth + 1);
        debug_assert_eq!(left, idx + 1);
        let right = self.build(mid, end, depth + 1);
        self.nodes[idx].offset = right as u32;
        self.nodes[idx].count = 0;
        idx
    }
}

/// The bin of centroid `c` on each axis.
#[inline]
fn bins_of(c: Vec3A, lo: Vec3A, scale: Vec3A) -> [usize; 3] {
    let b = ((c - lo) * scale).min(Vec3A::splat((BINS - 1) as f32));
    [b.x as usize, b.y as usize, b.z as usize]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn primitives_tested_alone_make_smaller_leaves() {
        // Twelve small boxes in a ring: packed, one leaf tests them all at once; tested one by
        // one, a leaf as wide as the ring would test all twelve for every ray entering it.
        let bounds: Vec<Aabb> = (0..12)
            .map(|i| {
                let a = i as f32 * std::f32::consts::TAU / 12.0;
                let c = Vec3::new(3.0 * a.cos(), 2.5, 3.0 * a.sin());
                Aabb { min: c - Vec3::splat(0.1), max: c + Vec3::splat(0.1) }
            })
            .collect();
        let leaves = |alone: &[bool]| build_binary(&bounds, alone).0.iter().filter(|n| n.count > 0).count();
        assert_eq!(leaves(&[]), 1);
        assert_eq!(leaves(&[false; 12]), 1);
        assert!(leaves(&[true; 12]) >= 4, "{} leaves", leaves(&[true; 12]));
    }

    #[test]
    fn the_parallel_build_makes_the_sequential_tree() {
        // Boxes of a jittered grid, more than twice the size built on one thread.
        let n = 3 * PARALLEL_MIN;
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        let bounds: Vec<Aabb> = (0..n)
            .map(|_| {
                let c = Vec3::new(rnd(), rnd(), rnd()) * 100.0;
                Aabb { min: c, max: c + Vec3::new(rnd(), rnd(), rnd()) }
            })
            .collect();
        let (nodes, order) = build_binary(&bounds, &[]);
        let boxes: Vec<Box3> = bounds.iter().map(|b| Box3 { min: b.min.into(), max: b.max.into() }).collect();
        let centroids: Vec<Vec3A> = boxes.iter().map(|b| 0.5 * (b.min + b.max)).collect();
        let mut seq_order: Vec<u32> = (0..n as u32).collect();
        let mut b = Builder {
            prims: Prims { boxes: &boxes, centroids: &centroids, alone: &[] },
            order: &mut seq_order,
            first: 0,
            nodes: Vec::new(),
        };
        b.build(0, n, 0);
        let seq = b.nodes;
        assert_eq!(seq.len(), nodes.len());
        for (k, (a, b)) in seq.iter().zip(&nodes).enumerate() {
            assert!(a.offset == b.offset && a.count == b.count && a.bounds == b.bounds, "node {k}: {a:?} vs {b:?}");
        }
        assert_eq!(seq_order, order);
    }
}
