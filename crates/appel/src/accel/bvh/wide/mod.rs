//! The wide BVH: the binary SAH tree collapsed into nodes of `W` (4 or 8) children tested with one
//! SIMD instruction per slab, and leaves of triangles gathered into blocks of four (see
//! `tri_block.rs`). The collapse follows Embree's BVH4/BVH8 builders (Wald et al. 2014): a node
//! adopts its children, then repeatedly opens the child with the largest surface area, until it has
//! `W` children or only leaves remain.

// `tri_block` first: its triangle filter (a macro) serves `quad_block` too.
#[macro_use]
mod tri_block;
mod leaf;
mod mt_block;
mod node;
mod packet;
mod quad_block;
mod refit;
#[cfg(target_arch = "x86_64")]
mod simd;
mod traverse;

pub use node::WideNode;
pub use packet::PACKET;
pub use quad_block::{QuadBlock, ID, PAIR, SWAP};
pub use tri_block::TriBlock;

use super::node::BvhNode;
use crate::accel::Primitives;
use crate::math::{Aabb, Vec3};
use mt_block::LaneTest;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};

#[derive(Clone, Debug, Default)]
pub struct WideBvh<const W: usize> {
    nodes: Vec<WideNode<W>>,
    /// The leaves' triangles; empty for compact leaves.
    blocks: Vec<TriBlock>,
    /// What the triangle blocks hold: three vertices, or a vertex and two edges for
    /// Moller-Trumbore triangles (`mt_block.rs`).
    test: LaneTest,
    /// The leaves' pairs of triangles (leaves tagged [`node::QUADS`]), when the tree was built
    /// over pairs ([`Self::from_collapsed_paired`]).
    quads: Vec<QuadBlock>,
    /// Compact leaves (`BvhOptions::compact`): each block's four primitive ids, padded as the
    /// blocks are, the vertices fetched through `Primitives` at every visit; empty otherwise.
    ids: Vec<[u32; 4]>,
    /// Edges from the root to the deepest leaf.
    depth: usize,
    /// The tree is one leaf (a scene of a few primitives): traversal tests it without a box test.
    root_leaf: Option<node::Child>,
    /// Traversal's common case: a 128-entry stack suffices and the leaves hold triangle blocks
    /// (decided once here rather than at every ray).
    common: bool,
    /// Whether traversal prefetches the children it pushes ([`crate::accel::PREFETCH_BYTES`]).
    prefetch: bool,
    /// The traversal rays take.
    path: traverse::Path,
}

/// A leaf's primitives before their vertices are gathered: a range of the binary tree's index array.
struct LeafRange {
    /// The wide node and lane whose slot points at this leaf.
    slot: (u32, u8),
    first_index: u32,
    count: u32,
    first_block: u32,
}

/// Fills the leaves' blocks (`leaves` in block order, each owning `ceil(count / 4)` consecutive
/// blocks) leaf by leaf; returns, per leaf, whether none of its primitives is a gathered triangle.
/// Reading the primitives in leaf order jumps around the scene's arrays (several dependent cache
/// misses per triangle: its reference, its indices, its vertices), so this is the fallback for
/// trees with more than 2^32 lanes; [`scatter`] is the usual way.
fn gather<P: Primitives>(
    prims: &P,
    test: LaneTest,
    leaves: &[LeafRange],
    indices: &[u32],
    blocks: &mut [TriBlock],
) -> Vec<bool> {
    // Each leaf owns a disjoint run of blocks: in parallel over leaves.
    runs(leaves, blocks)
        .into_par_iter()
        .map(|(l, run)| {
            let ids = &indices[l.first_index as usize..][..l.count as usize];
            let mut any_triangle = false;
            for (chunk, block) in ids.chunks(4).zip(run.iter_mut()) {
                *block = TriBlock::gather(prims, test, chunk);
                any_triangle |= block.has_triangle();
            }
            !any_triangle
        })
        .collect()
}

/// [`gather`]'s result, built the other way round: the primitives are read in their own order,
/// which is sequential in the scene's arrays, and each is written to its lane, wherever that is
/// (stores do not wait for memory the way dependent loads do). Then each leaf's last block has its
/// unused lanes filled with its lane 0. For scattered triangles the gather's dependent cache
/// misses were a large part of the build; this order removes them.
fn scatter<P: Primitives>(
    prims: &P,
    test: LaneTest,
    leaves: &[LeafRange],
    indices: &[u32],
    blocks: &mut [TriBlock],
) -> Vec<bool> {
    assert!(4 * blocks.len() <= u32::MAX as usize);
    // Every primitive's lane, `4 * block + lane`.
    let mut lane_of = vec![0u32; indices.len()];
    {
        let out = SharedU32(lane_of.as_mut_ptr());
        leaves.par_iter().for_each(|l| {
            let ids = &indices[l.first_index as usize..][..l.count as usize];
            for (k, &id) in ids.iter().enumerate() {
                // SAFETY: every id appears once in `indices`, so each element is written once.
                unsafe { out.write(id as usize, 4 * l.first_block + k as u32) };
            }
        });
    }
    let lanes = Lanes(blocks.as_mut_ptr());
    let called_back = AtomicBool::new(false);
    lane_of
        .par_iter()
        .enumerate()
        .with_min_len(4096)
        .for_each(|(id, &lane)| {
            let tri = test.lane(prims, id);
            if tri.is_none() {
                called_back.store(true, Relaxed);
            }
            // SAFETY: `lane_of` is a permutation of the leaves' lanes, all inside `blocks`.
            unsafe { lanes.write(lane as usize, id as u32, tri) };
        });
    drop(lane_of);
    let called_back = called_back.into_inner();
    // Pad each leaf's last block, and flag the leaves without triangles.
    runs(leaves, blocks)
        .into_par_iter()
        .map(|(l, run)| pad_and_flag(run, l.count as usize, called_back))
        .collect()
}

/// Pads a leaf's last block (`lanes` in use in the leaf) with its lane 0; returns whether the leaf
/// holds no triangle (only asked when some primitive is called back at all).
fn pad_and_flag(run: &mut [TriBlock], lanes: usize, called_back: bool) -> bool {
    let used = lanes - 4 * (run.len() - 1);
    run.last_mut().expect("a leaf has a block").pad_from(used);
    called_back && !run.iter().any(|b| b.has_triangle())
}

/// Lanes of triangle blocks, written by many threads, each lane by exactly one.
#[derive(Clone, Copy)]
struct Lanes(*mut TriBlock);
// SAFETY: the threads write disjoint lanes, through raw pointers (no references overlap).
unsafe impl Send for Lanes {}
unsafe impl Sync for Lanes {}

impl Lanes {
    /// SAFETY: `lane / 4` is in bounds, and no other thread touches this lane meanwhile.
    #[inline(always)]
    unsafe fn write(self, lane: usize, id: u32, tri: Option<[Vec3; 3]>) {
        let b = self.0.add(lane / 4);
        let l = lane % 4;
        std::ptr::addr_of_mut!((*b).id)
            .cast::<u32>()
            .add(l)
            .write(id);
        let v = std::ptr::addr_of_mut!((*b).v).cast::<f32>();
        for k in 0..3 {
            for a in 0..3 {
                let x = tri.map_or(f32::NAN, |t| t[k][a]);
                v.add(4 * (3 * k + a) + l).write(x);
            }
        }
    }
}

/// Lanes of pair blocks, as [`Lanes`].
#[derive(Clone, Copy)]
struct QuadLanes(*mut QuadBlock);
// SAFETY: as for `Lanes`.
unsafe impl Send for QuadLanes {}
unsafe impl Sync for QuadLanes {}

impl QuadLanes {
    /// SAFETY: as for [`Lanes::write`].
    #[inline(always)]
    unsafe fn write(self, lane: usize, code: u32, quad: Option<[Vec3; 4]>) {
        QuadBlock::write_lane_raw(self.0.add(lane / 4), lane % 4, code, quad);
    }
}

/// Fills the leaves of a tree built over pair items (`items`, see `accel/bvh/pairs.rs`; each leaf
/// of `leaves` a range of `indices`, which name items): each leaf becomes blocks of pairs where
/// that takes fewer bytes than triangle blocks (a pair's two triangles then take two lanes), and
/// its slot in `nodes` is rewritten to say which. As [`scatter`], the items are read in their own
/// order and written to their lanes. Returns the two block arrays.
fn scatter_paired<P: Primitives, const W: usize>(
    prims: &P,
    leaves: &[LeafRange],
    indices: &[u32],
    items: &[u32],
    nodes: &mut [WideNode<W>],
) -> (Vec<TriBlock>, Vec<QuadBlock>) {
    let is_pair = |k: u32| items[k as usize] & PAIR != 0;
    // Each leaf's kind and lanes: `(pairs?, lanes)`.
    let kinds: Vec<(bool, usize)> = leaves
        .par_iter()
        .map(|l| {
            let ids = &indices[l.first_index as usize..][..l.count as usize];
            let n = ids.len();
            let triangles = n + ids.iter().filter(|&&k| is_pair(k)).count();
            let quad_bytes = std::mem::size_of::<QuadBlock>() * n.div_ceil(4);
            let tri_bytes = std::mem::size_of::<TriBlock>() * triangles.div_ceil(4);
            if quad_bytes < tri_bytes {
                (true, n)
            } else {
                (false, triangles)
            }
        })
        .collect();
    let (mut tri_blocks, mut quad_blocks) = (0usize, 0usize);
    let firsts: Vec<u32> = leaves
        .iter()
        .zip(&kinds)
        .map(|(l, &(quad, lanes))| {
            let next = if quad {
                &mut quad_blocks
            } else {
                &mut tri_blocks
            };
            let first = *next as u32;
            *next += lanes.div_ceil(4);
            let tag = if quad { node::QUADS } else { 0 };
            nodes[l.slot.0 as usize].child[l.slot.1 as usize] =
                node::leaf(first, lanes as u32) | tag;
            first
        })
        .collect();
    // Lanes are numbered below 2^31, the top bit telling pair blocks from triangle blocks.
    assert!(4 * tri_blocks.max(quad_blocks) < PAIR as usize);
    // Every item's lane (its first triangle's, in a triangle block).
    let mut lane_of = vec![0u32; items.len()];
    {
        let out = SharedU32(lane_of.as_mut_ptr());
        leaves
            .par_iter()
            .zip(&kinds)
            .zip(&firsts)
            .for_each(|((l, &(quad, _)), &first)| {
                let ids = &indices[l.first_index as usize..][..l.count as usize];
                let mut lane = 4 * first;
                for &k in ids {
                    // SAFETY: every item appears once in `indices`, so each element is written once.
                    unsafe { out.write(k as usize, lane | if quad { PAIR } else { 0 }) };
                    lane += if quad || !is_pair(k) { 1 } else { 2 };
                }
            });
    }
    let mut blocks: Vec<TriBlock> = bytemuck::zeroed_vec(tri_blocks);
    let mut quads: Vec<QuadBlock> = bytemuck::zeroed_vec(quad_blocks);
    let (tri_lanes, quad_lanes) = (Lanes(blocks.as_mut_ptr()), QuadLanes(quads.as_mut_ptr()));
    let called_back = AtomicBool::new(false);
    lane_of
        .par_iter()
        .zip(items)
        .with_min_len(4096)
        .for_each(|(&lane, &code)| {
            let id = code & ID;
            let first = prims.watertight_triangle(id as usize);
            if first.is_none() {
                called_back.store(true, Relaxed);
            }
            let second = (code & PAIR != 0).then(|| {
                prims
                    .watertight_triangle(id as usize + 1)
                    .expect("a pair is two watertight triangles")
            });
            let at = (lane & !PAIR) as usize;
            // SAFETY: `lane_of` maps the items one to one onto the leaves' lanes (a pair in a
            // triangle block onto two), all inside the blocks allocated above.
            unsafe {
                if lane & PAIR != 0 {
                    let quad = first.map(|t| match second {
                        None => [t[0], t[1], t[2], t[2]],
                        Some(s) if code & SWAP != 0 => [t[0], s[1], t[1], t[2]],
                        Some(s) => [t[0], t[1], t[2], s[2]],
                    });
                    quad_lanes.write(at, code, quad);
                } else {
                    tri_lanes.write(at, id, first);
                    if let Some(s) = second {
                        tri_lanes.write(at + 1, id + 1, Some(s));
                    }
                }
            }
        });
    drop(lane_of);
    let called_back = called_back.into_inner();
    // Pad each leaf's last block; flag the triangle leaves without triangles.
    let (mut tri_rest, mut quad_rest) = (&mut blocks[..], &mut quads[..]);
    for ((l, &(quad, lanes)), &first) in leaves.iter().zip(&kinds).zip(&firsts) {
        let n = lanes.div_ceil(4);
        if quad {
            let (run, rest) = std::mem::take(&mut quad_rest).split_at_mut(n);
            run[n - 1].pad_from(lanes - 4 * (n - 1));
            quad_rest = rest;
        } else {
            let (run, rest) = std::mem::take(&mut tri_rest).split_at_mut(n);
            if pad_and_flag(run, lanes, called_back) {
                let slot = &mut nodes[l.slot.0 as usize].child[l.slot.1 as usize];
                debug_assert_eq!(node::leaf_range(*slot).0, first as usize);
                *slot |= node::NO_TRIANGLES;
            }
            tri_rest = rest;
        }
    }
    (blocks, quads)
}

/// Compact leaves: each leaf's ids in blocks of four, the last one padded with its lane 0, as
/// [`gather`] pads the triangle blocks; returns the same flags.
fn compact_ids<P: Primitives>(
    prims: &P,
    leaves: &[LeafRange],
    indices: &[u32],
    ids: &mut [[u32; 4]],
) -> Vec<bool> {
    // Flags need a look at each primitive in leaf order (scattered reads); skip it when no
    // primitive is called back, found by reading them in their own order.
    let called_back = (0..indices.len())
        .into_par_iter()
        .any(|i| prims.watertight_triangle(i).is_none());
    runs(leaves, ids)
        .into_par_iter()
        .map(|(l, run)| {
            let leaf = &indices[l.first_index as usize..][..l.count as usize];
            for (chunk, block) in leaf.chunks(4).zip(run.iter_mut()) {
                *block = [0, 1, 2, 3].map(|k| chunk[if k < chunk.len() { k } else { 0 }]);
            }
            called_back
                && leaf
                    .iter()
                    .all(|&id| prims.watertight_triangle(id as usize).is_none())
        })
        .collect()
}

/// Each leaf with its run of blocks, for working on leaves in parallel.
fn runs<'a, T>(leaves: &'a [LeafRange], blocks: &'a mut [T]) -> Vec<(&'a LeafRange, &'a mut [T])> {
    let mut runs = Vec::with_capacity(leaves.len());
    let mut rest = blocks;
    for l in leaves {
        let (run, tail) = rest.split_at_mut(l.count.div_ceil(4) as usize);
        runs.push((l, run));
        rest = tail;
    }
    runs
}

#[derive(Clone, Copy)]
struct SharedU32(*mut u32);
// SAFETY: used only to write distinct elements from different threads.
unsafe impl Send for SharedU32 {}
unsafe impl Sync for SharedU32 {}

impl SharedU32 {
    /// SAFETY: `i` is in bounds, and no other thread touches element `i` meanwhile.
    #[inline(always)]
    unsafe fn write(self, i: usize, x: u32) {
        self.0.add(i).write(x);
    }
}

impl<const W: usize> WideBvh<W> {
    /// Collapses a binary tree (`nodes` in depth-first order, leaves naming ranges of `indices`).
    pub fn from_binary<P: Primitives>(prims: &P, nodes: &[BvhNode], indices: &[u32]) -> Self {
        Self::from_binary_with(prims, nodes, indices, false)
    }

    /// [`Self::from_binary`], with compact leaves (primitive ids only) if `compact`.
    pub fn from_binary_with<P: Primitives>(
        prims: &P,
        nodes: &[BvhNode],
        indices: &[u32],
        compact: bool,
    ) -> Self {
        Self::from_collapsed(prims, Self::collapse(nodes), indices, compact)
    }

    /// The wide nodes over binary tree `nodes`, and the leaves to fill: the first half of
    /// [`Self::from_binary_with`], after which a builder may free the binary tree before the
    /// leaves' blocks are allocated (the binary nodes are large, and the build's peak comes while
    /// the blocks are filled).
    pub(crate) fn collapse(nodes: &[BvhNode]) -> Collapsed<W> {
        assert!(
            W == 4 || W == 8,
            "wide BVH nodes have 4 or 8 children, not {W}"
        );
        Collapse::<W>::run(nodes)
    }

    /// The second half of [`Self::from_binary_with`].
    pub(crate) fn from_collapsed<P: Primitives>(
        prims: &P,
        mut c: Collapsed<W>,
        indices: &[u32],
        compact: bool,
    ) -> Self {
        let mut blocks: Vec<TriBlock> = Vec::new();
        let mut ids: Vec<[u32; 4]> = Vec::new();
        // Compact leaves fetch watertight triangles only.
        let test = if compact {
            LaneTest::Watertight
        } else {
            LaneTest::of(prims)
        };
        let no_triangles = if compact {
            ids = vec![[0; 4]; c.blocks];
            compact_ids(prims, &c.leaves, indices, &mut ids)
        } else if 4 * c.blocks <= u32::MAX as usize {
            blocks = bytemuck::zeroed_vec(c.blocks);
            scatter(prims, test, &c.leaves, indices, &mut blocks)
        } else {
            blocks = bytemuck::zeroed_vec(c.blocks);
            gather(prims, test, &c.leaves, indices, &mut blocks)
        };
        for (l, _) in c.leaves.iter().zip(no_triangles).filter(|(_, none)| *none) {
            c.nodes[l.slot.0 as usize].child[l.slot.1 as usize] |= node::NO_TRIANGLES;
        }
        Self::assemble(c, blocks, test, Vec::new(), ids)
    }

    /// Fills the leaves of a collapsed binary tree built over pair items (`indices` name entries
    /// of `items`, each a primitive id with [`PAIR`] set where it holds the next primitive too:
    /// see `accel/bvh/pairs.rs`). Leaves mostly of pairs hold [`QuadBlock`]s, the others triangle
    /// blocks.
    pub(crate) fn from_collapsed_paired<P: Primitives>(
        prims: &P,
        mut c: Collapsed<W>,
        indices: &[u32],
        items: &[u32],
    ) -> Self {
        let (blocks, quads) = scatter_paired(prims, &c.leaves, indices, items, &mut c.nodes);
        Self::assemble(c, blocks, LaneTest::Watertight, quads, Vec::new())
    }

    fn assemble(
        c: Collapsed<W>,
        blocks: Vec<TriBlock>,
        test: LaneTest,
        quads: Vec<QuadBlock>,
        ids: Vec<[u32; 4]>,
    ) -> Self {
        let root = c.nodes.first();
        let root_leaf = root
            .filter(|r| c.nodes.len() == 1 && r.child[1..].iter().all(|&x| x == node::EMPTY))
            .map(|r| r.child[0])
            .filter(|&x| node::is_leaf(x));
        let mut tree = Self {
            common: traverse::stack_need::<W>(c.depth) <= 128 && ids.is_empty(),
            prefetch: false,
            nodes: c.nodes,
            blocks,
            test,
            quads,
            ids,
            depth: c.depth,
            root_leaf,
            path: traverse::Path::Empty,
        };
        tree.prefetch = tree.bytes() > crate::accel::PREFETCH_BYTES;
        tree.path = traverse::Path::of(&tree);
        tree
    }

    pub fn nodes(&self) -> &[WideNode<W>] {
        &self.nodes
    }

    pub fn depth(&self) -> usize {
        self.depth
    }

    pub fn bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<WideNode<W>>()
            + self.blocks.len() * std::mem::size_of::<TriBlock>()
            + self.quads.len() * std::mem::size_of::<QuadBlock>()
            + self.ids.len() * std::mem::size_of::<[u32; 4]>()
    }

    /// Whether the leaves hold primitive ids only (`BvhOptions::compact`).
    pub fn compact(&self) -> bool {
        !self.ids.is_empty()
    }

    /// Interior nodes and leaves.
    pub fn counts(&self) -> (usize, usize) {
        let leaves = self
            .nodes
            .iter()
            .flat_map(|n| n.child.iter())
            .filter(|&&c| c != node::EMPTY && node::is_leaf(c))
            .count();
        (self.nodes.len(), leaves)
    }
}

/// A binary tree collapsed into wide nodes, its leaves still to be filled.
pub(crate) struct Collapsed<const W: usize> {
    nodes: Vec<WideNode<W>>,
    leaves: Vec<LeafRange>,
    /// Triangle blocks the leaves need.
    blocks: usize,
    /// Wide nodes on the longest path from the root.
    depth: usize,
}

impl<'a, const W: usize> Collapse<'a, W> {
    /// The wide nodes over binary tree `nodes`, and the leaves to gather.
    fn run(nodes: &'a [BvhNode]) -> Collapsed<W> {
        let mut c = Collapse {
            bin: nodes,
            nodes: Vec::with_capacity(nodes.len() / (W - 1) + 1),
            leaves: Vec::new(),
            blocks: 0,
            depth: 0,
        };
        if !nodes.is_empty() {
            c.nodes.push(WideNode::EMPTY);
            if nodes[0].is_leaf() {
                c.depth = 1;
                let child = c.leaf(&nodes[0], (0, 0));
                c.nodes[0].set(0, nodes[0].min, nodes[0].max, child);
            } else {
                c.fill(0, 0, 1);
            }
        }
        assert!(
            c.blocks <= u32::MAX as usize,
            "too many leaf blocks for 32-bit block indices"
        );
        Collapsed {
            nodes: c.nodes,
            leaves: c.leaves,
            blocks: c.blocks,
            depth: c.depth,
        }
    }
}

struct Collapse<'a, const W: usize> {
    bin: &'a [BvhNode],
    nodes: Vec<WideNode<W>>,
    leaves: Vec<LeafRange>,
    blocks: usize,
    /// Wide nodes on the longest path from the root.
    depth: usize,
}

impl<const W: usize> Collapse<'_, W> {
    fn leaf(&mut self, n: &BvhNode, slot: (usize, usize)) -> node::Child {
        let first_block = self.blocks as u32;
        self.leaves.push(LeafRange {
            slot: (slot.0 as u32, slot.1 as u8),
            first_index: n.offset,
            count: n.count as u32,
            first_block,
        });
        self.blocks += (n.count as usize).div_ceil(4);
        node::leaf(first_block, n.count as u32)
    }

    /// Fills wide node `me` (at `level`, the root being 1) with the descendants of binary interior
    /// node `at`.
    fn fill(&mut self, me: usize, at: usize, level: usize) {
        self.depth = self.depth.max(level);
        let bin = self.bin;
        let area = |i: usize| Aabb::new(bin[i].min.into(), bin[i].max.into()).surface_area();
        let mut kids = [0usize; W];
        kids[0] = at + 1;
        kids[1] = bin[at].offset as usize;
        let mut len = 2;
        while len < W {
            let open = (0..len)
                .filter(|&k| !bin[kids[k]].is_leaf())
                .max_by(|&a, &b| area(kids[a]).total_cmp(&area(kids[b])));
            let Some(k) = open else { break };
            let b = kids[k];
            kids[k] = b + 1;
            kids[len] = bin[b].offset as usize;
            len += 1;
        }
        for (lane, &k) in kids[..len].iter().enumerate() {
            let n = &bin[k];
            let child = if n.is_leaf() {
                self.leaf(n, (me, lane))
            } else {
                let idx = self.nodes.len();
                self.nodes.push(WideNode::EMPTY);
                self.fill(idx, k, level + 1);
                idx as node::Child
            };
            self.nodes[me].set(lane, n.min, n.max, child);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::bvh::{Bvh, BvhOptions, Wide};
    use crate::accel::testutil::{agrees_with_brute, prims, rays, soup};
    use crate::accel::MeshPrimitives;
    use crate::geometry::PrimHit;
    use crate::math::{Ray, Vec3};

    fn binary(p: &impl Primitives) -> Bvh {
        Bvh::build_with(
            p,
            BvhOptions {
                width: 2,
                ..Default::default()
            },
        )
    }

    /// Every primitive in exactly one leaf, every child box inside its parent's.
    fn well_formed<const W: usize>(w: &WideBvh<W>, n: usize) {
        well_formed_over(w, n, None::<&MeshPrimitives>)
    }

    /// [`well_formed`], and each leaf lane the triangle `prims` has under that id, bit for bit.
    fn well_formed_over<const W: usize, P: Primitives>(
        w: &WideBvh<W>,
        n: usize,
        prims: Option<&P>,
    ) {
        let mut seen = vec![0u32; n];
        let mut stack = vec![(0usize, None::<([f32; 3], [f32; 3])>)];
        let mut visited = 0;
        while let Some((at, parent)) = stack.pop() {
            visited += 1;
            let node = &w.nodes[at];
            for lane in 0..W {
                let c = node.child[lane];
                if c == node::EMPTY {
                    continue;
                }
                let lo = [0, 2, 4].map(|k| node.bounds[k][lane]);
                let hi = [1, 3, 5].map(|k| node.bounds[k][lane]);
                if let Some((plo, phi)) = parent {
                    assert!((0..3).all(|a| plo[a] <= lo[a] && hi[a] <= phi[a]));
                }
                if node::is_leaf(c) {
                    for (id, tri) in leaf_triangles(w, c) {
                        seen[id as usize] += 1;
                        // Each triangle under its own id, its vertices in their own order.
                        if let Some(p) = prims {
                            assert_eq!(tri, p.watertight_triangle(id as usize), "{id}");
                        }
                        // The leaf's box holds its triangles.
                        for p in tri.into_iter().flatten() {
                            assert!((0..3).all(|a| lo[a] <= p[a] && p[a] <= hi[a]), "{id}");
                        }
                    }
                } else {
                    stack.push((c as usize, Some((lo, hi))));
                }
            }
        }
        assert_eq!(visited, w.nodes.len());
        assert!(seen.iter().all(|&k| k == 1));
    }

    /// A leaf's primitives and their triangles (`None` for those called back), pairs expanded.
    fn leaf_triangles<const W: usize>(
        w: &WideBvh<W>,
        leaf: node::Child,
    ) -> Vec<(u32, Option<[Vec3; 3]>)> {
        let (first, count) = node::leaf_range(leaf);
        let blocks = first..first + count.div_ceil(4);
        if leaf & node::QUADS == 0 {
            let lanes = w.blocks[blocks]
                .iter()
                .flat_map(|b| (0..4).map(|l| (b.id[l], b.triangle(l))));
            return lanes.take(count).collect();
        }
        let mut out = vec![];
        for (k, q) in w.quads[blocks].iter().enumerate() {
            for lane in 0..4.min(count - 4 * k) {
                out.push((q.prim(lane), q.triangle(lane)));
                if q.pair_mask() & (1 << lane) != 0 {
                    out.push((q.prim(lane + 4), q.triangle(lane + 4)));
                }
            }
        }
        out
    }

    /// `n` small random quads in the cube, each split as a fan into `(a, b, c)` and `(a, c, d)`
    /// (the pair the builder stores as one quad), except every fifth, whose second half is rotated
    /// (no pair), and a lone triangle after every seventh.
    fn quad_soup(n: usize, seed: u32) -> crate::geometry::TriangleMesh {
        let mut r = crate::accel::testutil::Rng(seed);
        let mut tris = vec![];
        for k in 0..n {
            let a = r.v(-1.0, 1.0);
            let (u, v) = (r.v(-0.15, 0.15), r.v(-0.15, 0.15));
            let (b, c, d) = (a + u, a + u + v + r.v(-0.02, 0.02), a + v);
            tris.push([a, b, c]);
            match k % 5 {
                4 => tris.push([c, d, a]),
                // The halves the other way round: paired too.
                3 => tris.insert(tris.len() - 1, [a, c, d]),
                _ => tris.push([a, c, d]),
            }
            if k % 7 == 6 {
                tris.push([a, a + v, a - u]);
            }
        }
        crate::accel::testutil::mesh(tris)
    }

    /// Trees over pairs: every primitive once, in a box that holds it; leaves of both kinds; and
    /// the same answers as brute force on every path (8 wide with AVX2, the SSE fallback, 4 wide,
    /// packets), with some primitives called back.
    #[test]
    fn trees_over_pairs_hold_every_triangle_once_and_agree_with_brute_force() {
        let m = quad_soup(3000, 41);
        let n = m.triangle_count();
        let p = prims(&m);
        assert!(crate::accel::bvh::pairs::pair_up(&p).is_some());
        for width in [4, 8] {
            let bvh = Bvh::build_with(
                &p,
                BvhOptions {
                    width,
                    ..Default::default()
                },
            );
            let hits = agrees_with_brute(
                &p,
                &rays(600, 42),
                |r, t, s| bvh.intersect(&p, r, t, s),
                |r, t, s| bvh.occluded(&p, r, t, s),
            );
            assert!(hits > 300, "{hits}");
            assert_eq!(bvh.stats().primitives, n);
            let (quads, tris) = match &bvh.wide {
                Wide::W4(w) => {
                    well_formed_over(w, n, Some(&p));
                    (w.quads.len(), w.blocks.len())
                }
                Wide::W8(w) => {
                    well_formed_over(w, n, Some(&p));
                    // Prefetching (large trees only) changes no answer.
                    let pf = WideBvh {
                        prefetch: true,
                        ..w.clone()
                    };
                    agrees_with_brute(
                        &p,
                        &rays(200, 46),
                        |r, t, s| pf.traverse::<_, false>(&p, r, t, s),
                        |r, t, s| pf.traverse::<_, true>(&p, r, t, s).is_some(),
                    );
                    // The deep traversal, which takes any kind of leaves.
                    agrees_with_brute(
                        &p,
                        &rays(200, 47),
                        |r, t, s| w.traverse_deep::<_, false, false>(&p, r, t, s),
                        |r, t, s| w.traverse_deep::<_, true, false>(&p, r, t, s).is_some(),
                    );
                    agrees_with_brute(
                        &p,
                        &rays(300, 43),
                        |r, t, s| w.traverse_sized::<_, false, false>(&p, r, t, s),
                        |r, t, s| w.traverse_sized::<_, true, false>(&p, r, t, s).is_some(),
                    );
                    (w.quads.len(), w.blocks.len())
                }
                Wide::Binary => unreachable!(),
            };
            // Most triangles sit in pair blocks, 26 bytes a triangle against 40.
            assert!(quads * 8 > n / 2 && tris > 0, "{quads} {tris}");
            // Off: triangle blocks only, and more bytes.
            let unpaired = Bvh::build_with(
                &p,
                BvhOptions {
                    width,
                    pairs: false,
                    ..Default::default()
                },
            );
            if let Wide::W8(w) = &unpaired.wide {
                assert!(w.quads.is_empty());
                well_formed(w, n);
            }
            let (paired, unpaired) = (bvh.stats().bytes, unpaired.stats().bytes);
            assert!(paired * 10 < unpaired * 9, "{paired} {unpaired}");
        }
        // Every ninth triangle called back: pairs only where both halves are triangles.
        let mixed = EveryNth(prims(&m), 9);
        let bvh = Bvh::build(&mixed);
        let Wide::W8(w) = &bvh.wide else {
            panic!("not 8 wide")
        };
        assert!(!w.quads.is_empty());
        well_formed_over(w, n, Some(&mixed));
        let hits = agrees_with_brute(
            &mixed,
            &rays(600, 44),
            |r, t, s| bvh.intersect(&mixed, r, t, s),
            |r, t, s| bvh.occluded(&mixed, r, t, s),
        );
        assert!(hits > 300, "{hits}");
        agrees_with_brute(
            &mixed,
            &rays(300, 48),
            |r, t, s| w.traverse_sized::<_, false, false>(&mixed, r, t, s),
            |r, t, s| {
                w.traverse_sized::<_, true, false>(&mixed, r, t, s)
                    .is_some()
            },
        );
        // A tree that is one leaf of pairs.
        let small = quad_soup(3, 49);
        let sp = prims(&small);
        let one = Bvh::build(&sp);
        let Wide::W8(w) = &one.wide else {
            panic!("not 8 wide")
        };
        assert!(w.root_leaf.is_some_and(|c| c & node::QUADS != 0));
        well_formed_over(w, small.triangle_count(), Some(&sp));
        // Random rays, and rays from far away aimed at each triangle's centroid.
        let aimed = (0..small.triangle_count()).flat_map(|i| {
            let c = small.vertices(i).iter().copied().sum::<Vec3>() / 3.0;
            [Vec3::new(9.0, 7.0, -8.0), Vec3::new(-6.0, -9.0, 5.0)].map(|o| Ray::new(o, c - o))
        });
        let all: Vec<Ray> = rays(300, 50).into_iter().chain(aimed).collect();
        let hits = agrees_with_brute(
            &sp,
            &all,
            |r, t, s| one.intersect(&sp, r, t, s),
            |r, t, s| one.occluded(&sp, r, t, s),
        );
        assert!(hits > 5, "{hits}");
    }

    /// Rays in packets through a tree over pairs answer as single rays do.
    #[test]
    fn packets_through_pairs_agree_with_single_rays() {
        let m = quad_soup(4000, 45);
        let p = prims(&m);
        let bvh = Bvh::build(&p);
        if !bvh.has_packets() {
            return; // no AVX2 here: packets go ray by ray
        }
        let eye = Vec3::new(0.1, 0.2, -4.0);
        let rays: Vec<Ray> = (0..64 * 8)
            .map(|k| {
                let (x, y) = ((k % 64) as f32 / 64.0 - 0.5, (k / 64) as f32 / 8.0 - 0.5);
                Ray::new(eye, Vec3::new(x, y, 1.5))
            })
            .collect();
        let mut s = crate::accel::TraversalStats::default();
        let mut hits = 0;
        for chunk in rays.chunks(super::PACKET) {
            let mut out = vec![None; chunk.len()];
            bvh.intersect_packet(&p, chunk, f32::INFINITY, &mut out, &mut s);
            for (r, o) in chunk.iter().zip(&out) {
                assert_eq!(*o, bvh.intersect(&p, r, f32::INFINITY, &mut s));
                hits += o.is_some() as usize;
            }
        }
        assert!(hits > 100, "{hits}");
    }

    /// Triangles whose index is a multiple of `.1` are "other" primitives, tested through the call
    /// back.
    struct EveryNth<'a>(MeshPrimitives<'a>, usize);

    impl Primitives for EveryNth<'_> {
        fn count(&self) -> usize {
            self.0.count()
        }
        fn bounds(&self, i: usize) -> crate::math::Aabb {
            self.0.bounds(i)
        }
        fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit> {
            self.0.intersect(i, ray, t_max)
        }
        fn watertight_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
            (!i.is_multiple_of(self.1)).then(|| self.0.mesh.vertices(i))
        }
    }

    #[test]
    fn collapse_keeps_every_primitive_once_and_nests_boxes() {
        for n in [1, 2, 5, 9, 300, 4000] {
            let m = soup(n, n as u32);
            let p = prims(&m);
            let b = binary(&p);
            let w4 = WideBvh::<4>::from_binary(&p, &b.nodes, &b.indices);
            let w8 = WideBvh::<8>::from_binary(&p, &b.nodes, &b.indices);
            well_formed(&w4, n);
            well_formed(&w8, n);
            // Collapsing only removes levels.
            assert!(w8.depth() <= w4.depth() && w4.depth() <= b.depth() + 1);
            if n >= 300 {
                // A full 8-wide node replaces seven binary interior nodes; nodes near the leaves
                // fill less.
                let interior = b.nodes.iter().filter(|x| !x.is_leaf()).count();
                assert!(
                    w8.nodes.len() * 2 < interior,
                    "{} {interior}",
                    w8.nodes.len()
                );
                assert!(w4.nodes.len() < interior, "{} {interior}", w4.nodes.len());
            }
        }
    }

    /// The scatter (the usual way) fills exactly the blocks, padding and flags the gather does,
    /// bit for bit, with triangles, called-back primitives and leaves of only the latter.
    #[test]
    fn scatter_fills_the_blocks_the_gather_does() {
        let m = soup(3001, 17);
        let mixed = Mixed(prims(&m));
        let moller = MeshPrimitives {
            mesh: &m,
            test: crate::geometry::TriangleTest::Moller,
        };
        fn both<P: Primitives>(p: &P) -> usize {
            let b = binary(p);
            let c = Collapse::<8>::run(&b.nodes);
            let mut x: Vec<TriBlock> = bytemuck::zeroed_vec(c.blocks);
            let mut y: Vec<TriBlock> = bytemuck::zeroed_vec(c.blocks);
            let test = LaneTest::of(p);
            let fx = gather(p, test, &c.leaves, &b.indices, &mut x);
            let fy = scatter(p, test, &c.leaves, &b.indices, &mut y);
            assert_eq!(fx, fy);
            let bits = |v: &[TriBlock]| -> Vec<u32> {
                v.iter()
                    .flat_map(|b| b.v.iter().flatten().map(|f| f.to_bits()).chain(b.id))
                    .collect()
            };
            assert!(bits(&x) == bits(&y));
            // Padded lanes exist (the test would not see them otherwise).
            assert!(c.leaves.iter().any(|l| l.count % 4 != 0));
            fx.iter().filter(|&&none| none).count()
        }
        assert_eq!(both(&prims(&m)), 0);
        assert!(both(&mixed) > 0);
        // Moller-Trumbore triangles are gathered too (as a vertex and two edges).
        assert_eq!(both(&moller), 0);
        assert!(both(&EveryNth(prims(&m), 1)) > 100);
    }

    /// Triangles whose index is odd are "other" primitives, tested through the call back.
    struct Mixed<'a>(MeshPrimitives<'a>);

    impl Primitives for Mixed<'_> {
        fn count(&self) -> usize {
            self.0.count()
        }
        fn bounds(&self, i: usize) -> crate::math::Aabb {
            self.0.bounds(i)
        }
        fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit> {
            self.0.intersect(i, ray, t_max)
        }
        fn watertight_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
            i.is_multiple_of(2).then(|| self.0.mesh.vertices(i))
        }
    }

    /// Primitives that are no triangle the blocks take: every leaf is called back, without the
    /// filter.
    #[test]
    fn leaves_without_triangles_are_flagged_and_agree() {
        let m = soup(2000, 6);
        let p = EveryNth(prims(&m), 1);
        let bvh = Bvh::build(&p);
        let Wide::W8(w) = &bvh.wide else {
            panic!("not 8 wide")
        };
        let leaves = w
            .nodes
            .iter()
            .flat_map(|n| n.child)
            .filter(|&c| c != node::EMPTY && node::is_leaf(c));
        assert!(leaves.clone().count() > 100);
        assert!(leaves.into_iter().all(|c| c & node::NO_TRIANGLES != 0));
        let hits = agrees_with_brute(
            &p,
            &rays(400, 8),
            |r, t, s| bvh.intersect(&p, r, t, s),
            |r, t, s| bvh.occluded(&p, r, t, s),
        );
        assert!(hits > 100, "{hits}");
        // Watertight and Moller-Trumbore triangles are gathered: no leaf is flagged.
        let moller = MeshPrimitives {
            mesh: &m,
            test: crate::geometry::TriangleTest::Moller,
        };
        for tree in [Bvh::build(&prims(&m)), Bvh::build(&moller)] {
            let Wide::W8(w) = &tree.wide else {
                panic!("not 8 wide")
            };
            assert!(w
                .nodes
                .iter()
                .flat_map(|n| n.child)
                .all(|c| c == node::EMPTY || c & node::NO_TRIANGLES == 0));
        }
    }

    /// Moller-Trumbore triangles as their first vertex and two edges, called back where
    /// `moller_triangle` says so (every `.1`-th): the hits are the scalar test's.
    struct MollerEveryNth<'a>(MeshPrimitives<'a>, usize);

    impl Primitives for MollerEveryNth<'_> {
        fn count(&self) -> usize {
            self.0.count()
        }
        fn bounds(&self, i: usize) -> crate::math::Aabb {
            self.0.bounds(i)
        }
        fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit> {
            self.0.intersect(i, ray, t_max)
        }
        fn moller_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
            (!i.is_multiple_of(self.1)).then(|| self.0.mesh.vertices(i))
        }
    }

    /// Trees of Moller-Trumbore blocks: every lane the triangle's vertex and edges, bit for bit,
    /// and the same answers as brute force over the scalar test on every path (AVX2, the SSE
    /// fallback, the deep traversal, 4 wide, a single leaf, packets), with some primitives called
    /// back; a refit reads the edges again.
    #[test]
    fn moller_trees_hold_edges_and_agree_with_brute_force() {
        use crate::geometry::triangle::moller_edges;
        let m = soup(3000, 51);
        let n = m.triangle_count();
        let moller = MeshPrimitives {
            mesh: &m,
            test: crate::geometry::TriangleTest::Moller,
        };
        let mixed = MollerEveryNth(moller, 7);
        // Lanes hold the edges of the triangle under their id (NaN where called back).
        fn lanes_hold_edges<const W: usize>(w: &WideBvh<W>, p: &impl Primitives, n: usize) {
            assert_eq!(w.test, LaneTest::Moller);
            let mut seen = vec![0; n];
            for c in w.nodes.iter().flat_map(|x| x.child) {
                if c == node::EMPTY || !node::is_leaf(c) {
                    continue;
                }
                assert_eq!(c & node::QUADS, 0);
                for (id, lane) in leaf_triangles(w, c) {
                    seen[id as usize] += 1;
                    assert_eq!(lane, p.moller_triangle(id as usize).map(moller_edges));
                }
            }
            assert!(seen.iter().all(|&k| k == 1));
        }
        for width in [4, 8] {
            let opts = BvhOptions {
                width,
                ..Default::default()
            };
            for (tree, p) in [
                (Bvh::build_with(&moller, opts), None),
                (Bvh::build_with(&mixed, opts), Some(&mixed)),
            ] {
                let hits = match p {
                    None => agrees_with_brute(
                        &moller,
                        &rays(500, 52),
                        |r, t, s| tree.intersect(&moller, r, t, s),
                        |r, t, s| tree.occluded(&moller, r, t, s),
                    ),
                    Some(p) => agrees_with_brute(
                        p,
                        &rays(500, 52),
                        |r, t, s| tree.intersect(p, r, t, s),
                        |r, t, s| tree.occluded(p, r, t, s),
                    ),
                };
                assert!(hits > 200, "{hits}");
                match &tree.wide {
                    Wide::W4(w) => match p {
                        None => lanes_hold_edges(w, &moller, n),
                        Some(p) => lanes_hold_edges(w, p, n),
                    },
                    Wide::W8(w) => {
                        match p {
                            None => lanes_hold_edges(w, &moller, n),
                            Some(p) => lanes_hold_edges(w, p, n),
                        }
                        agrees_with_brute(
                            &moller,
                            &rays(300, 53),
                            |r, t, s| w.traverse_sized::<_, false, false>(&moller, r, t, s),
                            |r, t, s| {
                                w.traverse_sized::<_, true, false>(&moller, r, t, s)
                                    .is_some()
                            },
                        );
                        agrees_with_brute(
                            &moller,
                            &rays(300, 54),
                            |r, t, s| w.traverse_deep::<_, false, false>(&moller, r, t, s),
                            |r, t, s| {
                                w.traverse_deep::<_, true, false>(&moller, r, t, s)
                                    .is_some()
                            },
                        );
                    }
                    Wide::Binary => unreachable!(),
                }
            }
        }
        // Packets answer as single rays do.
        let bvh = Bvh::build(&moller);
        if bvh.has_packets() {
            let eye = Vec3::new(0.1, 0.2, -4.0);
            let rays: Vec<Ray> = (0..64 * 8)
                .map(|k| {
                    let (x, y) = ((k % 64) as f32 / 64.0 - 0.5, (k / 64) as f32 / 8.0 - 0.5);
                    Ray::new(eye, Vec3::new(x, y, 1.5))
                })
                .collect();
            let mut s = crate::accel::TraversalStats::default();
            let mut hits = 0;
            for chunk in rays.chunks(super::PACKET) {
                let mut out = vec![None; chunk.len()];
                bvh.intersect_packet(&moller, chunk, f32::INFINITY, &mut out, &mut s);
                for (r, o) in chunk.iter().zip(&out) {
                    assert_eq!(*o, bvh.intersect(&moller, r, f32::INFINITY, &mut s));
                    hits += o.is_some() as usize;
                }
            }
            assert!(hits > 100, "{hits}");
        }
        // A tree of one leaf.
        let small = soup(5, 55);
        let sp = MeshPrimitives {
            mesh: &small,
            test: crate::geometry::TriangleTest::Moller,
        };
        let one = Bvh::build(&sp);
        let Wide::W8(w) = &one.wide else {
            panic!("not 8 wide")
        };
        assert!(w.root_leaf.is_some());
        let aimed = (0..5).map(|i| {
            let c = small.vertices(i).iter().copied().sum::<Vec3>() / 3.0;
            let o = Vec3::new(9.0, 7.0, -8.0);
            Ray::new(o, c - o)
        });
        let all: Vec<Ray> = rays(300, 56).into_iter().chain(aimed).collect();
        let hits = agrees_with_brute(
            &sp,
            &all,
            |r, t, s| one.intersect(&sp, r, t, s),
            |r, t, s| one.occluded(&sp, r, t, s),
        );
        assert!(hits >= 5, "{hits}");
        // A refit after the triangles moved reads their edges again.
        let mut moved = m.clone();
        for p in &mut moved.positions {
            *p = *p * 1.5 + Vec3::new(0.1, -0.2, 0.3);
        }
        let mp = MeshPrimitives {
            mesh: &moved,
            test: crate::geometry::TriangleTest::Moller,
        };
        let mut tree = Bvh::build(&moller);
        tree.refit(&mp);
        let Wide::W8(w) = &tree.wide else {
            panic!("not 8 wide")
        };
        lanes_hold_edges(w, &mp, n);
        let hits = agrees_with_brute(
            &mp,
            &rays(300, 57),
            |r, t, s| tree.intersect(&mp, r, t, s),
            |r, t, s| tree.occluded(&mp, r, t, s),
        );
        assert!(hits > 100, "{hits}");
    }

    #[test]
    fn called_back_primitives_mix_with_triangle_lanes() {
        let m = soup(3000, 4);
        let p = Mixed(prims(&m));
        for (width, compact) in [(4, false), (8, false), (4, true), (8, true)] {
            let bvh = Bvh::build_with(
                &p,
                BvhOptions {
                    width,
                    compact,
                    ..Default::default()
                },
            );
            let hits = agrees_with_brute(
                &p,
                &rays(500, 3),
                |r, t, s| bvh.intersect(&p, r, t, s),
                |r, t, s| bvh.occluded(&p, r, t, s),
            );
            assert!(hits > 200, "{hits}");
        }
    }

    /// Chain-like trees (midpoint splits peel the farthest triangle off, one level at a time)
    /// through the traversal with the large stack, which only trees deeper than any seen in
    /// practice take: it must answer like brute force too.
    #[test]
    fn the_deep_traversal_agrees_with_brute_force() {
        let tris: Vec<[Vec3; 3]> = (0..400)
            .map(|i| {
                let x = 1.05f32.powi(i);
                let c = Vec3::new(x, 0.0, 0.0);
                let s = 0.1 * x;
                [
                    c,
                    c + Vec3::new(0.5, 1.0, 0.0) * s,
                    c + Vec3::new(0.0, 0.3, 1.0) * s,
                ]
            })
            .collect();
        let m = crate::accel::testutil::mesh(tris);
        let p = prims(&m);
        let opts = BvhOptions {
            split: crate::accel::BvhSplit::Midpoint,
            ..Default::default()
        };
        let bvh = Bvh::build_with(&p, opts);
        let Wide::W8(w) = &bvh.wide else {
            panic!("not 8 wide")
        };
        let rays: Vec<Ray> = (0..400)
            .map(|i| {
                let x = 1.05f32.powi(i);
                Ray::new(Vec3::new(x * 1.015, 0.04 * x, -3.0), Vec3::Z)
            })
            .chain(rays(200, 5))
            .collect();
        let hits = agrees_with_brute(
            &p,
            &rays,
            |r, t, s| w.traverse_deep::<_, false, false>(&p, r, t, s),
            |r, t, s| w.traverse_deep::<_, true, false>(&p, r, t, s).is_some(),
        );
        assert!(hits > 300, "{hits}");
    }

    /// The traversal CPUs without AVX2 take: an 8-wide node's boxes tested as two SSE halves, and
    /// one SSE triangle filter per block.
    #[test]
    fn the_sse_fallback_agrees_with_brute_force() {
        let m = soup(3000, 12);
        let p = prims(&m);
        let bvh = Bvh::build(&p);
        let Wide::W8(w) = &bvh.wide else {
            panic!("not 8 wide")
        };
        let hits = agrees_with_brute(
            &p,
            &rays(500, 13),
            |r, t, s| w.traverse_sized::<_, false, false>(&p, r, t, s),
            |r, t, s| w.traverse_sized::<_, true, false>(&p, r, t, s).is_some(),
        );
        assert!(hits > 200, "{hits}");
    }

    #[test]
    fn prefetching_changes_no_answer() {
        // Small trees do not prefetch; force it on one, on both the AVX2 and the SSE path.
        let m = soup(3000, 14);
        let p = prims(&m);
        let bvh = Bvh::build(&p);
        let Wide::W8(w) = &bvh.wide else {
            panic!("not 8 wide")
        };
        assert!(!w.prefetch);
        let w = WideBvh {
            prefetch: true,
            ..w.clone()
        };
        let hits = agrees_with_brute(
            &p,
            &rays(500, 15),
            |r, t, s| w.traverse::<_, false>(&p, r, t, s),
            |r, t, s| w.traverse_sized::<_, true, false>(&p, r, t, s).is_some(),
        );
        assert!(hits > 200, "{hits}");
    }

    /// The twelve triangles of the box `lo..hi`, two to a face.
    fn cuboid(lo: Vec3, hi: Vec3) -> Vec<[Vec3; 3]> {
        let c = |i: usize| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        };
        let faces = [
            [0, 1, 3, 2],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 3, 7, 5],
        ];
        faces
            .iter()
            .flat_map(|&[a, b, d, e]| [[c(a), c(b), c(d)], [c(a), c(d), c(e)]])
            .collect()
    }

    /// A room of 36 triangles (its six walls and two boxes, a Cornell box's count) gets the small
    /// tree's leaves of at most four triangles, and rays from inside test fewer triangles than in
    /// the tree of the default leaves, which a file's explicit `traversal_cost` keeps; both answer
    /// like brute force.
    #[test]
    fn a_room_of_walls_gets_small_leaves_and_fewer_tests() {
        let mut tris = cuboid(Vec3::splat(-1.0), Vec3::splat(1.0));
        tris.extend(cuboid(Vec3::new(-0.8, -1.0, -0.7), Vec3::new(-0.2, 0.2, -0.1)));
        tris.extend(cuboid(Vec3::new(0.2, -1.0, 0.1), Vec3::new(0.7, -0.4, 0.6)));
        let m = crate::accel::testutil::mesh(tris);
        let p = prims(&m);
        let mut r = crate::accel::testutil::Rng(31);
        let inside: Vec<Ray> = (0..400)
            .map(|_| Ray::new(r.v(-0.95, 0.95), r.v(-1.0, 1.0)))
            .collect();
        let mut tests_per_tree = vec![];
        for opts in [
            BvhOptions::default(),
            BvhOptions {
                traversal_cost: 2.5,
                ..BvhOptions::default()
            },
        ] {
            let bvh = Bvh::build_with(&p, opts);
            let Wide::W8(w) = &bvh.wide else {
                panic!("not 8 wide")
            };
            well_formed_over(w, 36, Some(&p));
            let largest = w
                .nodes
                .iter()
                .flat_map(|n| n.child)
                .filter(|&c| c != node::EMPTY && node::is_leaf(c))
                .map(|c| leaf_triangles(w, c).len())
                .max()
                .unwrap();
            let hits = agrees_with_brute(
                &p,
                &inside,
                |r, t, s| w.traverse::<_, false>(&p, r, t, s),
                |r, t, s| w.traverse_sized::<_, true, false>(&p, r, t, s).is_some(),
            );
            assert!(hits > 700, "{hits}");
            let mut s = crate::accel::TraversalStats::default();
            for ray in &inside {
                w.traverse::<_, false>(&p, ray, f32::INFINITY, &mut s);
            }
            tests_per_tree.push((largest, s.prim_tests));
        }
        let [(small_leaf, small_tests), (default_leaf, default_tests)] = tests_per_tree[..] else {
            unreachable!()
        };
        assert!(small_leaf <= 4, "{small_leaf}");
        assert!(default_leaf > 4, "{default_leaf}");
        assert!(
            2 * small_tests < default_tests,
            "{small_tests} against {default_tests}"
        );
    }

    /// A tree of one leaf is tested without a node visit, and answers like brute force.
    #[test]
    fn a_single_leaf_tree_skips_the_node_test() {
        let m = soup(3, 21);
        let p = prims(&m);
        let bvh = Bvh::build(&p);
        let Wide::W8(w) = &bvh.wide else {
            panic!("not 8 wide")
        };
        assert!(w.root_leaf.is_some());
        // Random rays, and rays from far away aimed at each triangle's centroid.
        let aimed = (0..3).flat_map(|i| {
            let c = m.vertices(i).iter().copied().sum::<Vec3>() / 3.0;
            [Vec3::new(9.0, 7.0, -8.0), Vec3::new(-6.0, -9.0, 5.0)].map(|o| Ray::new(o, c - o))
        });
        let all: Vec<Ray> = rays(500, 22).into_iter().chain(aimed).collect();
        let hits = agrees_with_brute(
            &p,
            &all,
            |r, t, s| bvh.intersect(&p, r, t, s),
            |r, t, s| bvh.occluded(&p, r, t, s),
        );
        assert!(hits >= 6, "{hits}");
        let mut s = crate::accel::TraversalStats::default();
        for r in rays(50, 23) {
            bvh.intersect(&p, &r, f32::INFINITY, &mut s);
        }
        assert_eq!((s.rays, s.nodes_visited, s.prim_tests), (50, 0, 150));
        let big = Bvh::build(&prims(&soup(300, 1)));
        let Wide::W8(w) = &big.wide else {
            panic!("not 8 wide")
        };
        assert!(w.root_leaf.is_none());
    }

    /// Compact leaves hold the blocks' ids and nothing else, flag leaves without triangles
    /// as the blocks do, and answer like brute force (and so like the full blocks), with the AVX2
    /// pair filter, the SSE one, and leaves larger than two blocks (median splits down to 11).
    #[test]
    fn compact_leaves_agree_with_brute_force() {
        let m = soup(3000, 31);
        let moller = MeshPrimitives {
            mesh: &m,
            test: crate::geometry::TriangleTest::Moller,
        };
        let tri = prims(&m);
        for (split, leaf_size) in [
            (crate::accel::BvhSplit::Sah, 4),
            (crate::accel::BvhSplit::Median, 11),
        ] {
            let opts = BvhOptions {
                split,
                leaf_size,
                ..Default::default()
            };
            let full = Bvh::build_with(&tri, opts);
            let compact = Bvh::build_with(
                &tri,
                BvhOptions {
                    compact: true,
                    ..opts
                },
            );
            let (Wide::W8(f), Wide::W8(c)) = (&full.wide, &compact.wide) else {
                panic!("not 8 wide")
            };
            assert!(c.compact() && !f.compact() && c.blocks.is_empty());
            assert_eq!(c.nodes, f.nodes);
            assert!(c.ids.iter().zip(&f.blocks).all(|(i, b)| *i == b.id));
            assert_eq!(
                compact.stats().bytes,
                f.nodes.len() * 256 + f.blocks.len() * 16
            );
            let hits = agrees_with_brute(
                &tri,
                &rays(500, 32),
                |r, t, s| compact.intersect(&tri, r, t, s),
                |r, t, s| compact.occluded(&tri, r, t, s),
            );
            assert!(hits > 200, "{hits}");
            agrees_with_brute(
                &tri,
                &rays(300, 33),
                |r, t, s| c.traverse_sized::<_, false, false>(&tri, r, t, s),
                |r, t, s| c.traverse_sized::<_, true, false>(&tri, r, t, s).is_some(),
            );
        }
        let cm = Bvh::build_with(
            &moller,
            BvhOptions {
                compact: true,
                ..Default::default()
            },
        );
        let Wide::W8(w) = &cm.wide else {
            panic!("not 8 wide")
        };
        assert!(w
            .nodes
            .iter()
            .flat_map(|n| n.child)
            .all(|c| c == node::EMPTY || !node::is_leaf(c) || c & node::NO_TRIANGLES != 0));
        agrees_with_brute(
            &moller,
            &rays(300, 34),
            |r, t, s| cm.intersect(&moller, r, t, s),
            |r, t, s| cm.occluded(&moller, r, t, s),
        );
    }

    #[test]
    fn wide_stats_count_nodes_blocks_and_tests() {
        let m = soup(2000, 9);
        let p = prims(&m);
        let bvh = Bvh::build(&p);
        assert_eq!(bvh.width(), 8);
        let s = bvh.stats();
        let Wide::W8(w) = &bvh.wide else {
            panic!("not 8 wide")
        };
        assert_eq!(s.nodes, w.nodes.len());
        assert_eq!(s.bytes, w.nodes.len() * 256 + w.blocks.len() * 160);
        assert!(w.blocks.len() >= 2000 / 4);
        let mut ts = crate::accel::TraversalStats::default();
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        bvh.intersect(&p, &r, f32::INFINITY, &mut ts);
        assert_eq!(ts.rays, 1);
        assert!(ts.nodes_visited >= 1 && ts.prim_tests < 2000);
    }
}
