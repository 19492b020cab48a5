//! Front-to-back BSP traversal: the kd-tree's walk (pbrt's `KdTreeAccel::Intersect`, Pharr et al.
//! 2016, section 4.4.4) with a plane of any orientation. The near child is the side of the ray's
//! origin (for an origin on the plane, the side the ray heads into); the far child is entered at
//! `t = (d - n . o) / (n . dir)` if that lies inside the ray's interval in the cell, and waits on
//! a fixed stack, nearest on top. A leaf's closest hit that lies before the leaf's exit ends the
//! walk.

use super::{Bsp, INTERIOR, STACK};
use crate::accel::mailbox::{test_items, Mailbox};
use crate::accel::{Hit, Primitives, TraversalStats};
use crate::math::{far_scale, Ray, Vec3};

impl Bsp {
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
        let (mut t0, mut t1) =
            self.root
                .slab_intersect(ray, ray.dir.recip(), t_max * far_scale())?;
        let mut stack = [(0u32, 0.0f32, 0.0f32); STACK];
        let mut sp = 0usize;
        let mut cur = 0u32;
        let mut best = None;
        let mut mail = Mailbox::new();
        loop {
            stats.nodes_visited += 1;
            let node = &self.nodes[cur as usize];
            if node.count == INTERIOR {
                let [nx, ny, nz, d] = node.plane;
                let n = Vec3::new(nx, ny, nz);
                let dist = n.dot(ray.origin) - d;
                let den = n.dot(ray.dir);
                let below_first = dist < 0.0 || (dist == 0.0 && den <= 0.0);
                let (near, far) = if below_first {
                    (cur + 1, node.first)
                } else {
                    (node.first, cur + 1)
                };
                // Parallel to the plane: the origin's side throughout (a ray within rounding of
                // the plane finds what lies near it on either side: the margin).
                let t_split = if den == 0.0 {
                    f32::INFINITY
                } else {
                    -dist / den
                };
                if t_split > t1 || t_split <= 0.0 {
                    cur = near;
                } else if t_split < t0 {
                    cur = far;
                } else {
                    if t_split <= t_max {
                        stack[sp] = (far, t_split, t1);
                        sp += 1;
                    }
                    cur = near;
                    t1 = t_split;
                }
                continue;
            }
            let items = &self.items[node.first as usize..(node.first + node.count) as usize];
            test_items::<P, ANY>(items, prims, ray, &mut t_max, &mut best, &mut mail, stats);
            if ANY && best.is_some() {
                return best;
            }
            // The closest hit lies before this cell's exit: later cells cannot hold a nearer one
            // (a primitive whose hit the rounding of the exit moved is listed here too).
            if t_max <= t1 {
                return best;
            }
            // The waiting cells are in the order the ray crosses them.
            if sp == 0 {
                return best;
            }
            sp -= 1;
            (cur, t0, t1) = stack[sp];
            if t_max < t0 {
                return best;
            }
        }
    }
}
