//! Front-to-back traversal (pbrt's `KdTreeAccel::Intersect`, Pharr et al. 2016, section 4.4.4): a
//! small explicit stack of far children with their ray intervals, no recursion, and an early exit
//! once the closest hit lies before the end of the current cell. Leaves hold their triangles in
//! SIMD blocks of four (the BVH's `TriBlock`), filtered four at a time by the watertight test's edge
//! functions; the survivors go through a per-ray mailbox and the scalar test.

use super::{KdTree, STACK};
use crate::accel::bvh::{far_scale, finish, LaneValues, RayBox, RayTri};
use crate::accel::{test_primitive, Hit, Primitives, TraversalStats};
use crate::math::{Ray, Vec3};
use std::mem::MaybeUninit;

/// Direct-mapped per-ray mailbox (Amanatides & Woo 1987 mark primitives with a ray id; a per-ray
/// table on the stack needs no shared mutable marks, so it is thread-safe). A collision only costs a
/// repeated test, never a skipped one. Only the filter's survivors reach it - nearly always real
/// hits, or primitives called back - so it can be small.
const MAILBOX: usize = 32;

#[derive(Clone, Copy)]
struct Far {
    node: u32,
    t0: f32,
    t1: f32,
}

impl KdTree {
    #[inline(always)]
    pub(super) fn traverse<P: Primitives, const ANY: bool>(
        &self,
        prims: &P,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        stats.rays += 1;
        if self.nodes.is_empty() {
            return None;
        }
        let rb = RayBox::new(ray);
        let (mut t0, mut t1) =
            self.bounds
                .slab_intersect(ray, Vec3::from(rb.inv), t_max * far_scale())?;
        let rt = RayTri::new(ray);
        let mut vals = LaneValues::default();
        let mut stack = [const { MaybeUninit::<Far>::uninit() }; STACK];
        let mut sp = 0usize;
        let mut at = 0usize;
        let mut best = None;
        let mut mail = [u32::MAX; MAILBOX];
        loop {
            // The cell [t0, t1] starts beyond the closest hit: nothing in it or later can be nearer.
            if t_max < t0 {
                return best;
            }
            let node = self.nodes[at];
            stats.nodes_visited += 1;
            if !node.is_leaf() {
                let a = node.axis();
                let split = node.split();
                let (o, d) = (rb.o[a], ray.dir[a]);
                // A ray parallel to the plane stays on its origin's side; `0 * inf` would be NaN.
                let t_split = if d == 0.0 {
                    f32::INFINITY
                } else {
                    (split - o) * rb.inv[a]
                };
                let below_first = o < split || (o == split && d <= 0.0);
                let (first, second) = if below_first {
                    (at + 1, node.high() as usize)
                } else {
                    (node.high() as usize, at + 1)
                };
                if t_split > t1 || t_split <= 0.0 {
                    at = first;
                } else if t_split < t0 {
                    at = second;
                } else {
                    // The build limits the depth to `STACK - 1`, and each level pushes at most once.
                    stack[sp] = MaybeUninit::new(Far {
                        node: second as u32,
                        t0: t_split,
                        t1,
                    });
                    sp += 1;
                    at = first;
                    t1 = t_split;
                }
                continue;
            }
            let count = node.high() as usize;
            stats.prim_tests += count as u64;
            let first = node.data as usize;
            for b in &self.blocks[first..first + count.div_ceil(4)] {
                let mut m = rt.candidates(b, t_max, &mut vals);
                while m != 0 {
                    let lane = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let p = b.id[lane];
                    // A primitive tested in an earlier leaf (or an earlier lane: padding repeats
                    // lane 0) either missed or is already `best` (hits beyond their leaf are kept,
                    // not discarded), so testing it again cannot help.
                    let slot = (p.wrapping_mul(0x9E37_79B9) >> 27) as usize;
                    if mail[slot] == p {
                        continue;
                    }
                    mail[slot] = p;
                    let h = match b.triangle(lane) {
                        Some(tri) => finish(&vals, lane, tri, ray, t_max),
                        None => test_primitive::<P, ANY>(prims, p as usize, ray, t_max),
                    };
                    if let Some(h) = h {
                        best = Some(Hit::new(p as usize, h));
                        if ANY {
                            return best;
                        }
                        t_max = h.t;
                    }
                }
            }
            // The closest hit lies in this cell (or before it): later cells cannot beat it.
            if t_max <= t1 || sp == 0 {
                return best;
            }
            sp -= 1;
            // SAFETY: entries below `sp` were written by the pushes above.
            let f = unsafe { stack[sp].assume_init() };
            at = f.node as usize;
            t0 = f.t0;
            t1 = f.t1;
        }
    }
}
