//! A bounding volume hierarchy over primitive boxes: binned SAH build (Wald, "On fast
//! construction of SAH-based bounding volume hierarchies", 2007) and a stack-based,
//! front-to-back iterative traversal. It knows only boxes; callers test their primitives.

use crate::ray::Ray;
use crate::shape::Aabb;
use glam::{Vec3, Vec3A};

/// SAH bins per axis.
const BINS: usize = 16;
/// Leaves hold at most this many primitives unless the primitives cannot be separated.
const MAX_LEAF: usize = 8;
/// Deeper nodes become leaves; the traversal stack holds this many entries.
const MAX_DEPTH: usize = 64;
/// Cost of one node visit relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

/// A node: its box, and either two children or a range of primitives.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
struct Node {
    min: Vec3,
    /// Leaf: first primitive; interior: index of the second child (the first is this + 1).
    offset: u32,
    max: Vec3,
    /// Leaf: primitive count (> 0); interior: 0.
    count: u32,
}

/// The hierarchy. Primitive `k` in traversal order is the caller's primitive `order[k]`.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// BVH order → the caller's primitive index.
    pub order: Vec<u32>,
}

/// The ray with its inverse direction, in SIMD registers, for slab tests.
#[derive(Clone, Copy)]
struct RayInv {
    o: Vec3A,
    inv: Vec3A,
}

impl RayInv {
    #[inline]
    fn new(ray: &Ray) -> Self {
        RayInv { o: ray.o.into(), inv: Vec3A::from(ray.d).recip() }
    }

    /// Entry distance into the node's box if the ray meets it within [0, t_max), else ∞.
    /// A ray lying in a slab's boundary plane, parallel to it, gives 0·∞ = NaN there and
    /// counts as a miss: it can only touch that box's surface edge-on.
    #[inline]
    fn entry(&self, n: &Node, t_max: f32) -> f32 {
        let t0 = (Vec3A::from(n.min) - self.o) * self.inv;
        let t1 = (Vec3A::from(n.max) - self.o) * self.inv;
        let near = t0.min(t1).max_element().max(0.0);
        let far = t0.max(t1).min_element().min(t_max);
        if near <= far {
            near
        } else {
            f32::INFINITY
        }
    }
}

impl Bvh {
    /// Builds over the primitives' boxes.
    pub fn build(bounds: &[Aabb]) -> Bvh {
        let centroids: Vec<Vec3> = bounds.iter().map(|b| b.center()).collect();
        let mut b =
            Builder { bounds, centroids: &centroids, order: (0..bounds.len() as u32).collect(), nodes: Vec::new() };
        if !bounds.is_empty() {
            b.nodes.reserve(bounds.len());
            b.build(0, bounds.len(), 0);
        }
        Bvh { nodes: b.nodes, order: b.order }
    }

    /// The number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The box of everything.
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map(|n| Aabb { min: n.min, max: n.max }).unwrap_or(Aabb::EMPTY)
    }

    /// The closest primitive hit: `test(k, t_max)` intersects primitive `k` (BVH order) and
    /// returns its distance when below `t_max`. Returns (k, t).
    #[inline]
    pub fn closest(&self, ray: &Ray, mut test: impl FnMut(usize, f32) -> Option<f32>) -> Option<(usize, f32)> {
        let mut best: Option<(usize, f32)> = None;
        let mut t_max = ray.t_max;
        self.traverse(ray, &mut t_max, |k, t_max| {
            if let Some(t) = test(k, *t_max) {
                *t_max = t;
                best = Some((k, t));
            }
            false
        });
        best
    }

    /// True when some primitive is hit within the ray's range (stops at the first).
    #[inline]
    pub fn any(&self, ray: &Ray, mut test: impl FnMut(usize, f32) -> Option<f32>) -> bool {
        let mut t_max = ray.t_max;
        self.traverse(ray, &mut t_max, |k, t_max| test(k, *t_max).is_some())
    }

    /// Visits the leaves the ray reaches, nearer boxes first; `visit` returns true to stop,
    /// and then so does this.
    #[inline]
    fn traverse(&self, ray: &Ray, t_max: &mut f32, mut visit: impl FnMut(usize, &mut f32) -> bool) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let r = RayInv::new(ray);
        if r.entry(&self.nodes[0], *t_max) == f32::INFINITY {
            return false;
        }
        let mut stack = [(0u32, 0.0f32); MAX_DEPTH];
        let mut sp = 0usize;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if n.count > 0 {
                let first = n.offset as usize;
                for k in first..first + n.count as usize {
                    if visit(k, t_max) {
                        return true;
                    }
                }
            } else {
                let (a, b) = (node + 1, n.offset as usize);
                let ta = r.entry(&self.nodes[a], *t_max);
                let tb = r.entry(&self.nodes[b], *t_max);
                let (near, t_near, far, t_far) = if ta <= tb { (a, ta, b, tb) } else { (b, tb, a, ta) };
                if t_near != f32::INFINITY {
                    if t_far != f32::INFINITY {
                        stack[sp] = (far as u32, t_far);
                        sp += 1;
                    }
                    node = near;
                    continue;
                }
            }
            // Pop the next box that is still nearer than the closest hit so far.
            loop {
                if sp == 0 {
                    return false;
                }
                sp -= 1;
                let (k, t) = stack[sp];
                if t < *t_max {
                    node = k as usize;
                    break;
                }
            }
        }
    }
}

struct Builder<'a> {
    bounds: &'a [Aabb],
    centroids: &'a [Vec3],
    order: Vec<u32>,
    nodes: Vec<Node>,
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: usize,
}

impl Builder<'_> {
    /// Builds the subtree over order[start..end]; returns its node index.
    fn build(&mut self, start: usize, end: usize, depth: usize) -> usize {
        let idx = self.nodes.len();
        let mut bb = Aabb::EMPTY;
        let mut cb = Aabb::EMPTY;
        for &p in &self.order[start..end] {
            bb = bb.union(self.bounds[p as usize]);
            cb = cb.grow(self.centroids[p as usize]);
        }
        self.nodes.push(Node { min: bb.min, offset: start as u32, max: bb.max, count: (end - start) as u32 });
        let n = end - start;
        if n <= 1 || depth + 1 >= MAX_DEPTH {
            return idx;
        }
        let mid = match self.find_split(start, end, &bb, &cb) {
            Some(m) => m,
            None if n <= MAX_LEAF => return idx,
            // Inseparable by centroid (all equal) or SAH says leaf but too many: halve by index.
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
    fn find_split(&mut self, start: usize, end: usize, bb: &Aabb, cb: &Aabb) -> Option<usize> {
        let n = end - start;
        let extent = cb.max - cb.min;
        let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, first bin on the right)
        for axis in 0..3 {
            if extent[axis].is_nan() || extent[axis] <= 0.0 {
                continue;
            }
            let scale = BINS as f32 / extent[axis];
            let mut bins = [Bin { bounds: Aabb::EMPTY, count: 0 }; BINS];
            for &p in &self.order[start..end] {
                let b = bin_of(self.centroids[p as usize][axis], cb.min[axis], scale);
                bins[b].count += 1;
                bins[b].bounds = bins[b].bounds.union(self.bounds[p as usize]);
            }
            // Right-to-left sweep gives the cost of every right side.
            let mut right_area = [0.0f32; BINS];
            let mut right_count = [0usize; BINS];
            let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
            for i in (1..BINS).rev() {
                acc = acc.union(bins[i].bounds);
                cnt += bins[i].count;
                right_area[i] = acc.half_area();
                right_count[i] = cnt;
            }
            let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
            for i in 1..BINS {
                acc = acc.union(bins[i - 1].bounds);
                cnt += bins[i - 1].count;
                if cnt == 0 || right_count[i] == 0 {
                    continue;
                }
                let cost = acc.half_area() * cnt as f32 + right_area[i] * right_count[i] as f32;
                if !matches!(best, Some((c, _, _)) if c <= cost) {
                    best = Some((cost, axis, i));
                }
            }
        }
        let (cost, axis, split) = best?;
        let split_cost = TRAVERSAL_COST + cost / bb.half_area().max(f32::MIN_POSITIVE);
        if n <= MAX_LEAF && split_cost >= n as f32 {
            return None;
        }
        let scale = BINS as f32 / extent[axis];
        let (lo, centroids) = (cb.min[axis], self.centroids);
        let slice = &mut self.order[start..end];
        // In-place partition: primitives in bins below `split` go left.
        let mut i = 0;
        let mut j = slice.len();
        while i < j {
            if bin_of(centroids[slice[i] as usize][axis], lo, scale) < split {
                i += 1;
            } else {
                j -= 1;
                slice.swap(i, j);
            }
        }
        (i > 0 && i < n).then_some(start + i)
    }
}

#[inline]
fn bin_of(c: f32, lo: f32, scale: f32) -> usize {
    (((c - lo) * scale) as usize).min(BINS - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_primitive_lands_in_exactly_one_leaf_and_boxes_nest() {
        let boxes: Vec<Aabb> = (0..1000)
            .map(|i| {
                let c = Vec3::new((i * 37 % 101) as f32, (i * 59 % 103) as f32, (i % 7) as f32);
                Aabb { min: c, max: c + Vec3::splat(0.5) }
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        let mut seen = vec![0; boxes.len()];
        for &p in &bvh.order {
            seen[p as usize] += 1;
        }
        assert!(seen.iter().all(|&s| s == 1));
        // Each leaf's box holds its primitives; each interior box holds its children's.
        for (i, n) in bvh.nodes.iter().enumerate() {
            let inside = |b: &Aabb| b.min.cmpge(n.min).all() && b.max.cmple(n.max).all();
            if n.count > 0 {
                assert!(n.count as usize <= MAX_LEAF);
                for k in n.offset..n.offset + n.count {
                    assert!(inside(&boxes[bvh.order[k as usize] as usize]));
                }
            } else {
                for c in [i + 1, n.offset as usize] {
                    assert!(inside(&Aabb { min: bvh.nodes[c].min, max: bvh.nodes[c].max }));
                }
            }
        }
        // Identical boxes cannot be separated: they still build, halving by index.
        let same = vec![Aabb { min: Vec3::ZERO, max: Vec3::ONE }; 100];
        let bvh = Bvh::build(&same);
        assert_eq!(bvh.order.len(), 100);
        assert!(Bvh::build(&[]).closest(&Ray::new(Vec3::ZERO, Vec3::X), |_, _| Some(1.0)).is_none());
    }
}
