//! The binary tree the wide hierarchy is collapsed from: binned SAH (Wald, "On fast
//! construction of SAH-based bounding volume hierarchies", 2007), the three axes binned in
//! one pass over the primitives. A leaf costs one test per four primitives, since leaves
//! are tested four at a time.

use crate::shape::Aabb;
use glam::Vec3A;

/// SAH bins per axis.
const BINS: usize = 16;
/// Leaves hold at most this many primitives.
pub(super) const MAX_LEAF: usize = 8;
/// Below this depth splits follow the SAH; deeper ones halve by index, which bounds the
/// depth by this plus log₂ of the primitive count even for pathological inputs.
const SAH_DEPTH: usize = 64;
/// Cost of one node visit relative to one test of four primitives.
const TRAVERSAL_COST: f32 = 1.0;

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

/// The binary tree over `bounds` (non-empty) and the permutation of the primitives it
/// sorts into leaf order.
pub(super) fn build_binary(bounds: &[Aabb]) -> (Vec<BinaryNode>, Vec<u32>) {
    let boxes: Vec<Box3> = bounds.iter().map(|b| Box3 { min: b.min.into(), max: b.max.into() }).collect();
    let centroids: Vec<Vec3A> = boxes.iter().map(|b| 0.5 * (b.min + b.max)).collect();
    let mut b =
        Builder { boxes: &boxes, centroids: &centroids, order: (0..bounds.len() as u32).collect(), nodes: Vec::new() };
    b.nodes.reserve(bounds.len() / 2);
    b.build(0, bounds.len(), 0);
    (b.nodes, b.order)
}

/// The SAH cost of testing `n` primitives in one leaf, in four-wide tests.
#[inline]
fn leaf_cost(n: usize) -> f32 {
    n.div_ceil(4) as f32
}

struct Builder<'a> {
    boxes: &'a [Box3],
    centroids: &'a [Vec3A],
    order: Vec<u32>,
    nodes: Vec<BinaryNode>,
}

impl Builder<'_> {
    /// Builds the subtree over order[start..end]; returns its node index.
    fn build(&mut self, start: usize, end: usize, depth: usize) -> usize {
        let idx = self.nodes.len();
        let mut bb = Box3::EMPTY;
        let mut cb = Box3::EMPTY;
        for &p in &self.order[start..end] {
            bb = bb.union(self.boxes[p as usize]);
            let c = self.centroids[p as usize];
            cb = cb.union(Box3 { min: c, max: c });
        }
        let bounds = Aabb { min: bb.min.into(), max: bb.max.into() };
        self.nodes.push(BinaryNode { bounds, offset: start as u32, count: (end - start) as u32 });
        let n = end - start;
        if n <= 1 {
            return idx;
        }
        let split = if depth < SAH_DEPTH { self.find_split(start, end, &bb, &cb) } else { None };
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

    /// The SAH-best binned split of order[start..end], partitioned in place; None when a
    /// leaf is cheaper (and allowed) or the centroids cannot be separated.
    fn find_split(&mut self, start: usize, end: usize, bb: &Box3, cb: &Box3) -> Option<usize> {
        let n = end - start;
        let extent = cb.max - cb.min;
        // Axes of zero (or NaN) extent get scale 0: everything in bin 0, never a split.
        let scale = Vec3A::select(extent.cmpgt(Vec3A::ZERO), BINS as f32 / extent, Vec3A::ZERO);
        let mut bins = [[Box3::EMPTY; BINS]; 3];
        let mut counts = [[0usize; BINS]; 3];
        for &p in &self.order[start..end] {
            let b = bins_of(self.centroids[p as usize], cb.min, scale);
            let pb = self.boxes[p as usize];
            for axis in 0..3 {
                counts[axis][b[axis]] += 1;
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
            let (mut acc, mut cnt) = (Box3::EMPTY, 0);
            for i in (1..BINS).rev() {
                acc = acc.union(bins[i]);
                cnt += counts[i];
                right_cost[i] = acc.half_area() * leaf_cost(cnt);
                right_count[i] = cnt;
            }
            let (mut acc, mut cnt) = (Box3::EMPTY, 0);
            for i in 1..BINS {
                acc = acc.union(bins[i - 1]);
                cnt += counts[i - 1];
                if cnt == 0 || right_count[i] == 0 {
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
        if n <= MAX_LEAF && split_cost >= leaf_cost(n) {
            return None;
        }
        let (lo, scale, centroids) = (cb.min, scale, self.centroids);
        let slice = &mut self.order[start..end];
        // In-place partition: primitives in bins below `split` go left.
        let mut i = 0;
        let mut j = slice.len();
        while i < j {
            if bins_of(centroids[slice[i] as usize], lo, scale)[axis] < split {
                i += 1;
            } else {
                j -= 1;
                slice.swap(i, j);
            }
        }
        (i > 0 && i < n).then_some(start + i)
    }
}

/// The bin of centroid `c` on each axis.
#[inline]
fn bins_of(c: Vec3A, lo: Vec3A, scale: Vec3A) -> [usize; 3] {
    let b = ((c - lo) * scale).min(Vec3A::splat((BINS - 1) as f32));
    [b.x as usize, b.y as usize, b.z as usize]
}
