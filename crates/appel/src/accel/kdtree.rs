//! kd-tree with binned SAH splits (the cost model of MacDonald & Booth 1990 with the empty-space bonus
//! and termination rules of pbrt-v3's `KdTreeAccel`, Pharr et al. 2016, section 4.4).
//!
//! Split planes are chosen by binning, not by the exact sorted-event sweep of Wald & Havran 2006:
//! 32 bins per axis, the counts of primitive bounds (clipped to the node) starting and ending in each
//! bin give the primitives on either side of every bin boundary in one prefix sum. Build memory is the
//! primitive bounds plus one index list per node on the current recursion path.
//! Nodes are 8 bytes (pbrt's `KdAccelNode`): the below child follows its parent in memory.

use super::bvh::{far_scale, RayBox};
use super::{AccelStats, Hit, Primitives, TraversalStats};
use crate::math::{Aabb, Ray, Vec3};
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KdOptions {
    pub traversal_cost: f32,
    pub intersect_cost: f32,
    /// Fraction of the cost saved when one side of a split is empty (pbrt's 0.5).
    pub empty_bonus: f32,
    /// Leaves stop splitting at this many primitives.
    pub max_prims: usize,
    /// `None`: `8 + 1.3 log2(N)`, pbrt's rule of thumb.
    pub max_depth: Option<usize>,
}

impl Default for KdOptions {
    fn default() -> Self {
        // pbrt-v3's defaults: an intersection is 80 times a traversal step, which makes the tree
        // cut away empty space aggressively.
        Self {
            traversal_cost: 1.0,
            intersect_cost: 80.0,
            empty_bonus: 0.5,
            max_prims: 2,
            max_depth: None,
        }
    }
}

/// 8 bytes. Interior: `data` is the split position's bits, `flags` holds the axis (0-2) in its low two
/// bits and the above child's index above them. Leaf: low bits 3, `data` is the first entry of the
/// leaf in `leaf_prims` and the high bits the count.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct KdNode {
    data: u32,
    flags: u32,
}

const _: () = assert!(std::mem::size_of::<KdNode>() == 8);

impl KdNode {
    fn leaf(first: u32, count: u32) -> Self {
        Self {
            data: first,
            flags: 3 | count << 2,
        }
    }

    fn interior(axis: usize, split: f32, above: u32) -> Self {
        Self {
            data: split.to_bits(),
            flags: axis as u32 | above << 2,
        }
    }

    #[inline]
    fn is_leaf(&self) -> bool {
        self.flags & 3 == 3
    }

    #[inline]
    fn axis(&self) -> usize {
        (self.flags & 3) as usize
    }

    #[inline]
    fn high(&self) -> u32 {
        self.flags >> 2
    }

    #[inline]
    fn split(&self) -> f32 {
        f32::from_bits(self.data)
    }
}

const BINS: usize = 32;
const STACK: usize = 64;

#[derive(Clone, Debug, Default)]
pub struct KdTree {
    bounds: Aabb,
    nodes: Vec<KdNode>,
    leaf_prims: Vec<u32>,
    stats: AccelStats,
}

struct Builder<'a> {
    bounds: &'a [Aabb],
    opts: KdOptions,
    /// Primitives within this distance of a split plane go to both sides, so that rounding in the
    /// traversal's `t_split` can never hide a primitive from the cell where the ray meets it.
    margin: f32,
    nodes: Vec<KdNode>,
    leaf_prims: Vec<u32>,
    root_area: f64,
    sah: f64,
    depth: usize,
    leaves: usize,
}

impl KdTree {
    pub fn build<P: Primitives>(prims: &P) -> Self {
        Self::build_with(prims, KdOptions::default())
    }

    pub fn build_with<P: Primitives>(prims: &P, opts: KdOptions) -> Self {
        let n = prims.count();
        let bounds: Vec<Aabb> = (0..n).into_par_iter().map(|i| prims.bounds(i)).collect();
        let root = bounds.iter().fold(Aabb::EMPTY, |a, &b| a.union(b));
        let ids: Vec<u32> = (0..n as u32)
            .filter(|&i| !bounds[i as usize].is_empty())
            .collect();
        let mut tree = Self {
            bounds: root,
            ..Default::default()
        };
        if ids.is_empty() {
            tree.stats = AccelStats {
                name: "kdtree",
                primitives: n,
                ..Default::default()
            };
            return tree;
        }
        let max_depth = opts
            .max_depth
            .unwrap_or_else(|| (8.0 + 1.3 * (n as f64).log2()).round() as usize)
            .min(STACK - 1);
        let scale = root.min.abs().max(root.max.abs()).max_element();
        let mut b = Builder {
            bounds: &bounds,
            opts,
            margin: scale * 8.0 * f32::EPSILON,
            nodes: Vec::new(),
            leaf_prims: Vec::new(),
            root_area: root.surface_area() as f64,
            sah: 0.0,
            depth: 0,
            leaves: 0,
        };
        b.build(root, ids, max_depth, 0, 0);
        tree.stats = AccelStats {
            name: "kdtree",
            primitives: n,
            bytes: b.nodes.len() * std::mem::size_of::<KdNode>()
                + b.leaf_prims.len() * std::mem::size_of::<u32>(),
            nodes: b.nodes.len() - b.leaves,
            leaves: b.leaves,
            depth: b.depth,
            sah_cost: Some(b.sah),
            ..Default::default()
        };
        tree.nodes = b.nodes;
        tree.leaf_prims = b.leaf_prims;
        tree
    }

    #[inline]
    fn traverse<P: Primitives, const ANY: bool>(
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
        let mut stack = [(0u32, 0.0f32, 0.0f32); STACK];
        let mut sp = 0usize;
        let mut at = 0usize;
        let mut best = None;
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
                    stack[sp] = (second as u32, t_split, t1);
                    sp += 1;
                    at = first;
                    t1 = t_split;
                }
                continue;
            }
            let first = node.data as usize;
            for &p in &self.leaf_prims[first..first + node.high() as usize] {
                stats.prim_tests += 1;
                if let Some(h) = prims.intersect(p as usize, ray, t_max) {
                    best = Some(Hit::new(p as usize, h));
                    if ANY {
                        return best;
                    }
                    t_max = h.t;
                }
            }
            // The closest hit lies in this cell (or before it): later cells cannot beat it.
            if t_max <= t1 || sp == 0 {
                return best;
            }
            sp -= 1;
            let (n, a, b) = stack[sp];
            at = n as usize;
            t0 = a;
            t1 = b;
        }
    }

    #[inline]
    pub fn intersect<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        self.traverse::<P, false>(prims, ray, t_max, stats)
    }

    #[inline]
    pub fn occluded<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> bool {
        self.traverse::<P, true>(prims, ray, t_max, stats).is_some()
    }

    pub fn stats(&self) -> AccelStats {
        self.stats.clone()
    }
}

impl Builder<'_> {
    fn make_leaf(&mut self, node: Aabb, ids: &[u32], depth: usize) {
        let first = self.leaf_prims.len() as u32;
        self.leaf_prims.extend_from_slice(ids);
        self.nodes.push(KdNode::leaf(first, ids.len() as u32));
        self.leaves += 1;
        self.depth = self.depth.max(depth);
        self.sah += self.rel_area(node) * self.opts.intersect_cost as f64 * ids.len() as f64;
    }

    fn rel_area(&self, b: Aabb) -> f64 {
        if self.root_area > 0.0 {
            b.surface_area() as f64 / self.root_area
        } else {
            1.0
        }
    }

    /// Appends the subtree for `node` holding `ids`; `depth_left` and `bad` are pbrt's depth budget
    /// and count of splits that did not lower the cost.
    fn build(&mut self, node: Aabb, ids: Vec<u32>, depth_left: usize, bad: u32, depth: usize) {
        let n = ids.len();
        let o = self.opts;
        if n <= o.max_prims || depth_left == 0 {
            return self.make_leaf(node, &ids, depth);
        }
        let Some((cost, axis, split)) = self.best_split(node, &ids) else {
            return self.make_leaf(node, &ids, depth);
        };
        let leaf_cost = o.intersect_cost * n as f32;
        let bad = bad + (cost > leaf_cost) as u32;
        // pbrt: give up on splits far worse than a leaf for small nodes, or after three bad ones.
        if (cost > 4.0 * leaf_cost && n < 16) || bad == 3 {
            return self.make_leaf(node, &ids, depth);
        }
        let (lo, hi) = (split - self.margin, split + self.margin);
        let below: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|&i| self.bounds[i as usize].min[axis] <= hi)
            .collect();
        let above: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|&i| self.bounds[i as usize].max[axis] >= lo)
            .collect();
        drop(ids);
        let me = self.nodes.len();
        self.nodes.push(KdNode::interior(axis, split, 0));
        self.sah += self.rel_area(node) * o.traversal_cost as f64;
        let (mut bn, mut an) = (node, node);
        bn.max[axis] = split;
        an.min[axis] = split;
        self.build(bn, below, depth_left - 1, bad, depth + 1);
        let above_at = self.nodes.len() as u32;
        self.nodes[me] = KdNode::interior(axis, split, above_at);
        self.build(an, above, depth_left - 1, bad, depth + 1);
    }

    /// The cheapest bin-boundary plane over the three axes: `(cost, axis, position)`.
    fn best_split(&self, node: Aabb, ids: &[u32]) -> Option<(f32, usize, f32)> {
        let o = self.opts;
        let area = node.surface_area();
        if area.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let e = node.extent();
        let mut best: Option<(f32, usize, f32)> = None;
        for a in 0..3 {
            if e[a] <= 0.0 {
                continue;
            }
            let w = e[a] / BINS as f32;
            let inv_w = BINS as f32 / e[a];
            let mut starts = [0u32; BINS];
            let mut ends = [0u32; BINS];
            let bin = |x: f32| (((x - node.min[a]) * inv_w).max(0.0) as usize).min(BINS - 1);
            for &i in ids {
                let b = self.bounds[i as usize];
                starts[bin(b.min[a])] += 1;
                ends[bin(b.max[a])] += 1;
            }
            // Plane k (between bins k-1 and k): primitives starting in a bin below it are below;
            // primitives ending in bin k or later are above (conservative by a bin's width, which
            // only overestimates the cost; the partition itself is exact).
            let mut below = 0u32;
            let mut above = ids.len() as u32;
            for k in 1..BINS {
                below += starts[k - 1];
                above -= ends[k - 1];
                let plane = node.min[a] + k as f32 * w;
                let (mut bn, mut an) = (node, node);
                bn.max[a] = plane;
                an.min[a] = plane;
                let (pb, pa) = (bn.surface_area() / area, an.surface_area() / area);
                // The bonus rewards cutting off empty space, but only a slab worth a level of the
                // tree: pbrt's exact planes cut empty space once per side, binned planes would
                // otherwise shave a thin empty sliver off at every level until the depth limit.
                let empty_slab =
                    (below == 0 && k >= BINS / 8) || (above == 0 && k <= BINS - BINS / 8);
                let bonus = if empty_slab { o.empty_bonus } else { 0.0 };
                let cost = o.traversal_cost
                    + o.intersect_cost * (1.0 - bonus) * (pb * below as f32 + pa * above as f32);
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, a, plane));
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::testutil::{agrees_with_brute, mesh, prims, rays, soup};

    fn check(m: &crate::geometry::TriangleMesh, opts: KdOptions) -> (KdTree, usize) {
        let p = prims(m);
        let kd = KdTree::build_with(&p, opts);
        let hits = agrees_with_brute(
            &p,
            &rays(400, 17),
            |r, t, s| kd.intersect(&p, r, t, s),
            |r, t, s| kd.occluded(&p, r, t, s),
        );
        (kd, hits)
    }

    #[test]
    fn agrees_with_brute_force() {
        let m = soup(3000, 31);
        for intersect_cost in [1.0, 80.0] {
            let (kd, hits) = check(
                &m,
                KdOptions {
                    intersect_cost,
                    ..Default::default()
                },
            );
            assert!(hits > 200);
            let s = kd.stats();
            let max_depth = (8.0 + 1.3 * 3000f64.log2()).round() as usize;
            assert!(s.depth <= max_depth, "{}", s.depth);
            assert_eq!(s.nodes + s.leaves, kd.nodes.len());
        }
    }

    #[test]
    fn empty_single_and_coincident_inputs() {
        check(&mesh(vec![]), KdOptions::default());
        let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let (one, _) = check(&mesh(vec![t]), KdOptions::default());
        assert_eq!(one.nodes.len(), 1);
        let (same, _) = check(&mesh(vec![t; 300]), KdOptions::default());
        // Splitting coincident primitives duplicates them all: the tree must stay small.
        assert!(
            same.leaf_prims.len() <= 300 * 4,
            "{}",
            same.leaf_prims.len()
        );
    }

    #[test]
    fn empty_space_is_cut_away() {
        // Two distant clusters: the root splits between them, and a ray through the gap visits few
        // nodes and tests nothing.
        let mut m = soup(1000, 8);
        for (k, p) in m.positions.iter_mut().enumerate() {
            *p = *p * 0.1 + Vec3::new(if k < 1500 { -5.0 } else { 5.0 }, 0.0, 0.0);
        }
        check(&m, KdOptions::default());
        let kd = KdTree::build(&prims(&m));
        let mut s = TraversalStats::default();
        let r = Ray::new(Vec3::new(0.0, -3.0, 0.0), Vec3::Y);
        assert!(kd
            .intersect(&prims(&m), &r, f32::INFINITY, &mut s)
            .is_none());
        assert_eq!(s.prim_tests, 0);
    }
}
