//! Adaptive octree (Glassner 1984, "Space subdivision for fast ray tracing"): a cubical root cell
//! around the scene, split into eight equal children while it lists more than a leaf's worth of
//! primitives, down to a depth limit. Each primitive is listed in every cell it overlaps, by the
//! same exact answer the grid and the kd-tree ask ([`Primitives::clip_overlaps`]: the separating
//! axis triangle/box test for triangles). Traversal (`traverse.rs`) visits the children a ray
//! crosses in the order it crosses them, after Revelles, Urena & Lastra 2000 ("An efficient
//! parametric algorithm for octree traversal"), with a per-ray mailbox and an early exit.
//!
//! Nodes are 8 bytes (`OctNode`), the eight children of a node consecutive (one cache line), so a
//! node is an index and the boxes are implied by the root's: no pointers, nothing per primitive
//! but its id in the leaves' flat list.

mod build;
#[cfg(test)]
mod tests;
mod traverse;

use super::{AccelStats, BadOption, Hit, Primitives, Structure, TraversalStats};
use crate::math::{Aabb, Ray, Vec3};
use build::Builder;
use rayon::prelude::*;

/// `[render.octree]`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct OctreeOptions {
    /// A cell listing more primitives than this splits into eight. 8: a leaf's primitives are
    /// tested one by one (scalar), and eight tests cost about as much as the node steps a further
    /// split adds to every ray crossing the cell (docs/accel.md).
    pub max_prims: usize,
    /// Cells at this depth (the root is depth 0) stay leaves, however many primitives they list.
    /// 16: a cell of 1/65,536 of the root's side, fine enough for a dense mesh in a large scene
    /// (the teapot in the stadium); at most [`MAX_DEPTH`].
    pub max_depth: usize,
}

impl Default for OctreeOptions {
    fn default() -> Self {
        Self {
            max_prims: 8,
            max_depth: 16,
        }
    }
}

/// The deepest octree traversal's stack allows: a node pushes at most three of the four children a
/// ray crosses, so a path of `MAX_DEPTH` nodes keeps at most `3 * MAX_DEPTH` waiting.
pub const MAX_DEPTH: usize = 24;
const STACK: usize = 3 * MAX_DEPTH + 1;

/// Interior: `count == INTERIOR` and `first` is the first of its eight consecutive children, in
/// the order of their octant bits (bit `a` set: the upper half on axis `a`). Leaf: its primitives
/// are `items[first..first + count]`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct OctNode {
    first: u32,
    count: u32,
}

const INTERIOR: u32 = u32::MAX;
const _: () = assert!(std::mem::size_of::<OctNode>() == 8);

#[derive(Clone, Debug, Default)]
pub struct Octree {
    /// The root cell: a cube around the scene's bounds.
    root: Aabb,
    /// Node 0 is the root; empty for a scene without primitives.
    nodes: Vec<OctNode>,
    items: Vec<u32>,
    stats: AccelStats,
}

impl Octree {
    pub fn build<P: Primitives>(prims: &P) -> Self {
        Self::build_with(prims, OctreeOptions::default())
    }

    pub fn build_with<P: Primitives>(prims: &P, opts: OctreeOptions) -> Self {
        let n = prims.count();
        let bounds: Vec<Aabb> = (0..n).into_par_iter().map(|i| prims.bounds(i)).collect();
        let scene = bounds.iter().fold(Aabb::EMPTY, |a, &b| a.union(b));
        let ids: Vec<u32> = (0..n as u32)
            .filter(|&i| !bounds[i as usize].is_empty())
            .collect();
        let mut tree = Self {
            stats: AccelStats {
                name: Self::NAME,
                primitives: n,
                ..Default::default()
            },
            ..Default::default()
        };
        if ids.is_empty() {
            return tree;
        }
        // A cube, so that every cell is a cube (Glassner's octree); its side is the scene's largest
        // extent, grown a little so that no primitive lies on the root's faces.
        let half = 0.5 * scene.extent().max_element();
        let scale = scene.min.abs().max(scene.max.abs()).max_element();
        let margin = scale * MARGIN_ULPS * f32::EPSILON;
        let half = Vec3::splat(half * (1.0 + 1e-4) + 2.0 * margin);
        let c = scene.center();
        tree.root = Aabb::new(c - half, c + half);
        let mut b = Builder {
            prims,
            bounds: &bounds,
            max_prims: opts.max_prims.max(1),
            max_depth: opts.max_depth.min(MAX_DEPTH),
            margin,
            nodes: vec![OctNode::default()],
            items: Vec::new(),
            depth: 0,
            leaves: 0,
        };
        b.build(0, tree.root, ids, 0);
        tree.stats.bytes = b.nodes.len() * std::mem::size_of::<OctNode>()
            + b.items.len() * std::mem::size_of::<u32>();
        tree.stats.nodes = b.nodes.len() - b.leaves;
        tree.stats.leaves = b.leaves;
        tree.stats.depth = b.depth;
        tree.nodes = b.nodes;
        tree.items = b.items;
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

/// A primitive within this many ulps of the scene's largest coordinate of a cell's face is listed
/// in the cell on the face's other side too: the traversal computes the ray's crossing of a
/// central plane as `(c - o) / dir` (a subtraction and a multiplication by the rounded
/// reciprocal), whose point lies within a few ulps of `|c - o|` of the plane, and a hit the
/// rounding moves across the face must be found in the cell the walk puts it in. The kd-tree's
/// planes are crossed the same way and take the same 8 ulps; this is what `accel_agreement`
/// checks, with origins up to twice the scene's extent away.
const MARGIN_ULPS: f32 = 8.0;

/// The box of child `k` of the cell `b` (bit `a` of `k` set: the upper half on axis `a`). The
/// builder and the traversal both take the centre as `(min + max) / 2` from the same floats, so
/// their cells are the same to the bit.
#[inline(always)]
pub(crate) fn child_box(b: &Aabb, k: usize) -> Aabb {
    let c = b.center();
    let mut r = *b;
    for a in 0..3 {
        if k >> a & 1 == 1 {
            r.min[a] = c[a];
        } else {
            r.max[a] = c[a];
        }
    }
    r
}

impl Structure for Octree {
    const NAME: &'static str = "octree";
    type Options = OctreeOptions;

    fn check_options(o: &OctreeOptions) -> Result<(), BadOption> {
        BadOption::check_range("max_prims", o.max_prims, 1, 1 << 20)?;
        BadOption::check_range("max_depth", o.max_depth, 0, MAX_DEPTH)
    }

    fn build<P: Primitives>(prims: &P, options: &OctreeOptions) -> Self {
        Octree::build_with(prims, *options)
    }

    crate::accel::structure::forward_queries!(Octree);
}
