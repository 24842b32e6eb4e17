//! Packet traversal: sixteen rays walk the hierarchy together, each node's eight boxes tested
//! against every live ray at once (Wald, Slusallek, Benthin & Wagner, "Interactive rendering
//! with coherent ray tracing", 2001; masked for the rays a subtree can still matter to, as in
//! Wald et al., "Ray tracing deformable scenes using dynamic bounding volume hierarchies",
//! 2007). Coherent rays (a pixel's camera samples, shadow rays from neighbouring points to one
//! light) share their nodes, so one box test serves many rays. Each lane's slab test does the
//! operations of the single-ray [`RayBox`](super::wide::RayBox), so no ray loses a box it meets.

use super::wide::{inverse_direction, leaf_packs, Node, LEAF, WIDTH};
use super::{Bvh, STACK};
use crate::ray::Ray;
use crate::simd::{F16, LANES, M16};
use std::ops::Range;

/// Sixteen rays in structure-of-arrays form, with the inverse directions of the slab test.
#[derive(Clone, Copy, Debug)]
pub struct RayPacket {
    /// Origins, by axis.
    pub o: [F16; 3],
    /// Directions, by axis.
    pub d: [F16; 3],
    inv: [F16; 3],
    inv_far: [F16; 3],
    /// Each ray's far end.
    pub t_max: F16,
}

impl RayPacket {
    /// The rays `rays[i]` for the lanes of bit mask `active` (the others hold a copy of the first,
    /// so that they stay finite).
    #[inline(always)]
    pub fn new(rays: &[Ray; LANES], active: u32) -> Self {
        let first = rays[(active.trailing_zeros() as usize).min(LANES - 1)];
        let ray = |i: usize| if active >> i & 1 != 0 { rays[i] } else { first };
        let mut p = RayPacket {
            o: [F16::splat(0.0); 3],
            d: [F16::splat(0.0); 3],
            inv: [F16::splat(0.0); 3],
            inv_far: [F16::splat(0.0); 3],
            t_max: F16::splat(0.0),
        };
        for i in 0..LANES {
            let r = ray(i);
            let (inv, far) = inverse_direction(r.d);
            for a in 0..3 {
                p.o[a].0[i] = r.o[a];
                p.d[a].0[i] = r.d[a];
                p.inv[a].0[i] = inv[a];
                p.inv_far[a].0[i] = far[a];
            }
            p.t_max.0[i] = r.t_max;
        }
        p
    }

    /// Entry distances of every lane into child `c` of `n`, and the lanes of `live` that meet
    /// it within [0, `t_max`].
    #[inline(always)]
    fn hit(&self, n: &Node, c: usize, t_max: &F16, live: M16) -> (F16, M16) {
        let mut t_near = F16::splat(0.0);
        let mut t_far = *t_max;
        for a in 0..3 {
            let (lo, hi) = (F16::splat(n.b[0][a][c]), F16::splat(n.b[1][a][c]));
            let (t0, t1) = ((lo - self.o[a]) * self.inv[a], (hi - self.o[a]) * self.inv[a]);
            let (f0, f1) = ((lo - self.o[a]) * self.inv_far[a], (hi - self.o[a]) * self.inv_far[a]);
            // Per lane the near plane is the lower one for a positive direction: t0 < t1 then.
            let neg = self.inv[a].lt(F16::splat(0.0));
            t_near = t_near.max(t0.blend(neg, t1));
            t_far = t_far.min(f1.blend(neg, f0));
        }
        (t_near, t_near.le(t_far).and(live))
    }
}

/// What a packet walk does at a leaf. A trait rather than a closure, so that its test is
/// inlined into the walk and compiled for the walk's instruction set.
pub trait PacketLeaf {
    /// Tests the packs `packs` for the rays `lanes`; returns the lanes it has finished (for an
    /// any-hit walk those found blocked; a closest-hit walk lowers their `t_max` to the hit and
    /// returns 0).
    fn leaf(&mut self, packs: Range<usize>, lanes: M16, t_max: &mut F16) -> M16;
}

impl Bvh {
    /// Visits, for the rays of `active`, the leaves their boxes meet, calling `leaf` there
    /// (`ANY`: lanes it reports blocked leave the walk). Nearer subtrees go first for closest
    /// hits; a subtree is skipped for a ray whose closest hit so far lies before it.
    #[inline(always)]
    pub fn walk_packet<const ANY: bool>(
        &self,
        p: &RayPacket,
        t_max: &mut F16,
        active: M16,
        leaf: &mut impl PacketLeaf,
    ) -> M16 {
        let mut done = M16::NONE;
        if self.order.is_empty() || !active.any() {
            return done;
        }
        let mut small = [(0u32, M16::NONE, 0.0f32); STACK];
        let mut heap = Vec::new();
        let stack: &mut [(u32, M16, f32)] = if self.stack_need <= STACK {
            &mut small
        } else {
            heap.resize(self.stack_need, (0, M16::NONE, 0.0));
            &mut heap
        };
        let mut sp = 0usize;
        let (mut cur, mut lanes, mut t_min) = (self.root, active, 0.0f32);
        loop {
            // The lanes this entry can still matter to.
            lanes = if ANY { lanes.and_not(done) } else { lanes.and(t_max.gt(F16::splat(t_min))) };
            if lanes.any() {
                if cur & LEAF != 0 {
                    done = done.or(leaf.leaf(leaf_packs(cur), lanes, t_max));
                    if ANY && !active.and_not(done).any() {
                        return done;
                    }
                } else {
                    let n = &self.nodes[cur as usize];
                    let base = sp;
                    for c in 0..WIDTH {
                        if n.child[c] == 0 {
                            continue;
                        }
                        let (t_near, hit) = p.hit(n, c, t_max, lanes);
                        if !hit.any() {
                            continue;
                        }
                        // Closest hits: sorted so that the nearest entry is popped first.
                        let e = (n.child[c], hit, if ANY { 0.0 } else { t_near.min_of(hit) });
                        let mut j = sp;
                        while !ANY && j > base && stack[j - 1].2 < e.2 {
                            stack[j] = stack[j - 1];
                            j -= 1;
                        }
                        stack[j] = e;
                        sp += 1;
                    }
                }
            }
            if sp == 0 {
                return done;
            }
            sp -= 1;
            (cur, lanes, t_min) = stack[sp];
        }
    }
}
