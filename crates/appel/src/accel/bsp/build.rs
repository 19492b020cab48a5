//! The BSP tree's top-down build: at each node the cheapest candidate plane (`candidates.rs`) by
//! the surface area heuristic over convex cells, if it is cheaper than a leaf; the primitives go
//! to the sides their vertices reach (both, when they straddle the plane or lie within the
//! margin of it); and the cell is clipped into the children's polytopes.

use super::candidates::{is_axis, Chooser};
use super::polytope::Polytope;
use super::shape::Shape;
use super::{BspNode, BspOptions, INTERIOR};
use crate::accel::Primitives;
use crate::math::{Aabb, Vec3};

pub(super) struct Builder<'a, P> {
    pub(super) prims: &'a P,
    pub(super) shapes: &'a [Shape],
    pub(super) opts: BspOptions,
    pub(super) max_depth: usize,
    /// Primitives within this distance of a plane go to both sides (`MARGIN_ULPS`).
    pub(super) margin: f64,
    pub(super) nodes: Vec<BspNode>,
    pub(super) items: Vec<u32>,
    pub(super) depth: usize,
    pub(super) leaves: usize,
    pub(super) oblique: usize,
    pub(super) root_area: f64,
    /// The tree's SAH cost: each node's cost weighted by its cell's area relative to the root's.
    pub(super) sah: f64,
}

impl<P: Primitives> Builder<'_, P> {
    pub(super) fn build_root(&mut self, root: Aabb, ids: Vec<u32>) {
        let cell = Polytope::from_box(root.min.as_dvec3(), root.max.as_dvec3());
        self.root_area = cell.area();
        self.build(cell, ids, 0);
    }

    fn leaf(&mut self, area: f64, ids: &[u32], depth: usize) {
        self.nodes.push(BspNode {
            plane: [0.0; 4],
            first: u32::try_from(self.items.len()).expect("BSP tree of more than 2^32 references"),
            count: ids.len() as u32,
        });
        self.items.extend_from_slice(ids);
        self.leaves += 1;
        self.depth = self.depth.max(depth);
        if !ids.is_empty() {
            let o = self.opts;
            self.sah += area / self.root_area
                * (o.visit_cost as f64 + o.intersect_cost as f64 * ids.len() as f64);
        }
    }

    fn grown(&self, cell: &Polytope) -> Aabb {
        let b = cell.bounds();
        let g = b.extent() * 1e-4 + Vec3::splat(self.margin as f32);
        Aabb::new(b.min - g, b.max + g)
    }

    fn build(&mut self, cell: Polytope, ids: Vec<u32>, depth: usize) {
        let area = cell.area();
        let n = ids.len();
        if n <= self.opts.max_prims || depth >= self.max_depth {
            return self.leaf(area, &ids, depth);
        }
        let chooser = Chooser {
            shapes: self.shapes,
            opts: self.opts,
            margin: self.margin,
        };
        let leaf_cost = self.opts.visit_cost as f64 + self.opts.intersect_cost as f64 * n as f64;
        let Some(p) = chooser.best(&cell, &ids).filter(|p| p.cost < leaf_cost) else {
            return self.leaf(area, &ids, depth);
        };
        let (n64, d64) = (p.n.as_dvec3(), p.d as f64);
        let below_cell = cell.clip(n64, d64);
        let above_cell = cell.clip(-n64, -d64);
        drop(cell);
        // A primitive whose vertices straddle the plane may still miss one child's cell (a large
        // triangle beside a small cell: the plane cuts it far away). A triangle goes only to the
        // cells it comes within the margin of (clipped by the cell's planes); another primitive
        // only to the cells whose bounding boxes it overlaps ([`Primitives::clip_overlaps`],
        // each box grown by the margin and a little more for that test's own rounding, as the
        // kd-tree's are). Either way nothing the cell holds is lost.
        let (gb, ga) = (self.grown(&below_cell), self.grown(&above_cell));
        let (mut below, mut above) = (Vec::with_capacity(n), Vec::with_capacity(n / 2));
        for &i in &ids {
            let (mut b, mut a) = self.shapes[i as usize].sides(p.n, p.d, self.margin);
            if b && a {
                let (cb, ca) = match self.shapes[i as usize] {
                    Shape::Triangle(t) => {
                        let t = t.map(|v| v.as_dvec3());
                        (
                            below_cell.meets_triangle(t, self.margin),
                            above_cell.meets_triangle(t, self.margin),
                        )
                    }
                    Shape::Box(_) => (
                        self.prims.clip_overlaps(i as usize, &gb),
                        self.prims.clip_overlaps(i as usize, &ga),
                    ),
                };
                // Neither (only possible by rounding in an earlier test): keep both.
                if cb || ca {
                    (b, a) = (cb, ca);
                }
            }
            if b {
                below.push(i);
            }
            if a {
                above.push(i);
            }
        }
        // The binned counts the cost was taken from are estimates; a plane that in fact leaves
        // every primitive on both sides would recurse without end.
        if below.len() == n && above.len() == n {
            return self.leaf(area, &ids, depth);
        }
        drop(ids);
        let me = self.nodes.len();
        self.nodes.push(BspNode {
            plane: [p.n.x, p.n.y, p.n.z, p.d],
            first: 0,
            count: INTERIOR,
        });
        self.oblique += !is_axis(p.n) as usize;
        self.sah += area / self.root_area * self.opts.traversal_cost as f64;
        self.build(below_cell, below, depth + 1);
        self.nodes[me].first =
            u32::try_from(self.nodes.len()).expect("BSP tree of more than 2^32 nodes");
        self.build(above_cell, above, depth + 1);
    }
}
