//! Stack-based front-to-back traversal of the flattened BVH.

use super::node::BvhNode;
use super::Bvh;
use crate::accel::{test_primitive, Hit, Primitives, TraversalStats};
use crate::math::{gamma, Ray};

/// A ray prepared for box tests: reciprocal direction and the sign of each component (the sign bit,
/// so that `-0` counts as negative and gets `1 / -0 = -inf`).
#[derive(Clone, Copy)]
pub(crate) struct RayBox {
    pub o: [f32; 3],
    pub inv: [f32; 3],
    pub neg: [bool; 3],
}

/// `1 + 2 gamma(3)`: scaling the far slab distance by this keeps the slab test conservative under
/// rounding (pbrt-v4 section 6.8.2, after Ize 2013, "Robust BVH ray traversal").
#[inline]
pub(crate) fn far_scale() -> f32 {
    1.0 + 2.0 * gamma(3)
}

impl RayBox {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let inv = ray.dir.recip();
        Self {
            o: ray.origin.into(),
            inv: inv.into(),
            neg: [
                ray.dir.x.is_sign_negative(),
                ray.dir.y.is_sign_negative(),
                ray.dir.z.is_sign_negative(),
            ],
        }
    }

    /// Slab test against `[min, max]` clipped to `[0, t_max]`. A zero direction component gives an
    /// infinite `inv`: the slab distances are then `+-inf` (outside or inside the slab), or NaN when the
    /// origin lies exactly on the slab's plane; `f32::max`/`min` ignore a NaN, which counts such a ray
    /// as inside, like [`crate::math::Aabb::slab_intersect`].
    #[inline(always)]
    pub fn hits(&self, min: &[f32; 3], max: &[f32; 3], t_max: f32, far: f32) -> bool {
        let mut t0 = 0.0f32;
        let mut t1 = t_max;
        for a in 0..3 {
            let (lo, hi) = if self.neg[a] {
                (max[a], min[a])
            } else {
                (min[a], max[a])
            };
            t0 = t0.max((lo - self.o[a]) * self.inv[a]);
            t1 = t1.min((hi - self.o[a]) * self.inv[a] * far);
        }
        t0 <= t1
    }
}

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
