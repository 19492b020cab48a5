//! Binary space partitioning tree with planes of any orientation (Fuchs, Kedem & Naylor 1980, "On
//! visible surface generation by a priori tree structures", whose split planes are the scene's own
//! polygons' planes). Each node cuts its cell, a convex polytope, in two; a primitive goes to the
//! side its vertices (or, if it has none to give, its bounds' corners) lie on, and to both when
//! they straddle the plane. Candidate planes (`candidates.rs`) are the supporting planes of a
//! sample of the node's triangles and the 13 directions of a 26-DOP at the primitives' extents;
//! the cheapest by the surface area heuristic over the convex cells' areas (`polytope.rs`) wins.
//! Traversal (`traverse.rs`) is the kd-tree's front-to-back walk with a general plane: the near
//! side is the origin's, the far side is entered at the plane's crossing.
//!
//! Nodes are 24 bytes (`BspNode`): the plane, the above child's index (the below child follows
//! its parent) or a leaf's range of the flat item list.

mod build;
mod candidates;
mod polytope;
mod shape;
#[cfg(test)]
mod tests;
mod traverse;

use super::{AccelStats, BadOption, Hit, Primitives, Structure, TraversalStats};
use crate::math::{Aabb, Ray, Vec3};
use build::Builder;

/// `[render.bsp]`; costs are in units of `traversal_cost`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct BspOptions {
    /// A node step (a dot product pair and a division), the unit of the costs.
    pub traversal_cost: f32,
    /// Testing one primitive of a leaf (the scalar watertight test): about two node steps
    /// (docs/accel.md).
    pub intersect_cost: f32,
    /// Entering a non-empty leaf, beyond its primitives' tests (the loop, the early-exit test).
    pub visit_cost: f32,
    /// Nodes of this many primitives or fewer are leaves.
    pub max_prims: usize,
    /// `None`: `8 + 1.3 log2(N)`, pbrt's rule for kd-trees; at most [`MAX_DEPTH`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_depth: Option<usize>,
    /// Supporting planes of this many of a node's triangles, evenly spread through its list, are
    /// candidates (Fuchs et al.'s autopartition, sampled: every triangle's plane would cost
    /// O(N^2) per node to count).
    pub triangle_planes: usize,
    /// Planes per direction of the 26-DOP (binned over the extent of the node's primitives along
    /// it, plus the two extremes, which cut the empty space off), for nodes of up to `64 * bins`
    /// primitives; larger nodes take one per 64 primitives, at most 64. 0 for none.
    pub bins: usize,
}

impl Default for BspOptions {
    fn default() -> Self {
        Self {
            traversal_cost: 1.0,
            intersect_cost: 2.0,
            visit_cost: 1.0,
            max_prims: 2,
            max_depth: None,
            triangle_planes: 8,
            bins: 8,
        }
    }
}

/// The deepest tree the traversal's stack allows (one waiting cell per level).
pub const MAX_DEPTH: usize = 63;
const STACK: usize = MAX_DEPTH + 1;

/// Interior: `count == INTERIOR`, the plane is `n . x = d` with `plane = [n.x, n.y, n.z, d]`, the
/// below child (`n . x < d`) is the next node and `first` the above child's index. Leaf: its
/// primitives are `items[first..first + count]`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct BspNode {
    plane: [f32; 4],
    first: u32,
    count: u32,
}

const INTERIOR: u32 = u32::MAX;
const _: () = assert!(std::mem::size_of::<BspNode>() == 24);

#[derive(Clone, Debug, Default)]
pub struct Bsp {
    /// The root cell; rays are clipped to it before the first plane.
    root: Aabb,
    nodes: Vec<BspNode>,
    items: Vec<u32>,
    /// Interior nodes whose plane is not axis-aligned, to show how often oblique planes win.
    oblique: usize,
    stats: AccelStats,
}

/// A primitive within this many ulps of the scene's largest coordinate of a plane goes to both
/// sides: the traversal's plane crossing `(d - n . o) / (n . dir)` has a rounding error, in
/// distance from the plane, of about 30 ulps of that coordinate for a ray starting within the
/// scene's coordinate range (a three-term dot product with the origin and the subtraction of `d`,
/// about 9; the other with the direction, over the ray's length in the scene, about 18; the
/// division, about 4), and a hit the rounding moves across a plane must be found in the cell the
/// walk puts it in. (The kd-tree, whose crossing is one subtraction and one multiplication,
/// takes 8.)
const MARGIN_ULPS: f32 = 32.0;

impl Bsp {
    pub fn build<P: Primitives>(prims: &P) -> Self {
        Self::build_with(prims, BspOptions::default())
    }

    pub fn build_with<P: Primitives>(prims: &P, opts: BspOptions) -> Self {
        let n = prims.count();
        let mut tree = Self {
            stats: AccelStats {
                name: Self::NAME,
                primitives: n,
                ..Default::default()
            },
            ..Default::default()
        };
        let shapes = shape::shapes(prims);
        let scene = shapes.iter().fold(Aabb::EMPTY, |a, s| a.union(s.bounds()));
        let ids: Vec<u32> = (0..n as u32)
            .filter(|&i| !shapes[i as usize].bounds().is_empty())
            .collect();
        if ids.is_empty() {
            return tree;
        }
        let scale = scene.min.abs().max(scene.max.abs()).max_element();
        let margin = scale * MARGIN_ULPS * f32::EPSILON;
        let grow = Vec3::splat(2.0 * margin) + scene.extent() * 1e-4;
        tree.root = Aabb::new(scene.min - grow, scene.max + grow);
        let max_depth = opts
            .max_depth
            .unwrap_or_else(|| (8.0 + 1.3 * (n as f64).log2()).round() as usize)
            .min(MAX_DEPTH);
        let mut b = Builder {
            prims,
            shapes: &shapes,
            opts,
            max_depth,
            margin: margin as f64,
            nodes: Vec::new(),
            items: Vec::new(),
            depth: 0,
            leaves: 0,
            oblique: 0,
            root_area: 0.0,
            sah: 0.0,
        };
        b.build_root(tree.root, ids);
        tree.stats.bytes = b.nodes.len() * std::mem::size_of::<BspNode>()
            + b.items.len() * std::mem::size_of::<u32>();
        tree.stats.nodes = b.nodes.len() - b.leaves;
        tree.stats.leaves = b.leaves;
        tree.stats.depth = b.depth;
        tree.stats.sah_cost = Some(b.sah);
        tree.oblique = b.oblique;
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

    /// Interior nodes whose plane is not perpendicular to an axis.
    pub fn oblique_planes(&self) -> usize {
        self.oblique
    }
}

impl Structure for Bsp {
    const NAME: &'static str = "bsp";
    type Options = BspOptions;

    fn check_options(o: &BspOptions) -> Result<(), BadOption> {
        BadOption::check_positive("traversal_cost", o.traversal_cost)?;
        BadOption::check_positive("intersect_cost", o.intersect_cost)?;
        BadOption::check_non_negative("visit_cost", o.visit_cost)?;
        BadOption::check_range("max_prims", o.max_prims, 1, 1 << 20)?;
        if let Some(d) = o.max_depth {
            BadOption::check_range("max_depth", d, 1, MAX_DEPTH)?;
        }
        BadOption::check_range("triangle_planes", o.triangle_planes, 0, 1024)?;
        BadOption::check_range("bins", o.bins, 0, candidates::MAX_BINS)
    }

    fn build<P: Primitives>(prims: &P, options: &BspOptions) -> Self {
        Bsp::build_with(prims, *options)
    }

    crate::accel::structure::forward_queries!(Bsp);
}
