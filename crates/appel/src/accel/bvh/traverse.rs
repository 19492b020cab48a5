//! Stack-based front-to-back traversal of the flattened BVH.

use super::node::BvhNode;
use super::Bvh;
use crate::accel::{test_primitive, Hit, Primitives, TraversalStats};
use crate::math::{far_scale, Ray, RayBox};

impl Bvh {
    /// Dispatches on the tree depth to a traversal with a stack just large enough.
    #[inline]
    pub(super) fn traverse<P: Primitives, const ANY: bool>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        stats.rays += 1;
        if self.nodes.is_empty() {
            return None;
        }
        match self.depth {
            0..=32 => self.traverse_with::<P, ANY, 32>(prims, ray, t_max, stats),
            33..=64 => self.traverse_with::<P, ANY, 64>(prims, ray, t_max, stats),
            _ => self.traverse_with::<P, ANY, 128>(prims, ray, t_max, stats),
        }
    }

    /// pbrt-style traversal: pop a node, test its box, and at an interior node go on to the child on
    /// the near side of the split axis (by the sign of the direction) while the other waits on the
    /// stack. At most one node per level waits, so a stack of `depth` entries suffices.
    #[inline(always)]
    fn traverse_with<P: Primitives, const ANY: bool, const N: usize>(
        &self,
        prims: &P,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        let rb = RayBox::new(ray);
        let far = far_scale();
        // Nodes are culled against a slightly larger distance than the best hit, so that rounding in
        // the box test can never cull a primitive whose own test would report a nearer hit.
        let mut t_cull = t_max * far;
        let mut stack = [0u32; N];
        let mut sp = 0usize;
        let mut at = 0usize;
        let mut best = None;
        let nodes: &[BvhNode] = &self.nodes;
        loop {
            let node = &nodes[at];
            stats.nodes_visited += 1;
            if rb.hits(&node.min, &node.max, t_cull, far) {
                if node.is_leaf() {
                    let first = node.offset as usize;
                    for &p in &self.indices[first..first + node.count as usize] {
                        stats.prim_tests += 1;
                        if let Some(h) =
                            test_primitive::<P, ANY>(prims, p as usize, ray, t_max, stats)
                        {
                            best = Some(Hit::new(p as usize, h));
                            if ANY {
                                return best;
                            }
                            t_max = h.t;
                            t_cull = t_max * far;
                        }
                    }
                } else {
                    let (near, far_child) = if rb.neg[node.axis as usize] {
                        (node.offset as usize, at + 1)
                    } else {
                        (at + 1, node.offset as usize)
                    };
                    stack[sp] = far_child as u32;
                    sp += 1;
                    at = near;
                    continue;
                }
            }
            if sp == 0 {
                return best;
            }
            sp -= 1;
            at = stack[sp] as usize;
        }
    }
}
