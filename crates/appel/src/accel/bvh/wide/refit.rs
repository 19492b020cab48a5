//! Refitting the wide BVH after its primitives moved (same primitives, same ids, new positions):
//! the leaves' vertex copies are read again, then every box is recomputed bottom-up. The tree's
//! shape is kept, so its quality drifts as the motion takes primitives away from the neighbours
//! they were grouped with; [`WideBvh::sah_cost`] measures that drift (Wald, Boulos & Shirley 2007,
//! "Ray tracing deformable scenes using dynamic bounding volume hierarchies", section 4).

use super::mt_block::LaneTest;
use super::node::{self, Child};
use super::quad_block::{ID, PAIR, SWAP};
use super::{QuadBlock, TriBlock, WideBvh};
use crate::accel::bvh::pairs::item_bounds;
use crate::accel::Primitives;
use crate::math::{Aabb, Vec3};
use rayon::prelude::*;

impl<const W: usize> WideBvh<W> {
    /// Recomputes the leaves' vertices and every node's boxes from `prims`, which must be the
    /// primitives the tree was built over (same count, same ids), moved.
    pub(crate) fn refit<P: Primitives>(&mut self, prims: &P) {
        let test = self.test;
        self.blocks
            .par_iter_mut()
            .for_each(|b| refit_block(b, test, prims));
        self.quads.par_iter_mut().for_each(|q| refit_quad(q, prims));
        // Children always come after their parent in `nodes` (the collapse appends them), so one
        // backward pass sees every child's boxes before its parent needs them.
        for at in (0..self.nodes.len()).rev() {
            for lane in 0..W {
                let c = self.nodes[at].child[lane];
                if c == node::EMPTY {
                    continue;
                }
                let b = if node::is_leaf(c) {
                    self.leaf_bounds(c, prims)
                } else {
                    self.node_bounds(c as usize)
                };
                self.nodes[at].set(lane, b.min.to_array(), b.max.to_array(), c);
            }
        }
    }

    /// The union of the boxes of node `at`'s children.
    fn node_bounds(&self, at: usize) -> Aabb {
        let n = &self.nodes[at];
        (0..W)
            .filter(|&l| n.child[l] != node::EMPTY)
            .fold(Aabb::EMPTY, |b, l| {
                b.union(Aabb::new(
                    Vec3::new(n.bounds[0][l], n.bounds[2][l], n.bounds[4][l]),
                    Vec3::new(n.bounds[1][l], n.bounds[3][l], n.bounds[5][l]),
                ))
            })
    }

    /// The union of the bounds of a leaf's primitives (as the builder computed them).
    fn leaf_bounds<P: Primitives>(&self, c: Child, prims: &P) -> Aabb {
        let (first, count) = node::leaf_range(c);
        let lanes = (0..count).map(|k| (first + k / 4, k % 4));
        if c & node::QUADS != 0 {
            lanes.fold(Aabb::EMPTY, |b, (blk, l)| {
                b.union(item_bounds(prims, self.quads[blk].id[l]))
            })
        } else if self.compact() {
            lanes.fold(Aabb::EMPTY, |b, (blk, l)| {
                b.union(prims.bounds(self.ids[blk][l] as usize))
            })
        } else {
            lanes.fold(Aabb::EMPTY, |b, (blk, l)| {
                b.union(prims.bounds(self.blocks[blk].id[l] as usize))
            })
        }
    }

    /// The surface area heuristic cost of the tree as it stands (MacDonald & Booth 1990): each
    /// wide node costs one traversal step and each leaf one test per block of four, weighted by
    /// the probability `area(box) / area(root)` that a ray through the root reaches it. Only
    /// ratios of it mean anything: a refitted tree's cost over its cost when built is the drift
    /// the rebuild policy watches.
    pub fn sah_cost(&self) -> f64 {
        let area = |n: &super::WideNode<W>, l: usize| {
            Aabb::new(
                Vec3::new(n.bounds[0][l], n.bounds[2][l], n.bounds[4][l]),
                Vec3::new(n.bounds[1][l], n.bounds[3][l], n.bounds[5][l]),
            )
            .surface_area() as f64
        };
        if self.nodes.is_empty() {
            return 0.0;
        }
        let root_area = self.node_bounds(0).surface_area() as f64;
        if root_area <= 0.0 {
            return 0.0;
        }
        let mut cost = 1.0; // the root itself
        for n in &self.nodes {
            for l in 0..W {
                let c = n.child[l];
                if c == node::EMPTY {
                    continue;
                }
                let p = area(n, l) / root_area;
                cost += if node::is_leaf(c) {
                    p * node::leaf_range(c).1.div_ceil(4) as f64
                } else {
                    p
                };
            }
        }
        cost
    }
}

/// Reads the triangles of a block's lanes again; called-back lanes (NaN) stay so.
fn refit_block<P: Primitives>(b: &mut TriBlock, test: LaneTest, prims: &P) {
    for lane in 0..4 {
        if b.v[0][lane].is_nan() {
            continue;
        }
        let tri = test.lane(prims, b.id[lane] as usize);
        for k in 0..3 {
            for a in 0..3 {
                b.v[3 * k + a][lane] = tri.map_or(f32::NAN, |t| t[k][a]);
            }
        }
    }
}

/// Reads the quads of a block's lanes again, as the builder's scatter formed them.
fn refit_quad<P: Primitives>(q: &mut QuadBlock, prims: &P) {
    for lane in 0..4 {
        if q.v[0][lane].is_nan() {
            continue;
        }
        let code = q.id[lane];
        let id = (code & ID) as usize;
        let first = prims.watertight_triangle(id);
        let second = (code & PAIR != 0)
            .then(|| prims.watertight_triangle(id + 1))
            .flatten();
        let quad = first.map(|t| match second {
            None => [t[0], t[1], t[2], t[2]],
            Some(s) if code & SWAP != 0 => [t[0], s[1], t[1], t[2]],
            Some(s) => [t[0], t[1], t[2], s[2]],
        });
        // SAFETY: `lane < 4` and `q` is borrowed mutably.
        unsafe { QuadBlock::write_lane_raw(q, lane, code, quad) };
    }
}
