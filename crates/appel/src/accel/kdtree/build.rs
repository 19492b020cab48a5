//! The kd-tree's top-down SAH build (MacDonald & Booth 1990's cost model with pbrt-v3's empty-space
//! bonus and termination, Pharr et al. 2016, section 4.4.2; split candidates from clipped bounds as
//! in Wald & Havran 2006). See `docs/accel.md`.

use super::leaf::{KdBlock, LANES};
use super::node::KdNode;
use super::wide::LEVELS;
use super::{KdOptions, BINS, EMPTY_MIN, EXACT_MAX};
use crate::accel::Primitives;
use crate::math::{Aabb, Vec3};

pub(super) struct Builder<'a, P> {
    pub(super) prims: &'a P,
    pub(super) bounds: &'a [Aabb],
    pub(super) opts: KdOptions,
    /// Primitives within this distance of a split plane go to both sides, so that rounding in the
    /// traversal's `t_split` can never hide a primitive from the cell where the ray meets it.
    pub(super) margin: f32,
    pub(super) nodes: Vec<KdNode>,
    /// Leaf triangles, gathered eight by eight.
    pub(super) blocks: Vec<KdBlock>,
    /// Leaf references (primitives counted once per leaf holding them).
    pub(super) refs: usize,
    /// Nodes of at least this many primitives build their children in parallel.
    pub(super) par_min: usize,
    pub(super) root_area: f64,
    pub(super) sah: f64,
    pub(super) depth: usize,
    pub(super) leaves: usize,
}

impl<P: Primitives> Builder<'_, P> {
    fn make_leaf(&mut self, node: Aabb, ids: &[u32], depth: usize) {
        let first = self.blocks.len() as u32;
        for chunk in ids.chunks(LANES) {
            self.blocks.push(KdBlock::gather(self.prims, chunk));
        }
        self.refs += ids.len();
        self.nodes.push(KdNode::leaf(first, ids.len() as u32));
        self.leaves += 1;
        self.depth = self.depth.max(depth);
        if !ids.is_empty() {
            let o = self.opts;
            let cost = o.visit_cost + o.intersect_cost * ids.len() as f32;
            self.sah += self.rel_area(node) * cost as f64;
        }
    }

    /// The traversal cost of a split at binary depth `depth`: a node step on the first level of a
    /// three-level node, `inner_cost` on the two levels it holds below that.
    fn step_cost(&self, depth: usize) -> f32 {
        if depth.is_multiple_of(LEVELS) {
            self.opts.traversal_cost
        } else {
            self.opts.inner_cost
        }
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
    pub(super) fn build(
        &mut self,
        node: Aabb,
        ids: Vec<u32>,
        depth_left: usize,
        bad: u32,
        depth: usize,
    ) {
        let n = ids.len();
        let o = self.opts;
        if n <= o.max_prims || depth_left == 0 {
            return self.make_leaf(node, &ids, depth);
        }
        let clipped = self.clipped(node, &ids);
        let Some((below_above, axis, split)) = self.best_split(node, &clipped) else {
            return self.make_leaf(node, &ids, depth);
        };
        // The first of a three-level node's levels costs the node's step; a split on the other
        // two adds no step, only cells (`wide.rs`).
        let step = self.step_cost(depth);
        let cost = step + below_above;
        let leaf_cost = o.visit_cost + o.intersect_cost * n as f32;
        let bad = bad + (cost > leaf_cost) as u32;
        // pbrt: give up on splits far worse than a leaf for small nodes, or after three bad ones.
        if (cost > 4.0 * leaf_cost && n < 16) || bad >= o.max_bad {
            return self.make_leaf(node, &ids, depth);
        }
        let (mut bn, mut an) = (node, node);
        bn.max[axis] = split;
        an.min[axis] = split;
        let (below, above) = self.partition(ids, &clipped, axis, split, bn, an);
        drop(clipped);
        let me = self.nodes.len();
        self.nodes.push(KdNode::interior(axis, split, 0));
        self.sah += self.rel_area(node) * step as f64;
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
            blocks: Vec::new(),
            refs: 0,
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
        let first = self.blocks.len() as u32;
        self.nodes.extend(c.nodes.iter().map(|n| {
            if n.is_leaf() {
                KdNode::leaf(n.data + first, n.high())
            } else {
                KdNode::interior(n.axis(), n.split(), n.high() + base)
            }
        }));
        self.blocks.extend_from_slice(&c.blocks);
        self.refs += c.refs;
        self.sah += c.sah;
        self.depth = self.depth.max(c.depth);
        self.leaves += c.leaves;
        self.nodes.len() as u32
    }

    /// Splits `ids` between the children `bn` (below `split`) and `an` by their bounds clipped to
    /// the node (`clipped`, from [`Self::clipped`]), which the SAH counted: a primitive within the
    /// margin of the plane goes to both sides. A triangle's clipped bounds are those of the
    /// triangle's part inside the node, a convex polygon, so bounds that straddle the plane mean
    /// the triangle overlaps both children. Other primitives' bounds are only their boxes clipped
    /// to the node: one straddling the plane goes only to the children it really overlaps
    /// ([`Primitives::clip_overlaps`], against each child grown by the margin and a little more
    /// for that test's own rounding).
    fn partition(
        &self,
        ids: Vec<u32>,
        clipped: &[Aabb],
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
        for (&i, b) in ids.iter().zip(clipped) {
            let (to_b, to_a) = (b.min[axis] <= hi, b.max[axis] >= lo);
            let straddles = to_b && to_a && b.min[axis] < lo && b.max[axis] > hi;
            let (to_b, to_a) = if straddles && self.prims.watertight_triangle(i as usize).is_none()
            {
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

    /// The bounds of each primitive's part inside `node` (grown by the margin, so that a
    /// primitive the partition sent here for being within the margin keeps bounds): "perfect
    /// splits" (Havran 2000; Wald & Havran 2006, section 4.3) for triangles, clipped by
    /// Sutherland & Hodgman (1974) where their bounds reach outside the node; other primitives'
    /// boxes clipped to the node.
    fn clipped(&self, node: Aabb, ids: &[u32]) -> Vec<Aabb> {
        let m = Vec3::splat(self.margin);
        let grown = Aabb::new(node.min - m, node.max + m);
        ids.iter()
            .map(|&i| {
                let b = self.bounds[i as usize];
                let boxed = Aabb::new(b.min.max(grown.min), b.max.min(grown.max));
                if b.min.cmpge(grown.min).all() && b.max.cmple(grown.max).all() {
                    return b;
                }
                match self.prims.watertight_triangle(i as usize) {
                    Some(t) => match clip_triangle(t, grown) {
                        Some(c) => Aabb::new(c.min.max(boxed.min), c.max.min(boxed.max)),
                        // Not within the margin of the node: an empty box, on no side.
                        None => Aabb::EMPTY,
                    },
                    None => boxed,
                }
            })
            .collect()
    }

    /// SAH cost of the children of a plane with `nb` primitives below and `na` above (the
    /// traversal step is added by the caller); `pb`, `pa` the children's areas relative to the
    /// node's, `fb` the below side's fraction of the node's extent on the split axis. A non-empty
    /// child costs its visit (`visit_cost`) and its triangles; an empty one nothing, so cutting
    /// empty space away pays by itself. pbrt's empty-space bonus when one side is empty - but only for an empty slab
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
        let child = |p: f32, n: usize| {
            if n == 0 {
                0.0
            } else {
                p * (o.visit_cost + o.intersect_cost * (1.0 - bonus) * n as f32)
            }
        };
        child(pb, nb) + child(pa, na)
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
    fn best_split(&self, node: Aabb, clipped: &[Aabb]) -> Option<(f32, usize, f32)> {
        let area = node.surface_area();
        if area.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        // Dropped primitives (empty boxes) are in no child and no event.
        let clipped: Vec<Aabb> = clipped.iter().copied().filter(|b| !b.is_empty()).collect();
        let clipped = &clipped[..];
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
            if clipped.len() <= EXACT_MAX {
                self.sweep(node, area, a, clipped, &mut consider);
            } else {
                self.binned(node, area, a, clipped, &mut consider);
            }
        }
        best
    }

    /// Exact SAH sweep over the sorted clipped bounds on axis `a` (Wald & Havran 2006, algorithm
    /// 2): at each position, primitives ending there or lying flat in it leave the above side
    /// before the plane is evaluated; those starting there or flat join the below side after it.
    /// The plane is offered just above and just below the position, each counted as the partition
    /// will split it (see the comment in the loop).
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
            // The partition sends a primitive within the margin of the plane to both sides, so a
            // plane left on `x` holds everything touching `x` twice. Moved up past `x` (when no
            // other bound is near), it keeps the ending and flat ones below only and cuts the
            // starting ones (which then go to both sides); moved down, the reverse. Counting these
            // copies matters: a mesh vertex on the plane is where triangles end and start, and
            // without them the SAH sees splits through vertices as free and keeps making them,
            // copying each vertex's fan into ever more leaves.
            let (up, down) = (next - x > gap, x - prev > gap);
            if up {
                self.offer(node, area, a, x, 1.0, (nb + flat + starts, na), consider);
            }
            if down {
                self.offer(node, area, a, x, -1.0, (nb, na + ends + flat), consider);
            }
            if !up && !down {
                let touching = (nb + flat + starts, na + ends + flat);
                self.offer(node, area, a, x, 0.0, touching, consider);
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

/// The bounds of the part of triangle `t` inside box `b` (Sutherland & Hodgman 1974: the polygon
/// clipped by each of the box's six planes in turn), or `None` when they do not meet. Computed in
/// f64 and rounded outward to f32, so the bounds contain the exact part (the f64 rounding, about
/// 1e-16 of the coordinates, is far below the build's margin).
fn clip_triangle(t: [Vec3; 3], b: Aabb) -> Option<Aabb> {
    // Each plane adds at most one vertex: 3 + 6.
    let mut poly = [[0.0f64; 3]; 9];
    let mut next = [[0.0f64; 3]; 9];
    for (k, p) in t.iter().enumerate() {
        poly[k] = [p.x as f64, p.y as f64, p.z as f64];
    }
    let mut n = 3;
    for a in 0..3 {
        for (bound, keep_above) in [(b.min[a] as f64, true), (b.max[a] as f64, false)] {
            let inside = |p: &[f64; 3]| {
                if keep_above {
                    p[a] >= bound
                } else {
                    p[a] <= bound
                }
            };
            let mut m = 0;
            for k in 0..n {
                let (p, q) = (poly[k], poly[(k + 1) % n]);
                if inside(&p) {
                    next[m] = p;
                    m += 1;
                }
                if inside(&p) != inside(&q) {
                    let s = (bound - p[a]) / (q[a] - p[a]);
                    let mut x = [0.0; 3];
                    for c in 0..3 {
                        x[c] = p[c] + (q[c] - p[c]) * s;
                    }
                    x[a] = bound;
                    next[m] = x;
                    m += 1;
                }
            }
            if m == 0 {
                return None;
            }
            std::mem::swap(&mut poly, &mut next);
            n = m;
        }
    }
    let down = |x: f64| {
        let f = x as f32;
        if f as f64 > x {
            f.next_down()
        } else {
            f
        }
    };
    let up = |x: f64| {
        let f = x as f32;
        if (f as f64) < x {
            f.next_up()
        } else {
            f
        }
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in &poly[..n] {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    Some(Aabb::new(
        Vec3::new(down(lo[0]), down(lo[1]), down(lo[2])),
        Vec3::new(up(hi[0]), up(hi[1]), up(hi[2])),
    ))
}
