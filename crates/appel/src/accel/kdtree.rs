//! kd-tree with SAH splits (the cost model of MacDonald & Booth 1990 with the empty-space bonus
//! and termination rules of pbrt-v3's `KdTreeAccel`, Pharr et al. 2016, section 4.4).
//!
//! Split candidates are the primitives' bounds clipped to the node (Wald & Havran 2006 clip the
//! triangle itself, "perfect splits"; the builder sees only bounds, so it clips those): nodes of up
//! to `EXACT_MAX` primitives sweep all of them exactly, larger ones bin them into `BINS` bins over
//! the clipped bounds' extent. A primitive whose bounds straddle the chosen plane goes only to the
//! children it really overlaps (`Primitives::clip_overlaps`), so a large triangle whose bounds
//! cover a dense cluster is not copied into the cluster's leaves. Traversal keeps a small per-ray
//! mailbox, so a primitive copied into several leaves along a ray is tested once.
//! Build memory is the primitive bounds plus one index list per node on the current recursion path.
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
    /// A node becomes a leaf when it would be the `max_bad`-th split on its path that does not
    /// lower the SAH cost (pbrt: 3).
    pub max_bad: u32,
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
            max_bad: 3,
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

/// Bins per axis for nodes of more than `EXACT_MAX` primitives; smaller nodes use the exact sweep.
const BINS: usize = 1024;
const EXACT_MAX: usize = 1024;
/// Smallest empty slab, as a fraction of the node's extent, that earns the empty-space bonus.
const EMPTY_MIN: f32 = 0.125;
const STACK: usize = 64;
const PAR_MIN: usize = 1 << 15;
/// Direct-mapped per-ray mailbox, as in the grid: a primitive copied into several leaves along
/// the ray is tested once. A collision only costs a repeated test, never a skipped one.
const MAILBOX: usize = 64;

#[derive(Clone, Debug, Default)]
pub struct KdTree {
    bounds: Aabb,
    nodes: Vec<KdNode>,
    leaf_prims: Vec<u32>,
    stats: AccelStats,
}

struct Builder<'a, P> {
    prims: &'a P,
    bounds: &'a [Aabb],
    opts: KdOptions,
    /// Primitives within this distance of a split plane go to both sides, so that rounding in the
    /// traversal's `t_split` can never hide a primitive from the cell where the ray meets it.
    margin: f32,
    nodes: Vec<KdNode>,
    leaf_prims: Vec<u32>,
    /// Nodes of at least this many primitives build their children in parallel.
    par_min: usize,
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
        Self::build_par(prims, opts, PAR_MIN)
    }

    /// `par_min`: nodes of at least this many primitives build their children in parallel.
    fn build_par<P: Primitives>(prims: &P, opts: KdOptions, par_min: usize) -> Self {
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
            prims,
            bounds: &bounds,
            opts,
            margin: scale * 8.0 * f32::EPSILON,
            nodes: Vec::new(),
            leaf_prims: Vec::new(),
            root_area: root.surface_area() as f64,
            sah: 0.0,
            depth: 0,
            leaves: 0,
            par_min,
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
                    stack[sp] = (second as u32, t_split, t1);
                    sp += 1;
                    at = first;
                    t1 = t_split;
                }
                continue;
            }
            let first = node.data as usize;
            for &p in &self.leaf_prims[first..first + node.high() as usize] {
                // A primitive tested in an earlier leaf either missed or is already `best` (hits
                // beyond their leaf are kept, not discarded), so testing it again cannot help.
                let slot = (p.wrapping_mul(0x9E37_79B9) >> 26) as usize;
                if mail[slot] == p {
                    continue;
                }
                mail[slot] = p;
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

impl<P: Primitives> Builder<'_, P> {
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
        if (cost > 4.0 * leaf_cost && n < 16) || bad >= o.max_bad {
            return self.make_leaf(node, &ids, depth);
        }
        let (mut bn, mut an) = (node, node);
        bn.max[axis] = split;
        an.min[axis] = split;
        let (below, above) = self.partition(ids, axis, split, bn, an);
        let me = self.nodes.len();
        self.nodes.push(KdNode::interior(axis, split, 0));
        self.sah += self.rel_area(node) * o.traversal_cost as f64;
        if n >= self.par_min {
            // Large nodes build their children on two threads into separate arrays, appended in
            // the sequential order: the tree is the same as a sequential build's (tested).
            let (mut lb, mut ab) = (self.child(), self.child());
            rayon::join(
                || lb.build(bn, below, depth_left - 1, bad, depth + 1),
                || ab.build(an, above, depth_left - 1, bad, depth + 1),
            );
            let above_at = self.append(lb);
            self.nodes[me] = KdNode::interior(axis, split, above_at);
            self.append(ab);
            return;
        }
        self.build(bn, below, depth_left - 1, bad, depth + 1);
        let above_at = self.nodes.len() as u32;
        self.nodes[me] = KdNode::interior(axis, split, above_at);
        self.build(an, above, depth_left - 1, bad, depth + 1);
    }

    /// An empty builder for a subtree built in parallel.
    fn child(&self) -> Self {
        Self {
            nodes: Vec::new(),
            leaf_prims: Vec::new(),
            sah: 0.0,
            depth: 0,
            leaves: 0,
            ..*self
        }
    }

    /// Appends a subtree built by [`Self::child`], rebasing its child and leaf indices; returns
    /// the index of the node after it.
    fn append(&mut self, c: Self) -> u32 {
        let base = self.nodes.len() as u32;
        let first = self.leaf_prims.len() as u32;
        self.nodes.extend(c.nodes.iter().map(|n| {
            if n.is_leaf() {
                KdNode::leaf(n.data + first, n.high())
            } else {
                KdNode::interior(n.axis(), n.split(), n.high() + base)
            }
        }));
        self.leaf_prims.extend_from_slice(&c.leaf_prims);
        self.sah += c.sah;
        self.depth = self.depth.max(c.depth);
        self.leaves += c.leaves;
        self.nodes.len() as u32
    }

    /// Splits `ids` between the children `bn` (below `split`) and `an`. A primitive whose bounds
    /// straddle the plane goes only to the children it really overlaps ([`Primitives::clip_overlaps`],
    /// the triangle/box test for triangles): without this a large triangle whose bounds cover a
    /// dense cluster it does not touch (the stadium's field under the teapot) is copied into every
    /// leaf of the cluster. The test is against each child grown by the margin, so that a primitive
    /// within rounding distance of a child still goes to it.
    fn partition(
        &self,
        ids: Vec<u32>,
        axis: usize,
        split: f32,
        bn: Aabb,
        an: Aabb,
    ) -> (Vec<u32>, Vec<u32>) {
        let (lo, hi) = (split - self.margin, split + self.margin);
        let grow = |b: Aabb| {
            let g = b.extent() * 1e-4 + Vec3::splat(self.margin);
            Aabb::new(b.min - g, b.max + g)
        };
        let (gb, ga) = (grow(bn), grow(an));
        let mut below = Vec::with_capacity(ids.len());
        let mut above = Vec::with_capacity(ids.len() / 2);
        for &i in &ids {
            let b = self.bounds[i as usize];
            let (to_b, to_a) = (b.min[axis] <= hi, b.max[axis] >= lo);
            let (to_b, to_a) = if to_b && to_a && b.min[axis] < lo && b.max[axis] > hi {
                let (cb, ca) = (
                    self.prims.clip_overlaps(i as usize, &gb),
                    self.prims.clip_overlaps(i as usize, &ga),
                );
                // Neither (only possible by rounding in an earlier test): keep it on both sides.
                if cb || ca {
                    (cb, ca)
                } else {
                    (true, true)
                }
            } else {
                (to_b, to_a)
            };
            if to_b {
                below.push(i);
            }
            if to_a {
                above.push(i);
            }
        }
        (below, above)
    }

    /// SAH cost of a plane with `nb` primitives below and `na` above; `pb`, `pa` the children's
    /// areas relative to the node's, `fb` the below side's fraction of the node's extent on the
    /// split axis. pbrt's empty-space bonus when one side is empty - but only for an empty slab
    /// of at least `EMPTY_MIN` of the node: a thin sliver costs nearly the node's area either way,
    /// and with the bonus such cuts (which appear beside every subset of primitives that does not
    /// reach the node's sides) won over real splits at every level, spending the depth budget
    /// (on `uniform`: 25 tests per camera ray with the unconditional bonus, see docs/accel.md).
    #[inline]
    fn cost(&self, (pb, pa): (f32, f32), (nb, na): (usize, usize), fb: f32) -> f32 {
        let o = self.opts;
        let bonus = if (nb == 0 && fb >= EMPTY_MIN) || (na == 0 && 1.0 - fb >= EMPTY_MIN) {
            o.empty_bonus
        } else {
            0.0
        };
        o.traversal_cost + o.intersect_cost * (1.0 - bonus) * (pb * nb as f32 + pa * na as f32)
    }

    /// Relative child areas for a plane at `x` on `axis`.
    #[inline]
    fn areas(node: Aabb, area: f32, axis: usize, x: f32) -> (f32, f32) {
        let (mut bn, mut an) = (node, node);
        bn.max[axis] = x;
        an.min[axis] = x;
        (bn.surface_area() / area, an.surface_area() / area)
    }

    /// Offers the plane at `x` on axis `a` with `nb` primitives below and `na` above, moved by
    /// twice the margin in the direction `shift` (-1, 0, 1). A candidate plane lies on primitive
    /// bounds; the margin rule of [`Self::partition`] would copy the primitives that only touch it
    /// into the other child as well, which at the boundary of the geometry puts them into the
    /// empty child (and a node of `max_prims` is a leaf at once, so the empty space would never be
    /// cut away). The callers shift only where no other bound lies within the moved distance, so
    /// the counts stay right.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn offer(
        &self,
        node: Aabb,
        area: f32,
        a: usize,
        x: f32,
        shift: f32,
        (nb, na): (usize, usize),
        consider: &mut impl FnMut(f32, usize, f32),
    ) {
        let x = x + shift * 2.0 * self.margin;
        let (pb, pa) = Self::areas(node, area, a, x);
        let fb = (x - node.min[a]) / (node.max[a] - node.min[a]);
        consider(self.cost((pb, pa), (nb, na), fb), a, x);
    }

    /// The cheapest plane over the three axes, `(cost, axis, position)`, among planes strictly
    /// inside the node. Candidates come from the primitives' bounds clipped to the node (Wald &
    /// Havran 2006, section 4.3; we clip the bounds, not the triangle, since the builder sees
    /// only bounds): small nodes sweep every clipped bound exactly, large ones bin them.
    fn best_split(&self, node: Aabb, ids: &[u32]) -> Option<(f32, usize, f32)> {
        let area = node.surface_area();
        if area.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let clipped: Vec<Aabb> = ids
            .iter()
            .map(|&i| {
                let b = self.bounds[i as usize];
                Aabb::new(b.min.max(node.min), b.max.min(node.max))
            })
            .collect();
        let mut best: Option<(f32, usize, f32)> = None;
        let mut consider = |cost: f32, a: usize, x: f32| {
            if x > node.min[a] && x < node.max[a] && best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, a, x));
            }
        };
        for a in 0..3 {
            if node.extent()[a] <= 0.0 {
                continue;
            }
            if ids.len() <= EXACT_MAX {
                self.sweep(node, area, a, &clipped, &mut consider);
            } else {
                self.binned(node, area, a, &clipped, &mut consider);
            }
        }
        best
    }

    /// Exact SAH sweep over the sorted clipped bounds on axis `a` (Wald & Havran 2006, algorithm
    /// 2): at each position, primitives ending there or lying flat in it leave the above side
    /// before the plane is evaluated; those starting there or flat join the below side after it.
    /// Flat primitives are counted on the cheaper side.
    fn sweep(
        &self,
        node: Aabb,
        area: f32,
        a: usize,
        clipped: &[Aabb],
        consider: &mut impl FnMut(f32, usize, f32),
    ) {
        // Event kinds sort end < flat < start at equal positions.
        let mut events: Vec<(f32, u8)> = Vec::with_capacity(2 * clipped.len());
        for b in clipped {
            if b.min[a] == b.max[a] {
                events.push((b.min[a], 1));
            } else {
                events.push((b.min[a], 2));
                events.push((b.max[a], 0));
            }
        }
        events.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let (mut nb, mut na) = (0usize, clipped.len());
        let mut prev = f32::NEG_INFINITY;
        let mut i = 0;
        let gap = 4.0 * self.margin;
        while i < events.len() {
            let x = events[i].0;
            let mut count = [0usize; 3];
            while i < events.len() && events[i].0 == x {
                count[events[i].1 as usize] += 1;
                i += 1;
            }
            let next = events.get(i).map_or(f32::INFINITY, |e| e.0);
            let [ends, flat, starts] = count;
            na -= ends + flat;
            // Flat ones below: the plane may move up past everything ending here.
            if ends > 0 || flat > 0 {
                let up = if starts == 0 && next - x > gap {
                    1.0
                } else {
                    0.0
                };
                self.offer(node, area, a, x, up, (nb + flat, na), consider);
            }
            if flat > 0 || starts > 0 {
                // Flat ones above: the plane may move down below everything starting here.
                let down = if ends == 0 && x - prev > gap {
                    -1.0
                } else {
                    0.0
                };
                self.offer(node, area, a, x, down, (nb, na + flat), consider);
            }
            nb += starts + flat;
            prev = x;
        }
    }

    /// Binned SAH for large nodes: `BINS` bins over the extent of the clipped bounds (not the
    /// node), so that the first and last planes lie exactly on the geometry and cut off the empty
    /// space beside it in one split, as an exact sweep would; binning over the node instead left a
    /// sliver of empty space that the bonus then shaved at every level.
    fn binned(
        &self,
        node: Aabb,
        area: f32,
        a: usize,
        clipped: &[Aabb],
        consider: &mut impl FnMut(f32, usize, f32),
    ) {
        let (g0, g1) = clipped
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), b| {
                (l.min(b.min[a]), h.max(b.max[a]))
            });
        let n = clipped.len();
        if g1 <= g0 {
            // Everything flat in one plane: only that plane, with everything on either side.
            self.offer(node, area, a, g0, 1.0, (n, 0), consider);
            self.offer(node, area, a, g0, -1.0, (0, n), consider);
            return;
        }
        let inv_w = BINS as f32 / (g1 - g0);
        let bin = |x: f32| (((x - g0) * inv_w).max(0.0) as usize).min(BINS - 1);
        let mut starts = [0u32; BINS];
        let mut ends = [0u32; BINS];
        for b in clipped {
            starts[bin(b.min[a])] += 1;
            ends[bin(b.max[a])] += 1;
        }
        // Plane k (between bins k-1 and k, k = 0 and BINS on the geometry's ends): primitives
        // starting in a bin below it are below, those ending in bin k or later above. Both counts
        // can only be overestimated by the bin width; the partition itself is exact.
        let (mut nb, mut na) = (0usize, n);
        for k in 0..=BINS {
            if k > 0 {
                nb += starts[k - 1] as usize;
                na -= ends[k - 1] as usize;
            }
            let x = if k == BINS {
                g1
            } else {
                g0 + k as f32 * (g1 - g0) / BINS as f32
            };
            // The end planes lie on the geometry: move them off it, into the empty space.
            let shift = [-1.0, 0.0, 1.0][(k > 0) as usize + (k == BINS) as usize];
            self.offer(node, area, a, x, shift, (nb, na), consider);
        }
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

    #[test]
    fn small_dense_mesh_in_a_huge_sparse_one_is_cheap() {
        // The stadium's large triangles have bounds covering the teapot. Before the builder
        // clipped them (and the traversal mailboxed), they were copied into every leaf around the
        // teapot and retested in each: more tests per camera ray than primitives in the scene.
        let target = crate::bench::bench_scene("teapot-in-stadium", 5000, 64, 48).unwrap();
        let g = &target.geometry;
        let rays = crate::bench::camera_rays(&target.camera);
        let kd = KdTree::build(g);
        let bvh = crate::accel::Bvh::build(g);
        let brute = crate::accel::Brute::build(g);
        let (mut sk, mut sb, mut sr) = Default::default();
        let mut hits = 0;
        for r in &rays {
            let k = kd.intersect(g, r, f32::INFINITY, &mut sk);
            let b = bvh.intersect(g, r, f32::INFINITY, &mut sb);
            let f = brute.intersect(g, r, f32::INFINITY, &mut sr);
            assert_eq!(k.map(|h| h.t), f.map(|h| h.t));
            assert_eq!(b.map(|h| h.t), f.map(|h| h.t));
            hits += k.is_some() as usize;
        }
        assert!(hits > rays.len() / 2, "{hits}");
        let per_ray = |s: TraversalStats| s.prim_tests as f64 / s.rays as f64;
        let (k, b) = (per_ray(sk), per_ray(sb));
        assert!(k <= 3.0 * b.max(1.0), "kd-tree {k} tests per ray, bvh {b}");
        assert!(
            sk.prim_tests <= sr.prim_tests / 20,
            "{sk:?} vs brute {sr:?}"
        );
        // Build memory: the leaves hold a primitive about 11 times on average (the stadium's large
        // triangles span many cells of its surface), not hundreds.
        let n = crate::accel::Primitives::count(g);
        assert!(
            kd.leaf_prims.len() <= 16 * n,
            "{} for {n}",
            kd.leaf_prims.len()
        );
    }

    #[test]
    fn parallel_build_is_the_sequential_build() {
        let target = crate::bench::bench_scene("teapot-in-stadium", 20000, 8, 8).unwrap();
        let g = &target.geometry;
        let par = KdTree::build_par(g, KdOptions::default(), 2000);
        let seq = KdTree::build_par(g, KdOptions::default(), usize::MAX);
        assert!(par.nodes.len() > 1000);
        assert_eq!(par.nodes, seq.nodes);
        assert_eq!(par.leaf_prims, seq.leaf_prims);
        let (p, s) = (par.stats(), seq.stats());
        assert_eq!((p.nodes, p.leaves, p.depth), (s.nodes, s.leaves, s.depth));
    }
}
