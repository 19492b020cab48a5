//! Single-ray traversal of the wide BVH: all children's slab tests at once, hit children visited
//! nearest first from an explicit stack that remembers each one's entry distance, so a child
//! farther than the best hit found since it was pushed is skipped when popped.
//!
//! The `W = 8` path uses AVX2 when the CPU has it (detected once, at run time); otherwise, and for
//! `W = 4`, the slab tests run four lanes at a time in SSE (part of every x86_64), or lane by lane
//! on other targets.

use super::leaf::{test_blocks, test_moller_blocks, test_quads};
use super::mt_block::LaneTest;
use super::node::{self, Child, WideNode};
use super::quad_block::QuadBlock;
use super::tri_block::{LaneValues, RayTri, TriBlock};
use super::WideBvh;
use crate::accel::{test_primitive, Hit, Primitives, TraversalStats};
use crate::math::{far_scale, Ray};
use std::mem::MaybeUninit;

/// A ray prepared for the slab tests. `near[a]` and `far[a]` pick the rows of [`WideNode::bounds`]
/// holding the near and far planes along axis `a`, by the sign bit of the direction (so `-0` counts
/// as negative and meets `1 / -0 = -inf`, Williams et al. 2005). `inv_far` is `inv` times
/// [`far_scale`], for the far planes (see [`slabs`]).
struct RayBoxes {
    o: [f32; 3],
    inv: [f32; 3],
    inv_far: [f32; 3],
    near: [usize; 3],
    far: [usize; 3],
    far_scale: f32,
}

impl RayBoxes {
    #[inline(always)]
    fn new(ray: &Ray) -> Self {
        let d = ray.dir;
        // The sign bits, read directly: `glam`'s indexing checks the index on every access.
        let neg = [d.x, d.y, d.z].map(|c| (c.to_bits() >> 31) as usize);
        let inv = d.recip().to_array();
        let far_scale = far_scale();
        Self {
            o: ray.origin.to_array(),
            inv,
            inv_far: inv.map(|i| i * far_scale),
            near: [neg[0], 2 + neg[1], 4 + neg[2]],
            far: [1 - neg[0], 3 - neg[1], 5 - neg[2]],
            far_scale,
        }
    }
}

#[derive(Clone, Copy)]
struct Entry {
    child: Child,
    t: f32,
}

/// The slab test of [`crate::math::RayBox::hits`] on every child, conservative in the same
/// way: the far distance is scaled by `1 + 2 gamma(3)` (Ize 2013). The scale is folded into the
/// reciprocal once per ray (`inv_far`) rather than applied at every node: `(b - o) (inv s)`
/// takes as many roundings as `((b - o) inv) s`, each a factor within `1 +- 2^-24`, so the same
/// error bound holds, and a node step saves three multiplications. A NaN slab distance (origin on
/// a slab's plane, direction parallel to it) is ignored by taking it as the first operand of
/// `max`/`min`, which return the second when either is NaN.
/// Returns the mask of children hit in `[0, t_cull]` and their entry distances.
#[inline(always)]
fn slabs<const W: usize, const AVX: bool>(
    n: &WideNode<W>,
    r: &RayBoxes,
    t_cull: f32,
    dist: &mut [f32; W],
) -> u32 {
    #[cfg(target_arch = "x86_64")]
    {
        if AVX && W == 8 {
            // SAFETY: `AVX` is true only inside `traverse_avx2`, entered after detecting AVX2.
            return unsafe { slabs8_avx(n.bounds.as_ptr().cast(), r, t_cull, dist.as_mut_ptr()) };
        }
        let mut mask = 0;
        for c in 0..W / 4 {
            // SAFETY: every row holds W >= 4 floats, and `4 c + 3 < W`.
            mask |= unsafe {
                slabs4_sse(
                    n.bounds.as_ptr().cast(),
                    W,
                    4 * c,
                    r,
                    t_cull,
                    dist.as_mut_ptr(),
                )
            } << (4 * c);
        }
        mask
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let mut mask = 0;
        for (lane, d) in dist.iter_mut().enumerate() {
            let mut t0 = 0.0f32;
            let mut t1 = t_cull;
            for a in 0..3 {
                t0 = t0.max((n.bounds[r.near[a]][lane] - r.o[a]) * r.inv[a]);
                t1 = t1.min((n.bounds[r.far[a]][lane] - r.o[a]) * r.inv_far[a]);
            }
            *d = t0;
            mask |= ((t0 <= t1) as u32) << lane;
        }
        mask
    }
}

/// The slab test's body over any lane width: `$row(k)` loads the lanes of row `k` of the bounds.
#[cfg(target_arch = "x86_64")]
macro_rules! slab_lanes {
    ($r:expr, $t_cull:expr, $row:expr) => {{
        let r: &RayBoxes = $r;
        let row = $row;
        let mut t0 = splat(0.0);
        let mut t1 = splat($t_cull);
        for a in 0..3 {
            let o = splat(r.o[a]);
            t0 = max(mul(sub(row(r.near[a]), o), splat(r.inv[a])), t0);
            t1 = min(mul(sub(row(r.far[a]), o), splat(r.inv_far[a])), t1);
        }
        (t0, le(t0, t1))
    }};
}

/// Four lanes starting at `lane` of a node whose rows hold `w` floats each.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn slabs4_sse(
    bounds: *const f32,
    w: usize,
    lane: usize,
    r: &RayBoxes,
    t_cull: f32,
    dist: *mut f32,
) -> u32 {
    use super::simd::sse::*;
    let (t0, hit) = slab_lanes!(r, t_cull, |k: usize| loadu(bounds.add(k * w + lane)));
    store(dist.add(lane), t0);
    mask(hit)
}

#[cfg(target_arch = "x86_64")]
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn slabs8_avx(bounds: *const f32, r: &RayBoxes, t_cull: f32, dist: *mut f32) -> u32 {
    use super::simd::avx::*;
    let (t0, hit) = slab_lanes!(r, t_cull, |k: usize| loadu(bounds.add(k * 8)));
    store(dist, t0);
    mask(hit)
}

/// What a tree's leaves hold, the traversal's `LEAVES` parameter, so that each kind of tree runs
/// code with no test for the others: triangle blocks (and called-back primitives) only. A test for
/// pairs at every leaf visit would be paid by every ray through a tree without pairs.
pub(super) const BLOCKS: u8 = 0;
/// Compact leaves: primitive ids, their vertices fetched at each visit.
pub(super) const COMPACT: u8 = 1;
/// Triangle blocks and blocks of pairs ([`node::QUADS`]).
pub(super) const PAIRS: u8 = 2;
/// Moller-Trumbore blocks (`mt_block.rs`), and called-back primitives.
pub(super) const MOLLER: u8 = 3;

/// Which traversal a tree's rays take, decided once at the build ([`Path::of`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) enum Path {
    /// No nodes: every ray misses.
    #[default]
    Empty,
    /// A tree of one leaf, tested without a node visit.
    RootLeaf(Child),
    /// 8 wide on a CPU with AVX2, triangle blocks (and called-back primitives) only...
    #[cfg(target_arch = "x86_64")]
    Avx2Blocks,
    /// ...or with blocks of pairs too...
    #[cfg(target_arch = "x86_64")]
    Avx2Pairs,
    /// ...or Moller-Trumbore blocks.
    #[cfg(target_arch = "x86_64")]
    Avx2Moller,
    /// SSE (or scalar) node tests: 4 wide, or no AVX2.
    Sized,
}

impl Path {
    pub(super) fn of<const W: usize>(tree: &WideBvh<W>) -> Self {
        if tree.nodes.is_empty() {
            return Path::Empty;
        }
        if let Some(leaf) = tree.root_leaf {
            return Path::RootLeaf(leaf);
        }
        #[cfg(target_arch = "x86_64")]
        if W == 8 && crate::accel::has_avx2() {
            return if tree.test == LaneTest::Moller {
                Path::Avx2Moller
            } else if tree.quads.is_empty() {
                Path::Avx2Blocks
            } else {
                Path::Avx2Pairs
            };
        }
        Path::Sized
    }
}

/// Stack entries a traversal may need: each level pushes at most `W` children and pops one.
pub(super) fn stack_need<const W: usize>(depth: usize) -> usize {
    depth * (W - 1) + 1
}

impl<const W: usize> WideBvh<W> {
    #[inline]
    pub(crate) fn traverse<P: Primitives, const ANY: bool>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        stats.rays += 1;
        // One branch on the way decided at the build, rather than a test per condition (each
        // would cost instructions on every ray, a real share of a ray through a small scene).
        match self.path {
            Path::Empty => None,
            Path::RootLeaf(leaf) => {
                self.traverse_root_leaf::<P, ANY>(leaf, prims, ray, t_max, stats)
            }
            // SAFETY (both): the builder chose these paths after detecting AVX2. One function per
            // kind of leaves: with both kinds' traversals inlined into one, its entry saves more
            // registers, which every ray through a tree without pairs would pay for.
            #[cfg(target_arch = "x86_64")]
            Path::Avx2Blocks => unsafe {
                self.traverse_avx2::<P, ANY, BLOCKS>(prims, ray, t_max, stats)
            },
            #[cfg(target_arch = "x86_64")]
            Path::Avx2Pairs => unsafe {
                self.traverse_avx2::<P, ANY, PAIRS>(prims, ray, t_max, stats)
            },
            #[cfg(target_arch = "x86_64")]
            Path::Avx2Moller => unsafe {
                self.traverse_avx2::<P, ANY, MOLLER>(prims, ray, t_max, stats)
            },
            Path::Sized => self.traverse_sized::<P, ANY, false>(prims, ray, t_max, stats),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn traverse_avx2<P: Primitives, const ANY: bool, const LEAVES: u8>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        self.traverse_sized_as::<P, ANY, true, LEAVES>(prims, ray, t_max, stats)
    }

    /// The primitive count of a tree that is one leaf of called-back primitives, whose queries
    /// [`Self::traverse_root_leaf`] answers by [`Primitives::intersect_all`] when it holds them all.
    #[inline(always)]
    pub(crate) fn single_leaf(&self) -> Option<usize> {
        let leaf = self.root_leaf?;
        (leaf & node::NO_TRIANGLES != 0).then(|| node::leaf_range(leaf).1)
    }

    /// A tree that is a single leaf: its primitives tested directly, without the set-up of a
    /// node traversal, which costs more than a handful of primitive tests (Whitted's scene).
    #[inline(never)]
    fn traverse_root_leaf<P: Primitives, const ANY: bool>(
        &self,
        leaf: Child,
        prims: &P,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        if leaf & node::NO_TRIANGLES != 0 {
            // Spheres, rectangles and the like: a loop of calls, kept apart from the triangle
            // filter's set-up, whose registers and stack frame would otherwise be paid for on every
            // ray.
            let (first, count) = node::leaf_range(leaf);
            stats.prim_tests += count as u64;
            if count == prims.count() {
                // The leaf holds every primitive: the set may know a faster way to test them all.
                return prims.intersect_all::<ANY>(ray, &mut t_max, stats);
            }
            let ids = self.blocks[first..].iter().flat_map(|b| b.id).take(count);
            return prims.intersect_ids::<ANY>(ids, ray, &mut t_max, stats);
        }
        self.root_leaf_triangles::<P, ANY>(leaf, prims, ray, t_max, stats)
    }

    /// [`Self::traverse_root_leaf`] of a leaf with triangles, in a function of its own (see there).
    #[inline(never)]
    fn root_leaf_triangles<P: Primitives, const ANY: bool>(
        &self,
        leaf: Child,
        prims: &P,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        let mut best = None;
        if self.compact() {
            self.leaf::<P, ANY, false, COMPACT>(
                leaf, &mut None, prims, ray, &mut t_max, &mut best, stats,
            );
        } else if self.test == LaneTest::Moller {
            self.leaf::<P, ANY, false, MOLLER>(
                leaf, &mut None, prims, ray, &mut t_max, &mut best, stats,
            );
        } else {
            self.leaf::<P, ANY, false, PAIRS>(
                leaf, &mut None, prims, ray, &mut t_max, &mut best, stats,
            );
        }
        best
    }

    /// Tests one leaf, narrowing `t_max` and setting `best` at each nearer hit (with `ANY`,
    /// stopping at the first). `rt` is the triangle filter's per-ray set-up, made at the first
    /// leaf that needs it.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn leaf<P: Primitives, const ANY: bool, const AVX: bool, const LEAVES: u8>(
        &self,
        leaf: Child,
        rt: &mut Option<RayTri>,
        prims: &P,
        ray: &Ray,
        t_max: &mut f32,
        best: &mut Option<Hit>,
        stats: &mut TraversalStats,
    ) {
        let (first, count) = node::leaf_range(leaf);
        if LEAVES == PAIRS && leaf & node::QUADS != 0 {
            // SAFETY: the builder wrote this leaf's blocks, `first..first + ceil(count / 4)`.
            let quads = unsafe { self.quads.get_unchecked(first..first + count.div_ceil(4)) };
            let rt = rt.get_or_insert_with(|| RayTri::new(ray));
            test_quads::<P, ANY, AVX>(quads, count, rt, prims, ray, t_max, best, stats);
            return;
        }
        stats.prim_tests += count as u64;
        if LEAVES == COMPACT {
            self.compact_leaf::<P, ANY, AVX>(leaf, rt, prims, ray, t_max, best, stats);
            return;
        }
        let blocks = &self.blocks[first..first + count.div_ceil(4)];
        if LEAVES == MOLLER && leaf & node::NO_TRIANGLES == 0 {
            test_moller_blocks::<P, ANY, AVX>(blocks, count, prims, ray, t_max, best, stats);
            return;
        }
        if leaf & node::NO_TRIANGLES == 0 {
            let rt = rt.get_or_insert_with(|| RayTri::new(ray));
            test_blocks::<P, ANY, AVX>(blocks, count, rt, prims, ray, t_max, best, stats);
            return;
        }
        // Spheres, implicit surfaces, instances: no filter, every primitive called back.
        // The ids in order, without an index check per primitive.
        let ids = blocks.iter().flat_map(|b| b.id).take(count);
        if let Some(h) = prims.intersect_ids::<ANY>(ids, ray, t_max, stats) {
            *best = Some(h);
        }
    }

    /// A compact leaf: its triangles fetched through `prims` into blocks on the stack, two at a
    /// time, then tested as a leaf of blocks is, so that the hits are the same bit for bit.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn compact_leaf<P: Primitives, const ANY: bool, const AVX: bool>(
        &self,
        leaf: Child,
        rt: &mut Option<RayTri>,
        prims: &P,
        ray: &Ray,
        t_max: &mut f32,
        best: &mut Option<Hit>,
        stats: &mut TraversalStats,
    ) {
        let (first, count) = node::leaf_range(leaf);
        let ids = &self.ids[first..first + count.div_ceil(4)];
        if leaf & node::NO_TRIANGLES != 0 {
            // Called back in order, as a leaf of blocks is (`Self::leaf`).
            let in_order = ids.iter().flatten().copied().take(count);
            if let Some(h) = prims.intersect_ids::<ANY>(in_order, ray, t_max, stats) {
                *best = Some(h);
            }
            return;
        }
        let rt = rt.get_or_insert_with(|| RayTri::new(ray));
        let mut vals = LaneValues::new();
        let mut buf = [TriBlock::PADDING; 2];
        let mut at = 0;
        while at < ids.len() {
            // Two blocks per AVX filter where the leaf has them, as `leaf_blocks` does.
            let step = if AVX && at + 1 < ids.len() { 2 } else { 1 };
            let n = (count - 4 * at).min(4 * step);
            for (b, lanes) in ids[at..at + step].iter().enumerate() {
                buf[b] =
                    TriBlock::gather(prims, LaneTest::Watertight, &lanes[..(n - 4 * b).min(4)]);
            }
            #[cfg(target_arch = "x86_64")]
            let mut m = if step == 2 {
                // SAFETY: `AVX` is true only inside `traverse_avx2`.
                unsafe { rt.candidates_pair_avx2(&buf[0], &buf[1], *t_max, &mut vals) }
            } else {
                rt.candidates(&buf[0], *t_max, &mut vals)
            };
            #[cfg(not(target_arch = "x86_64"))]
            let mut m = rt.candidates(&buf[0], *t_max, &mut vals);
            if n < 8 {
                m &= (1 << n) - 1;
            }
            // The kept lanes get the scalar test through `prims` (the filter's values are not
            // reused here): the same hits bit for bit, and no second copy of the finishing code
            // beside the usual leaf test's, which the compiler would then stop inlining there.
            let pair = &ids[at..at + step];
            at += step;
            while m != 0 {
                let bit = m.trailing_zeros() as usize;
                m &= m - 1;
                let id = pair[bit / 4][bit % 4];
                if let Some(h) = test_primitive::<P, ANY>(prims, id as usize, ray, *t_max, stats) {
                    *best = Some(Hit::new(id as usize, h));
                    if ANY {
                        return;
                    }
                    *t_max = h.t;
                }
            }
        }
    }

    /// Asks for a waiting child's node (or its leaf's first two triangle blocks or first block of
    /// pairs: most leaves hold up to eight triangles) to be brought into the cache while the
    /// nearer children are visited.
    #[inline(always)]
    fn prefetch_child(&self, child: Child) {
        if node::is_leaf(child) {
            let (first, _) = node::leaf_range(child);
            if child & node::QUADS != 0 {
                let at = self.quads.as_ptr().wrapping_add(first);
                crate::accel::prefetch(at, std::mem::size_of::<QuadBlock>());
            } else {
                let at = self.blocks.as_ptr().wrapping_add(first);
                crate::accel::prefetch(at, 2 * std::mem::size_of::<TriBlock>());
            }
        } else {
            let at = self.nodes.as_ptr().wrapping_add(child as usize);
            crate::accel::prefetch(at, std::mem::size_of::<WideNode<W>>());
        }
    }

    /// Picks a stack just large enough for the tree's depth. Compact leaves take the other
    /// function too, so that the usual one has no trace of them (a test per leaf visit would be
    /// paid by every ray); a tree without pairs of triangles takes an
    /// instance that does not test for them ([`LEAVES`](BLOCKS)).
    #[inline(always)]
    pub(super) fn traverse_sized<P: Primitives, const ANY: bool, const AVX: bool>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        if self.test == LaneTest::Moller {
            self.traverse_sized_as::<P, ANY, AVX, MOLLER>(prims, ray, t_max, stats)
        } else if self.quads.is_empty() {
            self.traverse_sized_as::<P, ANY, AVX, BLOCKS>(prims, ray, t_max, stats)
        } else {
            self.traverse_sized_as::<P, ANY, AVX, PAIRS>(prims, ray, t_max, stats)
        }
    }

    /// [`Self::traverse_sized`] for a tree whose leaves are of kind `LEAVES` (or, for the deep
    /// traversal, any kind).
    #[inline(always)]
    fn traverse_sized_as<P: Primitives, const ANY: bool, const AVX: bool, const LEAVES: u8>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        if self.common {
            self.traverse_with::<P, ANY, AVX, LEAVES, 128>(prims, ray, t_max, stats)
        } else {
            self.traverse_deep::<P, ANY, AVX>(prims, ray, t_max, stats)
        }
    }

    /// Trees deeper than the common case, and compact leaves, get their own function, so that the
    /// common one keeps a small stack frame.
    #[inline(never)]
    pub(super) fn traverse_deep<P: Primitives, const ANY: bool, const AVX: bool>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        // The builder bounds the depth (a forced median split past depth 64), so this always
        // suffices.
        debug_assert!(stack_need::<W>(self.depth) <= 1024);
        if self.compact() {
            return self.traverse_with::<P, ANY, AVX, COMPACT, 1024>(prims, ray, t_max, stats);
        }
        if self.test == LaneTest::Moller {
            return self.traverse_with::<P, ANY, AVX, MOLLER, 1024>(prims, ray, t_max, stats);
        }
        self.traverse_with::<P, ANY, AVX, PAIRS, 1024>(prims, ray, t_max, stats)
    }

    #[inline(always)]
    fn traverse_with<
        P: Primitives,
        const ANY: bool,
        const AVX: bool,
        const LEAVES: u8,
        const N: usize,
    >(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        self.traverse_from::<P, ANY, AVX, LEAVES, N>(0, prims, ray, t_max, stats)
    }

    /// The traversal of the subtree under interior node `start` (the root is node 0): packets
    /// hand a lone remaining ray to it.
    #[inline(always)]
    pub(super) fn traverse_from<
        P: Primitives,
        const ANY: bool,
        const AVX: bool,
        const LEAVES: u8,
        const N: usize,
    >(
        &self,
        start: Child,
        prims: &P,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        let rb = RayBoxes::new(ray);
        // The triangle filter's set-up (three divisions) waits for the first leaf with triangles.
        let mut rt: Option<RayTri> = None;
        let far = rb.far_scale;
        // Boxes are culled against a slightly larger distance than the best hit, so that rounding in
        // the box test never culls a primitive whose own test would report a nearer hit.
        let mut t_cull = t_max * far;
        let mut stack = [const { MaybeUninit::<Entry>::uninit() }; N];
        let mut sp = 0usize;
        let mut best = None;
        let mut dist = [0.0f32; W];
        let mut cur: Child = start;
        // Pushes the children of node `$n` in `$mask`, in lane order, with their entry distances;
        // in large trees it asks for each to be brought into the cache meanwhile. (A macro: as an
        // inlined method taking the stack and its pointer, the compiler keeps less of the
        // traversal's state in registers.)
        macro_rules! push_children {
            ($n:expr, $mask:expr) => {{
                let mut m: u32 = $mask;
                while m != 0 {
                    let lane = m.trailing_zeros() as usize & (W - 1);
                    m &= m - 1;
                    stack[sp] = MaybeUninit::new(Entry {
                        child: $n.child[lane],
                        t: dist[lane],
                    });
                    sp += 1;
                    if self.prefetch {
                        self.prefetch_child($n.child[lane]);
                    }
                }
            }};
        }
        loop {
            if !node::is_leaf(cur) {
                // SAFETY: child slots hold indices of nodes the collapse wrote.
                let n = unsafe { self.nodes.get_unchecked(cur as usize) };
                stats.nodes_visited += 1;
                let mask = slabs::<W, AVX>(n, &rb, t_cull, &mut dist);
                if mask != 0 {
                    // `& (W - 1)`: the mask has `W` bits; it lets the compiler drop index checks.
                    let first = mask.trailing_zeros() as usize & (W - 1);
                    let rest = mask & (mask - 1);
                    if rest == 0 {
                        cur = n.child[first];
                        continue;
                    }
                    if !ANY && rest & (rest - 1) == 0 {
                        // Two children: the farther waits, the nearer is visited
                        // next (on a tie the later lane, as the sort below orders them).
                        let second = rest.trailing_zeros() as usize & (W - 1);
                        let (near, far) = if dist[first] < dist[second] {
                            (first, second)
                        } else {
                            (second, first)
                        };
                        push_children!(n, 1 << far);
                        cur = n.child[near];
                        continue;
                    }
                    if ANY {
                        // Any hit at all ends an any-hit query, so the children go unsorted
                        // (sorting would only delay the first hit): the last one hit is visited
                        // next, the others wait.
                        let last = (31 - mask.leading_zeros()) as usize & (W - 1);
                        push_children!(n, mask & !(1 << last));
                        cur = n.child[last];
                        continue;
                    }
                    // Push every child hit, then order the pushed run so the nearest is on top.
                    let base = sp;
                    push_children!(n, mask);
                    // SAFETY: entries `base..sp` were just written.
                    let run = unsafe {
                        std::slice::from_raw_parts_mut(
                            stack.as_mut_ptr().add(base).cast::<Entry>(),
                            sp - base,
                        )
                    };
                    for i in 1..run.len() {
                        let e = run[i];
                        let mut j = i;
                        while j > 0 && run[j - 1].t < e.t {
                            run[j] = run[j - 1];
                            j -= 1;
                        }
                        run[j] = e;
                    }
                    sp -= 1;
                    // SAFETY: entry `sp` was written above.
                    cur = unsafe { stack[sp].assume_init() }.child;
                    continue;
                }
            } else {
                self.leaf::<P, ANY, AVX, LEAVES>(
                    cur, &mut rt, prims, ray, &mut t_max, &mut best, stats,
                );
                if ANY && best.is_some() {
                    return best;
                }
                t_cull = t_max * far;
            }
            // Pop the nearest waiting child that can still hold a nearer hit.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                // SAFETY: entries below `sp` were written before.
                let e = unsafe { stack[sp].assume_init() };
                if e.t <= t_cull {
                    cur = e.child;
                    break;
                }
            }
        }
    }
}
