//! kd-tree with SAH splits (the cost model of MacDonald & Booth 1990 with the empty-space bonus
//! and termination rules of pbrt-v3's `KdTreeAccel`, Pharr et al. 2016, section 4.4).
//!
//! Split candidates are the primitives' bounds clipped to the node (Wald & Havran 2006 clip the
//! triangle itself, "perfect splits"; the builder sees only bounds, so it clips those): nodes of up
//! to `EXACT_MAX` primitives sweep all of them exactly, larger ones bin them into `BINS` bins over
//! the clipped bounds' extent. A primitive whose bounds straddle the chosen plane goes only to the
//! children it really overlaps (`Primitives::clip_overlaps`), so a large triangle whose bounds
//! cover a dense cluster is not copied into the cluster's leaves. Leaves store their triangles
//! gathered into SIMD blocks of eight (`leaf.rs`); traversal filters a block at once and passes
//! the survivors through a small per-ray mailbox, so a primitive copied into several leaves along
//! a ray is tested once. Build memory is the primitive bounds plus one index list per node on
//! the current recursion path. The builder makes 8-byte binary nodes (pbrt's `KdAccelNode`,
//! `node.rs`), which are then collapsed three levels at a time into 128-byte nodes of seven planes
//! and eight cells (`wide.rs`) that traversal tests in one 8-lane step.

mod build;
mod leaf;
mod node;
#[cfg(test)]
mod tests;
mod traverse;
mod wide;

pub use node::KdNode;
pub use wide::KdNode8;

use super::{AccelStats, BadOption, Hit, Primitives, Structure, TraversalStats};
use crate::math::{Aabb, Ray};
use build::Builder;
use leaf::KdBlock;
use rayon::prelude::*;

/// `[render.kdtree]`; costs are in units of a node step.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct KdOptions {
    /// A node step: the cost of a split on the first of a three-level node's levels.
    pub traversal_cost: f32,
    /// A split on the second or third level of a three-level node: the node's step computes all
    /// three levels at once, so such a split adds cells to cross, not a step.
    pub inner_cost: f32,
    /// Visiting a non-empty leaf, beyond its triangles: the pop, the leaf-or-node branch and the
    /// loop over its blocks.
    pub visit_cost: f32,
    /// Per triangle of a leaf.
    pub intersect_cost: f32,
    /// Fraction of the cost saved when one side of a split is empty (pbrt's 0.5).
    pub empty_bonus: f32,
    /// Leaves stop splitting at this many primitives.
    pub max_prims: usize,
    /// `None`: `8 + 1.3 log2(N)`, pbrt's rule of thumb; at most `STACK - 1`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_depth: Option<usize>,
    /// A node becomes a leaf when it would be the `max_bad`-th split on its path that does not
    /// lower the SAH cost (pbrt: 3; here 1, the first).
    pub max_bad: u32,
}

impl Default for KdOptions {
    fn default() -> Self {
        // Not pbrt-v3's (80:1, leaves of 2, 3 bad splits), in units of a node step: leaves test
        // their triangles eight at a time, so one triangle costs a tenth of a step, whose latency
        // (a dependent load and the eight cells' intervals) bounds the traversal; pbrt's 80:1
        // copies triangles into many leaves and drives every path to the depth limit. A
        // non-empty leaf costs two steps to enter (loading its first block costs about as much as
        // a step and a half), which replaces the empty-space bonus (empty children cost nothing);
        // a split on a node's lower two levels costs 0.3, since the node's step computes them
        // anyway. Together they give fewer lanes and nodes per ray (docs/performance.md).
        Self {
            traversal_cost: 1.0,
            inner_cost: 0.3,
            visit_cost: 2.0,
            intersect_cost: 0.1,
            empty_bonus: 0.0,
            max_prims: 4,
            max_depth: None,
            max_bad: 1,
        }
    }
}

/// Bins per axis for nodes of more than `EXACT_MAX` primitives; smaller nodes use the exact sweep.
const BINS: usize = 1024;
const EXACT_MAX: usize = 1024;
/// Smallest empty slab, as a fraction of the node's extent, that earns the empty-space bonus.
const EMPTY_MIN: f32 = 0.125;
const STACK: usize = 64;
/// Cells a traversal may have waiting: a three-level node pushes at most seven, and the binary depth
/// limit (`STACK - 1`) allows `STACK / 3 + 1` such nodes on a path.
const WIDE_STACK: usize = (STACK / 3 + 1) * 7 + 1;
const PAR_MIN: usize = 1 << 15;

#[derive(Clone, Debug, Default)]
pub struct KdTree {
    bounds: Aabb,
    /// Three levels of the binary tree per node (`wide.rs`); the binary nodes are dropped once
    /// collapsed.
    nodes: Vec<KdNode8>,
    /// The root's cell; `None` for a tree without primitives.
    root: Option<wide::Cell>,
    /// Nodes of the binary tree (interior and leaves), as built.
    binary_nodes: usize,
    /// Whether traversal prefetches the cells it pushes ([`crate::accel::PREFETCH_BYTES`]).
    prefetch: bool,
    /// Leaf triangles in SIMD blocks of eight; a leaf's blocks are consecutive.
    blocks: Vec<KdBlock>,
    /// Leaf references: each primitive counted once per leaf that holds it.
    refs: usize,
    stats: AccelStats,
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
                name: Self::NAME,
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
            blocks: Vec::new(),
            refs: 0,
            root_area: root.surface_area() as f64,
            sah: 0.0,
            depth: 0,
            leaves: 0,
            par_min,
        };
        b.build(root, ids, max_depth, 0, 0);
        let mut nodes = Vec::new();
        tree.root = wide::collapse(&b.nodes, &mut nodes);
        tree.stats = AccelStats {
            name: Self::NAME,
            primitives: n,
            bytes: nodes.len() * std::mem::size_of::<KdNode8>()
                + b.blocks.len() * std::mem::size_of::<KdBlock>(),
            nodes: b.nodes.len() - b.leaves,
            leaves: b.leaves,
            depth: b.depth,
            sah_cost: Some(b.sah),
            ..Default::default()
        };
        tree.binary_nodes = b.nodes.len();
        tree.prefetch = tree.stats.bytes > crate::accel::PREFETCH_BYTES;
        tree.nodes = nodes;
        tree.blocks = b.blocks;
        tree.refs = b.refs;
        tree
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

impl Structure for KdTree {
    const NAME: &'static str = "kdtree";
    type Options = KdOptions;

    fn check_options(o: &KdOptions) -> Result<(), BadOption> {
        BadOption::check_positive("traversal_cost", o.traversal_cost)?;
        BadOption::check_non_negative("inner_cost", o.inner_cost)?;
        BadOption::check_non_negative("visit_cost", o.visit_cost)?;
        BadOption::check_positive("intersect_cost", o.intersect_cost)?;
        BadOption::check_range("empty_bonus", o.empty_bonus, 0.0, 1.0)?;
        BadOption::check_range("max_prims", o.max_prims, 1, 1 << 20)?;
        if let Some(d) = o.max_depth {
            BadOption::check_range("max_depth", d, 1, STACK - 1)?;
        }
        BadOption::check_range("max_bad", o.max_bad, 1, 64)
    }

    fn build<P: Primitives>(prims: &P, options: &KdOptions) -> Self {
        KdTree::build_with(prims, *options)
    }

    crate::accel::structure::forward_queries!(KdTree);
}
