//! Front-to-back octree traversal after Revelles, Urena & Lastra 2000: in a cell the ray crosses
//! during `[t0, t1]`, the parameters at which it crosses the cell's three central planes give the
//! octants it visits and their order - the first octant is the one holding the ray at `t0`, and
//! each crossing inside `(t0, t1)`, taken in increasing order, flips that axis's bit (the paper's
//! state transitions). Revelles et al. mirror the ray into the positive octant and take the
//! central parameters as the means of the cell's slab parameters; here the central planes'
//! parameters are computed from the planes themselves, so a zero direction component (an
//! infinite parameter, whose mean with its opposite is NaN) needs no special case beyond "never
//! crosses". Octants waiting wait on a fixed stack, nearest on top; empty leaves are never pushed
//! (the eight children share a cache line, so looking is cheap).

use super::{child_box, Octree, INTERIOR, STACK};
use crate::accel::mailbox::{test_items, Mailbox};
use crate::accel::{Hit, Primitives, TraversalStats};
use crate::math::{far_scale, Aabb, Ray, RayBox, Vec3};
use std::mem::MaybeUninit;

/// A cell waiting to be visited, with the ray's interval in it.
#[derive(Clone, Copy)]
struct Waiting {
    node: u32,
    cell: Aabb,
    t0: f32,
    t1: f32,
}

impl Octree {
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
        let inv = Vec3::from(rb.inv);
        let (t0, t1) = self.root.slab_intersect(ray, inv, t_max * far_scale())?;
        let mut cur = Waiting {
            node: 0,
            cell: self.root,
            t0,
            t1,
        };
        // Uninitialised: a ray rarely needs more than a few entries of the 73.
        let mut stack = [const { MaybeUninit::<Waiting>::uninit() }; STACK];
        let mut sp = 0usize;
        let mut best = None;
        let mut mail = Mailbox::new();
        loop {
            stats.nodes_visited += 1;
            let n = self.nodes[cur.node as usize];
            if n.count == INTERIOR {
                let mut order = [(0u32, 0.0f32, 0.0f32); 4];
                let k = octants(ray, inv, &cur, &mut order);
                // Push the later octants, farthest first, and go on into the first non-empty one.
                let mut next = None;
                for &(o, s0, s1) in order[..k].iter().rev() {
                    let child = n.first + o;
                    if self.nodes[child as usize].count == 0 || s0 > t_max {
                        continue;
                    }
                    if let Some(w) = next.replace(Waiting {
                        node: child,
                        cell: child_box(&cur.cell, o as usize),
                        t0: s0,
                        t1: s1,
                    }) {
                        stack[sp] = MaybeUninit::new(w);
                        sp += 1;
                    }
                }
                if let Some(w) = next {
                    cur = w;
                    continue;
                }
            } else {
                let items = &self.items[n.first as usize..(n.first + n.count) as usize];
                test_items::<P, ANY>(items, prims, ray, &mut t_max, &mut best, &mut mail, stats);
                if ANY && best.is_some() {
                    return best;
                }
                // The closest hit lies before this cell's exit: the cells after it cannot hold a
                // nearer one (one whose hit the rounding of the exit moved is listed here too).
                if t_max <= cur.t1 {
                    return best;
                }
            }
            // The waiting cells are in the order the ray crosses them: once the nearest starts
            // beyond the closest hit, so do the others.
            if sp == 0 {
                return best;
            }
            sp -= 1;
            // SAFETY: entries below `sp` were written by the pushes above.
            cur = unsafe { stack[sp].assume_init() };
            if t_max < cur.t0 {
                return best;
            }
        }
    }
}

/// The octants of `w.cell` the ray crosses during `[w.t0, w.t1]`, in order: `(octant, t_in,
/// t_out)` in `out[..k]`; returns `k` (1 to 4).
#[inline(always)]
fn octants(ray: &Ray, inv: Vec3, w: &Waiting, out: &mut [(u32, f32, f32); 4]) -> usize {
    let c = w.cell.center();
    let mut bits = 0u32;
    // The central planes crossed inside the interval: (t, axis bit).
    let mut cross = [(f32::INFINITY, 0u32); 3];
    let mut nc = 0;
    for a in 0..3 {
        let d = ray.dir[a];
        if d == 0.0 {
            // Parallel to the plane: the side of the origin throughout (on the plane itself,
            // either: primitives within the margin of it are listed on both sides).
            bits |= ((ray.origin[a] >= c[a]) as u32) << a;
            continue;
        }
        let t = (c[a] - ray.origin[a]) * inv[a];
        // Before the crossing the ray is on the lower side if it moves up, and the reverse.
        let crossed = t <= w.t0;
        bits |= (((d > 0.0) == crossed) as u32) << a;
        if !crossed && t < w.t1 {
            cross[nc] = (t, 1 << a);
            nc += 1;
        }
    }
    // Three elements: a sorting network.
    if cross[1].0 < cross[0].0 {
        cross.swap(0, 1);
    }
    if cross[2].0 < cross[1].0 {
        cross.swap(1, 2);
        if cross[1].0 < cross[0].0 {
            cross.swap(0, 1);
        }
    }
    let mut t = w.t0;
    for (k, &(tc, bit)) in cross[..nc].iter().enumerate() {
        out[k] = (bits, t, tc);
        bits ^= bit;
        t = tc;
    }
    out[nc] = (bits, t, w.t1);
    nc + 1
}
