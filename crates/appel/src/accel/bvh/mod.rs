//! Bounding volume hierarchy: binned-SAH (or midpoint / median) build, flattened 32-byte nodes,
//! front-to-back stack traversal. See `docs/accel.md`.

mod build;
mod build_prim;
mod node;
mod pairs;
mod refit;
mod traverse;
mod wide;

pub use build::{BvhOptions, BvhSplit};
pub use node::BvhNode;
pub use wide::{QuadBlock, TriBlock, WideBvh, WideNode, PACKET};

use super::{AccelStats, BadOption, Hit, Primitives, Structure, TraversalStats};
#[cfg(test)]
use crate::math::Vec3;
use crate::math::{Aabb, Ray};
use rayon::prelude::*;

#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// The binary tree; emptied once collapsed into a wide one.
    nodes: Vec<BvhNode>,
    /// Primitive ids in leaf order: leaf `[offset, offset + count)` is a range of this array.
    indices: Vec<u32>,
    /// The tree traversal uses when `BvhOptions::width` is 4 or 8.
    wide: Wide,
    /// Edges from the root to the deepest leaf.
    depth: usize,
    stats: AccelStats,
}

#[derive(Clone, Debug, Default)]
enum Wide {
    #[default]
    Binary,
    W4(WideBvh<4>),
    W8(WideBvh<8>),
}

impl Bvh {
    pub fn build<P: Primitives>(prims: &P) -> Self {
        Self::build_with(prims, BvhOptions::default())
    }

    pub fn build_with<P: Primitives>(prims: &P, opts: BvhOptions) -> Self {
        let n = prims.count();
        assert!(
            n < u32::MAX as usize,
            "a BVH indexes primitives with u32, got {n}"
        );
        assert!(
            matches!(opts.width, 2 | 4 | 8),
            "BVH width must be 2, 4 or 8, not {}",
            opts.width
        );
        // Wide trees with vertex blocks build over pairs of triangles where the mesh is made of
        // quads: each item then stands for two triangles, and the costs count blocks of pairs.
        let items = (opts.width > 2 && !opts.compact && opts.pairs)
            .then(|| pairs::pair_up(prims))
            .flatten();
        let item_count = items.as_ref().map_or(n, Vec::len);
        let opts = if build::SMALL_TREE_ITEMS.contains(&item_count) {
            opts.for_small_tree()
        } else {
            opts
        };
        let build_opts = if items.is_some() {
            opts.for_pairs()
        } else {
            opts
        };
        let mut refs: Vec<build::BuildPrim> = match &items {
            Some(items) => items
                .par_iter()
                .enumerate()
                .map(|(k, &code)| build::BuildPrim::new(pairs::item_bounds(prims, code), k as u32))
                .collect(),
            None => (0..n)
                .into_par_iter()
                .map(|i| build::BuildPrim::new(prims.bounds(i), i as u32))
                .collect(),
        };
        let nodes = build::build(&build::Ctx { opts: build_opts }, &mut refs);
        let indices: Vec<u32> = refs.par_iter().map(|r| r.id()).collect();
        drop(refs);
        let mut bvh = Self {
            nodes,
            indices,
            wide: Wide::Binary,
            depth: 0,
            stats: AccelStats::default(),
        };
        bvh.measure(&build_opts);
        bvh.stats.primitives = n;
        /// The wide tree, the binary nodes freed before its leaves are filled.
        fn collapse<P: Primitives, const W: usize>(
            prims: &P,
            bvh: &mut Bvh,
            items: &Option<Vec<u32>>,
            compact: bool,
        ) -> WideBvh<W> {
            let c = WideBvh::collapse(&bvh.nodes);
            bvh.nodes = Vec::new();
            match items {
                Some(items) => WideBvh::from_collapsed_paired(prims, c, &bvh.indices, items),
                None => WideBvh::from_collapsed(prims, c, &bvh.indices, compact),
            }
        }
        let (bytes, counts, wide) = match opts.width {
            2 => return bvh,
            4 => {
                let w = collapse::<P, 4>(prims, &mut bvh, &items, opts.compact);
                (w.bytes(), w.counts(), Wide::W4(w))
            }
            _ => {
                let w = collapse::<P, 8>(prims, &mut bvh, &items, opts.compact);
                (w.bytes(), w.counts(), Wide::W8(w))
            }
        };
        bvh.wide = wide;
        bvh.stats.bytes = bytes;
        (bvh.stats.nodes, bvh.stats.leaves) = counts;
        bvh.depth = match &bvh.wide {
            Wide::W4(w) => w.depth(),
            Wide::W8(w) => w.depth(),
            Wide::Binary => bvh.depth,
        };
        bvh.stats.depth = bvh.depth;
        bvh.nodes = Vec::new();
        bvh.indices = Vec::new();
        bvh
    }

    /// Children per node: 2, 4 or 8.
    pub fn width(&self) -> usize {
        match self.wide {
            Wide::Binary => 2,
            Wide::W4(_) => 4,
            Wide::W8(_) => 8,
        }
    }

    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Walks the tree once for depth, node counts and SAH cost (the expected cost of a random ray
    /// hitting the root, MacDonald & Booth 1990).
    fn measure(&mut self, o: &BvhOptions) {
        let blocks = build::BlockCount::new(o);
        let mut interior = 0;
        let mut leaves = 0;
        let mut depth = 0;
        let mut cost = 0.0f64;
        if let Some(root) = self.nodes.first() {
            let area = |n: &BvhNode| Aabb::new(n.min.into(), n.max.into()).surface_area() as f64;
            let root_area = area(root);
            let mut stack = vec![(0usize, 0usize)];
            while let Some((at, d)) = stack.pop() {
                let n = &self.nodes[at];
                depth = depth.max(d);
                let rel = if root_area > 0.0 {
                    area(n) / root_area
                } else {
                    1.0
                };
                if n.is_leaf() {
                    leaves += 1;
                    cost += rel * o.intersect_cost as f64 * blocks.of(n.count as u32) as f64;
                } else {
                    interior += 1;
                    cost += rel * o.traversal_cost as f64;
                    stack.push((at + 1, d + 1));
                    stack.push((n.offset as usize, d + 1));
                }
            }
        }
        self.depth = depth;
        self.stats = AccelStats {
            name: Self::NAME,
            primitives: self.indices.len(),
            build_time: Default::default(),
            bytes: self.nodes.len() * std::mem::size_of::<BvhNode>()
                + self.indices.len() * std::mem::size_of::<u32>(),
            nodes: interior,
            leaves,
            depth,
            sah_cost: (!self.nodes.is_empty()).then_some(cost),
        };
    }

    #[inline]
    pub fn intersect<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        match &self.wide {
            Wide::Binary => self.traverse::<P, false>(prims, ray, t_max, stats),
            Wide::W4(w) => w.traverse::<P, false>(prims, ray, t_max, stats),
            Wide::W8(w) => w.traverse::<P, false>(prims, ray, t_max, stats),
        }
    }

    /// See [`Structure::single_leaf`]: a wide tree that is one leaf without triangles.
    #[inline(always)]
    pub fn single_leaf(&self) -> Option<usize> {
        match &self.wide {
            Wide::Binary => None,
            Wide::W4(w) => w.single_leaf(),
            Wide::W8(w) => w.single_leaf(),
        }
    }

    /// Whether [`Self::intersect_packet`] traces packets together: the 8-wide layout of more than
    /// one leaf, on a CPU with AVX2.
    pub fn has_packets(&self) -> bool {
        matches!(&self.wide, Wide::W8(w) if w.has_packets())
    }

    /// Closest hits of up to [`PACKET`] rays (`out[i]` for `rays[i]`), the answers of
    /// [`Self::intersect`] on each: the 8-wide tree traverses coherent packets together (see
    /// `wide/packet.rs`), other layouts go ray by ray.
    pub fn intersect_packet<P: Primitives>(
        &self,
        prims: &P,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<Hit>],
        stats: &mut TraversalStats,
    ) {
        match &self.wide {
            Wide::W8(w) => w.intersect_packet(prims, rays, t_max, out, stats),
            _ => {
                for (ray, o) in rays.iter().zip(out.iter_mut()) {
                    *o = self.intersect(prims, ray, t_max, stats);
                }
            }
        }
    }

    #[inline]
    pub fn occluded<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> bool {
        match &self.wide {
            Wide::Binary => self.traverse::<P, true>(prims, ray, t_max, stats),
            Wide::W4(w) => w.traverse::<P, true>(prims, ray, t_max, stats),
            Wide::W8(w) => w.traverse::<P, true>(prims, ray, t_max, stats),
        }
        .is_some()
    }

    pub fn stats(&self) -> AccelStats {
        self.stats.clone()
    }
}

impl Structure for Bvh {
    const NAME: &'static str = "bvh";
    type Options = BvhOptions;

    fn check_options(o: &BvhOptions) -> Result<(), BadOption> {
        if ![2, 4, 8].contains(&o.width) {
            return Err(BadOption::new(
                "width",
                format!("`width` must be 2, 4 or 8, got {}", o.width),
            ));
        }
        BadOption::check_range("bins", o.bins, 2, 32)?;
        BadOption::check_range("max_leaf", o.max_leaf, 1, 255)?;
        BadOption::check_range("leaf_size", o.leaf_size, 1, 255)?;
        BadOption::check_positive("traversal_cost", o.traversal_cost)?;
        BadOption::check_positive("intersect_cost", o.intersect_cost)
    }

    fn build<P: Primitives>(prims: &P, options: &BvhOptions) -> Self {
        // A file's `max_leaf` bounds the leaves of every split, midpoint and median too.
        let options = BvhOptions {
            leaf_size: options.leaf_size.min(options.max_leaf),
            ..*options
        };
        Bvh::build_with(prims, options)
    }

    crate::accel::structure::forward_queries!(Bvh);

    fn has_packets(&self) -> bool {
        Bvh::has_packets(self)
    }

    #[inline(always)]
    fn single_leaf(&self) -> Option<usize> {
        Bvh::single_leaf(self)
    }

    fn intersect_packet<P: Primitives>(
        &self,
        prims: &P,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<Hit>],
        stats: &mut TraversalStats,
    ) {
        Bvh::intersect_packet(self, prims, rays, t_max, out, stats)
    }

    fn refit<P: Primitives>(&mut self, prims: &P) -> Option<f64> {
        Some(Bvh::refit(self, prims))
    }

    fn current_sah_cost(&self) -> Option<f64> {
        Some(Bvh::current_sah_cost(self))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::testutil::{agrees_with_brute, mesh, prims, rays, soup};

    /// Builds the binary tree (whose nodes the structural tests inspect) and checks it, and its 4-
    /// and 8-wide collapses, against brute force.
    fn check(m: &crate::geometry::TriangleMesh, opts: BvhOptions) -> (Bvh, usize) {
        let p = prims(m);
        for width in [4, 8] {
            let wide = Bvh::build_with(&p, BvhOptions { width, ..opts });
            assert_eq!(wide.width(), width);
            agrees_with_brute(
                &p,
                &rays(400, 7),
                |r, t, s| wide.intersect(&p, r, t, s),
                |r, t, s| wide.occluded(&p, r, t, s),
            );
        }
        let bvh = Bvh::build_with(&p, BvhOptions { width: 2, ..opts });
        let hits = agrees_with_brute(
            &p,
            &rays(400, 7),
            |r, t, s| bvh.intersect(&p, r, t, s),
            |r, t, s| bvh.occluded(&p, r, t, s),
        );
        (bvh, hits)
    }

    /// Structural invariants: every primitive in exactly one leaf, children inside their parent.
    fn well_formed(bvh: &Bvh, n: usize) {
        let mut seen = vec![0u32; n];
        for node in &bvh.nodes {
            if node.is_leaf() {
                for &p in &bvh.indices[node.offset as usize..][..node.count as usize] {
                    seen[p as usize] += 1;
                }
            } else {
                let parent = Aabb::new(node.min.into(), node.max.into());
                let at = bvh
                    .nodes
                    .iter()
                    .position(|m| std::ptr::eq(m, node))
                    .unwrap();
                for c in [at + 1, node.offset as usize] {
                    let child = &bvh.nodes[c];
                    assert!(parent.contains(child.min.into()) && parent.contains(child.max.into()));
                }
            }
        }
        assert!(seen.iter().all(|&k| k == 1));
    }

    #[test]
    fn every_split_agrees_with_brute_force() {
        let m = soup(3000, 11);
        for split in [BvhSplit::Sah, BvhSplit::Midpoint, BvhSplit::Median] {
            let (bvh, hits) = check(
                &m,
                BvhOptions {
                    split,
                    ..Default::default()
                },
            );
            assert!(hits > 200, "{hits}");
            well_formed(&bvh, 3000);
            assert!(bvh.depth() < 40, "{split:?}: depth {}", bvh.depth());
        }
    }

    #[test]
    fn parallel_build_gives_a_valid_tree() {
        let m = soup(5000, 3);
        let (bvh, _) = check(
            &m,
            BvhOptions {
                parallel_threshold: 100,
                ..Default::default()
            },
        );
        well_formed(&bvh, 5000);
        let seq = Bvh::build_with(
            &prims(&m),
            BvhOptions {
                width: 2,
                parallel_threshold: usize::MAX,
                ..Default::default()
            },
        );
        // Same decisions in the same order: the same tree.
        assert_eq!(seq.nodes, bvh.nodes);
    }

    #[test]
    fn empty_single_and_coincident_inputs() {
        let (empty, _) = check(&mesh(vec![]), BvhOptions::default());
        assert!(empty.nodes.is_empty());
        assert_eq!(empty.stats().sah_cost, None);
        let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let (one, hits) = check(&mesh(vec![t]), BvhOptions::default());
        assert_eq!(one.nodes.len(), 1);
        assert!(hits > 0);
        for split in [BvhSplit::Sah, BvhSplit::Midpoint, BvhSplit::Median] {
            let (same, _) = check(
                &mesh(vec![t; 1000]),
                BvhOptions {
                    split,
                    ..Default::default()
                },
            );
            well_formed(&same, 1000);
            // Halving: about log2(1000 / leaf) levels.
            assert!(same.depth() <= 10, "{}", same.depth());
        }
    }

    #[test]
    fn sah_beats_median_on_clustered_input_and_leaves_stay_small() {
        // Two dense clusters far apart plus sparse filler: SAH's expected cost must not exceed the
        // median split's.
        let mut m = soup(2000, 5);
        for p in m.positions.iter_mut().take(3000) {
            *p = *p * 0.01 + Vec3::splat(5.0);
        }
        let binary = BvhOptions {
            width: 2,
            ..Default::default()
        };
        let sah = Bvh::build_with(&prims(&m), binary);
        let med = Bvh::build_with(
            &prims(&m),
            BvhOptions {
                split: BvhSplit::Median,
                width: 2,
                ..Default::default()
            },
        );
        let (a, b) = (sah.stats().sah_cost.unwrap(), med.stats().sah_cost.unwrap());
        assert!(a <= b, "sah {a} median {b}");
        assert!(sah.nodes.iter().all(|n| n.count <= 8));
    }

    #[test]
    fn stats_count_nodes_and_bytes() {
        let m = soup(500, 9);
        let bvh = Bvh::build_with(
            &prims(&m),
            BvhOptions {
                width: 2,
                ..Default::default()
            },
        );
        let s = bvh.stats();
        assert_eq!(s.nodes + s.leaves, bvh.nodes.len());
        assert_eq!(s.leaves, s.nodes + 1);
        assert_eq!(s.bytes, bvh.nodes.len() * 32 + 500 * 4);
        let mut ts = TraversalStats::default();
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        bvh.intersect(&prims(&m), &r, f32::INFINITY, &mut ts);
        assert_eq!(ts.rays, 1);
        assert!(ts.nodes_visited >= 1 && ts.prim_tests < 500);
    }
}
