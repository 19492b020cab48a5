//! The octree's top-down build: a cell lists the primitives that overlap it, and splits into its
//! eight octants while it lists more than `max_prims`, until `max_depth`.

use super::{child_box, OctNode, INTERIOR};
use crate::accel::Primitives;
use crate::math::{Aabb, Vec3};

pub(super) struct Builder<'a, P> {
    pub(super) prims: &'a P,
    pub(super) bounds: &'a [Aabb],
    pub(super) max_prims: usize,
    pub(super) max_depth: usize,
    /// Primitives within this distance of a cell are listed in it too (`MARGIN_ULPS`).
    pub(super) margin: f32,
    pub(super) nodes: Vec<OctNode>,
    pub(super) items: Vec<u32>,
    pub(super) depth: usize,
    pub(super) leaves: usize,
}

impl<P: Primitives> Builder<'_, P> {
    fn leaf(&mut self, at: usize, ids: &[u32], depth: usize) {
        self.nodes[at] = OctNode {
            first: u32::try_from(self.items.len()).expect("octree of more than 2^32 references"),
            count: ids.len() as u32,
        };
        self.items.extend_from_slice(ids);
        self.leaves += 1;
        self.depth = self.depth.max(depth);
    }

    /// Fills node `at`, the cell `cell` listing `ids`, and its subtree.
    pub(super) fn build(&mut self, at: usize, cell: Aabb, ids: Vec<u32>, depth: usize) {
        if ids.len() <= self.max_prims || depth >= self.max_depth {
            return self.leaf(at, &ids, depth);
        }
        let children = self.distribute(&cell, &ids);
        // A split that copies primitives while two or more octants still list all of them makes
        // no progress: the primitives are stacked over each other and larger than the octants
        // (or all meet at the centre), and every level below would copy them again, into every
        // cell along their surface down to the depth limit (4^depth cells for a stack of
        // coincident triangles). Such a cell stays a leaf. One octant listing them all is
        // progress (a small dense mesh in one octant, with a large triangle copied beside it),
        // and so are copies when every octant lists fewer (walls crossing the cell).
        let copies: usize = children.iter().map(Vec::len).sum();
        let full = children.iter().filter(|c| c.len() == ids.len()).count();
        if copies > ids.len() && full >= 2 {
            return self.leaf(at, &ids, depth);
        }
        drop(ids);
        let first = self.nodes.len();
        assert!(
            first + 8 < INTERIOR as usize,
            "octree of more than 2^32 nodes"
        );
        self.nodes[at] = OctNode {
            first: first as u32,
            count: INTERIOR,
        };
        self.nodes.resize(first + 8, OctNode::default());
        for (k, ids) in children.into_iter().enumerate() {
            self.build(first + k, child_box(&cell, k), ids, depth + 1);
        }
    }

    /// The primitives of each octant of `cell`: those whose bounds reach the octant (grown by the
    /// margin) and, where the bounds reach more than one octant, that the exact overlap test
    /// ([`Primitives::clip_overlaps`]) finds in it. The overlap test's cell is grown a little more
    /// for its own rounding, as the kd-tree's is.
    fn distribute(&self, cell: &Aabb, ids: &[u32]) -> [Vec<u32>; 8] {
        let c = cell.center();
        let m = self.margin;
        let mut out: [Vec<u32>; 8] = Default::default();
        for &i in ids {
            let b = &self.bounds[i as usize];
            // Per axis: whether the bounds reach the lower and the upper half.
            let lo: [bool; 3] = std::array::from_fn(|a| b.min[a] <= c[a] + m);
            let hi: [bool; 3] = std::array::from_fn(|a| b.max[a] >= c[a] - m);
            let one = (0..3).all(|a| lo[a] != hi[a]);
            for (k, list) in out.iter_mut().enumerate() {
                let reaches = (0..3).all(|a| if k >> a & 1 == 1 { hi[a] } else { lo[a] });
                if !reaches {
                    continue;
                }
                if one
                    || self
                        .prims
                        .clip_overlaps(i as usize, &self.grown(child_box(cell, k)))
                {
                    list.push(i);
                }
            }
        }
        out
    }

    fn grown(&self, b: Aabb) -> Aabb {
        let g = b.extent() * 1e-4 + Vec3::splat(self.margin);
        Aabb::new(b.min - g, b.max + g)
    }
}
