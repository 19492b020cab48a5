//! Refitting a BVH whose primitives moved: the tree's shape is kept and its boxes recomputed
//! bottom-up (see `wide/refit.rs` for the wide layouts and the cost that measures the drift).

use super::{Bvh, BvhNode, Wide};
use crate::accel::Primitives;
use crate::math::Aabb;

impl Bvh {
    /// Recomputes every box (and the wide leaves' vertex copies) from `prims`, the primitives the
    /// tree was built over, moved; their count must not have changed. Returns the tree's SAH cost
    /// afterwards ([`Self::current_sah_cost`]).
    pub fn refit<P: Primitives>(&mut self, prims: &P) -> f64 {
        assert_eq!(
            prims.count(),
            self.stats.primitives,
            "a refit keeps the primitives the tree was built over"
        );
        match &mut self.wide {
            Wide::Binary => refit_binary(&mut self.nodes, &self.indices, prims),
            Wide::W4(w) => w.refit(prims),
            Wide::W8(w) => w.refit(prims),
        }
        self.current_sah_cost()
    }

    /// The SAH cost of the tree as it stands, in units of one node visit, counting one test per
    /// leaf block of the wide layouts (per primitive in the binary one). Unlike
    /// [`crate::accel::AccelStats::sah_cost`] (the build's estimate, over the binary tree) it can
    /// be computed again after a refit, and its ratio to its value at build time is the drift.
    pub fn current_sah_cost(&self) -> f64 {
        match &self.wide {
            Wide::Binary => binary_sah_cost(&self.nodes),
            Wide::W4(w) => w.sah_cost(),
            Wide::W8(w) => w.sah_cost(),
        }
    }
}

/// The binary tree's refit: nodes are in depth-first order (children after their parent), so a
/// backward pass meets every child before its parent.
fn refit_binary<P: Primitives>(nodes: &mut [BvhNode], indices: &[u32], prims: &P) {
    for at in (0..nodes.len()).rev() {
        let n = nodes[at];
        let b = if n.is_leaf() {
            indices[n.offset as usize..][..n.count as usize]
                .iter()
                .fold(Aabb::EMPTY, |b, &i| b.union(prims.bounds(i as usize)))
        } else {
            let (l, r) = (&nodes[at + 1], &nodes[n.offset as usize]);
            Aabb::new(l.min.into(), l.max.into()).union(Aabb::new(r.min.into(), r.max.into()))
        };
        nodes[at].min = b.min.to_array();
        nodes[at].max = b.max.to_array();
    }
}

fn binary_sah_cost(nodes: &[BvhNode]) -> f64 {
    let area = |n: &BvhNode| Aabb::new(n.min.into(), n.max.into()).surface_area() as f64;
    let Some(root) = nodes.first() else {
        return 0.0;
    };
    let root_area = area(root);
    if root_area <= 0.0 {
        return 0.0;
    }
    nodes
        .iter()
        .map(|n| area(n) / root_area * if n.is_leaf() { n.count as f64 } else { 1.0 })
        .sum()
}

#[cfg(test)]
mod tests {
    use crate::accel::bvh::{Bvh, BvhOptions};
    use crate::accel::testutil::{agrees_with_brute, prims, rays};
    use crate::geometry::TriangleMesh;
    use crate::math::Vec3;

    /// An `n` by `n` sheet of quads, each split as `(p0, p1, p2), (p0, p2, p3)` (so the wide
    /// builds pair them), rippled by `phase`.
    fn sheet(n: u32, phase: f32) -> TriangleMesh {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (
                    i as f32 / n as f32 * 2.0 - 1.0,
                    j as f32 / n as f32 * 2.0 - 1.0,
                );
                positions.push(Vec3::new(x, y, 0.3 * (3.0 * x + phase).sin() * y));
            }
        }
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut indices = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (p0, p1, p2, p3) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                indices.push([p0, p1, p2]);
                indices.push([p0, p2, p3]);
            }
        }
        TriangleMesh {
            positions,
            indices,
            normals: None,
            uvs: None,
        }
    }

    #[test]
    fn a_refitted_tree_answers_as_brute_force_and_unmoved_keeps_its_cost() {
        let rays = rays(400, 7);
        for width in [2, 4, 8] {
            for (pairs, compact) in [(true, false), (false, false), (false, true)] {
                let opts = BvhOptions {
                    width,
                    pairs,
                    compact,
                    ..Default::default()
                };
                let rest = sheet(24, 0.0);
                let mut bvh = Bvh::build_with(&prims(&rest), opts);
                let built = bvh.current_sah_cost();
                assert_eq!(bvh.refit(&prims(&rest)), built, "width {width}");
                let moved = sheet(24, 2.0);
                let p = prims(&moved);
                let cost = bvh.refit(&p);
                assert!(cost > 0.0 && cost.is_finite());
                let hits = agrees_with_brute(
                    &p,
                    &rays,
                    |r, t, s| bvh.intersect(&p, r, t, s),
                    |r, t, s| bvh.occluded(&p, r, t, s),
                );
                assert!(hits > 50, "width {width}: {hits} hits");
            }
        }
    }

    #[test]
    fn scrambling_the_primitives_makes_the_cost_drift() {
        // The same triangles, their ids shuffled: the refitted tree groups far-apart triangles.
        let a = sheet(32, 0.0);
        let mut b = a.clone();
        let n = a.indices.len();
        // 7919 is prime and does not divide n = 2048, so this is a permutation.
        b.indices = (0..n).map(|k| a.indices[k * 7919 % n]).collect();
        let mut bvh = Bvh::build(&prims(&a));
        let built = bvh.current_sah_cost();
        let drifted = bvh.refit(&prims(&b));
        assert!(drifted > 3.0 * built, "{built} -> {drifted}");
    }
}
