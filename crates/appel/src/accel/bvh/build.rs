//! Top-down BVH construction over primitive bounds and centroids.
//!
//! Binned SAH after Wald 2007 ("On fast construction of SAH-based bounding volume hierarchies"):
//! centroids are binned along all three axes in one pass and every bin boundary is a candidate plane.
//! Build memory is flat: one array of 32-byte (bounds, id) records that the build partitions in
//! place - moving the records rather than indices into them keeps every pass sequential in memory -
//! so a leaf ends up a contiguous range of it. Large ranges are built in parallel
//! (`rayon::join`) into separate node arrays, each copied once into the final depth-first array.

use super::build_prim::Box4;
pub(crate) use super::build_prim::BuildPrim;
use super::node::BvhNode;
use crate::math::Aabb;
use glam::Vec4;
use rayon::prelude::*;

/// How an interior node chooses its split.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BvhSplit {
    /// Binned surface area heuristic (Goldsmith & Salmon 1987, MacDonald & Booth 1990).
    #[default]
    Sah,
    /// Split the centroid bounds at the middle of their largest axis.
    Midpoint,
    /// Split into two halves of equal count along the largest centroid axis.
    Median,
}

impl BvhSplit {
    pub const NAMES: &'static [&'static str] = &["sah", "midpoint", "median"];

    pub fn name(self) -> &'static str {
        match self {
            Self::Sah => "sah",
            Self::Midpoint => "midpoint",
            Self::Median => "median",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "sah" => Some(Self::Sah),
            "midpoint" => Some(Self::Midpoint),
            "median" => Some(Self::Median),
            _ => None,
        }
    }
}

/// Build parameters. The SAH cost of a node is `traversal_cost + intersect_cost * (n_l * A_l + n_r *
/// A_r) / A` against `intersect_cost * n` for making it a leaf. `[render.bvh]` sets all but `block`
/// and `parallel_threshold`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct BvhOptions {
    pub split: BvhSplit,
    /// Children per node: 2 (the binary tree as built), or 4 or 8 (collapsed, SIMD slab tests and
    /// triangles tested four at a time).
    pub width: usize,
    /// SAH bins per axis, clamped to `2..=32`.
    pub bins: usize,
    /// The largest leaf SAH may keep (it splits larger sets whatever the cost); at most 255.
    pub max_leaf: usize,
    /// Midpoint and median splits stop at this many primitives.
    pub leaf_size: usize,
    pub traversal_cost: f32,
    /// The cost of testing one block of primitives.
    pub intersect_cost: f32,
    /// Primitives tested together (the SAH counts a leaf of `n` as `ceil(n / block)` tests), a power
    /// of two (others are rounded up): 4 for the wide layouts, whose leaves test triangles four at a
    /// time; 0 means 4 when `width > 2` and 1 otherwise.
    #[serde(skip)]
    pub block: usize,
    /// Ranges larger than this build their two children in parallel.
    #[serde(skip)]
    pub parallel_threshold: usize,
    /// Wide layouts only: leaves keep their primitives' ids (4 bytes each) instead of their
    /// triangles' vertices (40 bytes each), which traversal fetches through `Primitives` at
    /// every leaf visit: a quarter of the structure's memory, slower rays (docs/performance.md).
    pub compact: bool,
    /// Wide layouts with vertex blocks: build over pairs of triangles that share an edge where at
    /// least half of the triangles pair (meshes of quads), stored four vertices per pair
    /// (`accel/bvh/pairs.rs`). The hits are the same; memory and build time fall.
    pub pairs: bool,
}

impl Default for BvhOptions {
    fn default() -> Self {
        Self {
            split: BvhSplit::Sah,
            width: 8,
            bins: 16,
            max_leaf: 8,
            leaf_size: 4,
            // A node visit weighs twice a triangle test (docs/accel.md): cheaper nodes make
            // leaves of one or two triangles, more memory and slower traversal; dearer ones fewer
            // nodes but slower camera rays.
            traversal_cost: 2.0,
            intersect_cost: 1.0,
            block: 0,
            parallel_threshold: 32 * 1024,
            compact: false,
            pairs: true,
        }
    }
}

const MAX_BINS: usize = 32;
/// Beyond this depth every split is a median split, which halves the count: the tree is then at most
/// `FORCE_MEDIAN_DEPTH + 33` deep for up to 2^32 primitives, so traversal's fixed stack always suffices.
const FORCE_MEDIAN_DEPTH: usize = 64;
/// Ranges larger than this bin and bound their centroids in parallel chunks.
const PARALLEL_SCAN: usize = 128 * 1024;

/// `ceil(n / block)` by a shift: the SAH sweep asks it twice per candidate plane.
#[derive(Clone, Copy)]
pub(crate) struct BlockCount {
    add: u32,
    shift: u32,
}

impl BlockCount {
    pub fn new(o: &BvhOptions) -> Self {
        let b = o.block_size() as u32;
        Self {
            add: b - 1,
            shift: b.trailing_zeros(),
        }
    }

    #[inline(always)]
    pub fn of(self, n: u32) -> f32 {
        ((n + self.add) >> self.shift) as f32
    }
}

pub(super) struct Ctx {
    pub opts: BvhOptions,
}

impl BvhOptions {
    /// The leaf block size in effect (see [`BvhOptions::block`]), rounded up to a power of two.
    pub fn block_size(&self) -> usize {
        match self.block {
            0 if self.width > 2 => 4,
            0 => 1,
            b => b.next_power_of_two(),
        }
    }

    /// The options for a build over pairs of triangles, each item two triangles: leaf sizes halved,
    /// so that leaves hold as many triangles as in a build over triangles, and a block of four
    /// items costed as one, though it holds eight triangles: it is one AVX filter run, as a pair of
    /// triangle blocks is. Costed as two triangle blocks, the SAH overprices leaves of pairs and
    /// builds a larger, slower tree (docs/performance.md keeps the comparison). The tree's SAH cost
    /// (`--stats`) then counts blocks of pairs, so it is not comparable with a build over
    /// single triangles.
    pub(crate) fn for_pairs(&self) -> Self {
        Self {
            block: self.block_size(),
            // The builder clamps `max_leaf` to 255: halve what it would use.
            max_leaf: (self.max_leaf.clamp(1, 255) / 2).max(1),
            leaf_size: (self.leaf_size / 2).max(1),
            ..*self
        }
    }
}

/// Trees over this many build items (triangles, pairs, other primitives) are built with
/// [`BvhOptions::for_small_tree`]. Up to eight the defaults make the tree one leaf, which
/// traversal tests without a node visit (cheaper than any tree: Whitted's scene); from 65 on,
/// the defaults' leaves are a small part of the tree.
pub(crate) const SMALL_TREE_ITEMS: std::ops::RangeInclusive<usize> = 9..=64;

impl BvhOptions {
    /// The options for a tree of a handful of items (a Cornell box: 36 triangles), when the caller
    /// left the leaf size and the costs at their defaults. The defaults price a node visit at two
    /// blocks of four, so every range of up to eight items is a leaf: the box's walls, each a
    /// slab spanning the room, shared leaves, and every ray from inside the room entered most of
    /// them, testing most of its triangles under one 8-wide node. Leaves of at most four triangles
    /// (two pairs), split wherever the SAH sees any gain, let a ray test only the walls it can
    /// meet (docs/performance.md); the tree's memory is a few kilobytes either way.
    pub(crate) fn for_small_tree(&self) -> Self {
        let default = Self::default();
        if self.max_leaf != default.max_leaf || self.traversal_cost != default.traversal_cost {
            return *self;
        }
        Self {
            max_leaf: 4,
            leaf_size: self.leaf_size.min(4),
            traversal_cost: 0.1,
            ..*self
        }
    }
}

/// The top of the tree, built in parallel: a few boxed nodes above chunks built sequentially.
enum Top {
    Interior {
        bounds: Aabb,
        axis: u16,
        children: Box<(Top, Top)>,
    },
    Chunk(Vec<BvhNode>),
}

/// Bounds of a range's primitives and of their centroids: what a node needs to decide its split.
#[derive(Clone, Copy)]
struct RangeBounds {
    bounds: Box4,
    centroids: Box4,
}

enum Decision {
    Leaf,
    /// The range was partitioned: `[..mid]` goes left. The children's bounds come with the split
    /// (from the SAH bins and the partition pass), so no child scans its range again for them.
    Split {
        mid: usize,
        axis: usize,
        left: RangeBounds,
        right: RangeBounds,
    },
}

/// Builds the flattened tree; `indices` (all primitives, in any order) is reordered so that each leaf
/// is a contiguous range of it.
pub(super) fn build(ctx: &Ctx, indices: &mut [BuildPrim]) -> Vec<BvhNode> {
    if indices.is_empty() {
        return Vec::new();
    }
    let top = build_top(ctx, indices, range_bounds(indices), 0, 0);
    let mut out = Vec::new();
    flatten(top, &mut out);
    out
}

fn build_top(
    ctx: &Ctx,
    indices: &mut [BuildPrim],
    rb: RangeBounds,
    base: usize,
    depth: usize,
) -> Top {
    if indices.len() <= ctx.opts.parallel_threshold {
        let mut v = Vec::with_capacity(indices.len());
        build_seq(ctx, indices, rb, base, depth, &mut v);
        return Top::Chunk(v);
    }
    let bounds = rb.bounds;
    match decide(ctx, indices, rb, depth) {
        Decision::Leaf => Top::Chunk(vec![leaf(bounds.to_aabb(), base, indices.len())]),
        Decision::Split {
            mid,
            axis,
            left,
            right,
        } => {
            let (l, r) = indices.split_at_mut(mid);
            let children = rayon::join(
                || build_top(ctx, l, left, base, depth + 1),
                || build_top(ctx, r, right, base + mid, depth + 1),
            );
            Top::Interior {
                bounds: bounds.to_aabb(),
                axis: axis as u16,
                children: Box::new(children),
            }
        }
    }
}

/// Appends the subtree over `indices` to `out` in depth-first order. Interior offsets are relative to
/// the start of `out`; leaf offsets are absolute positions in the index array.
fn build_seq(
    ctx: &Ctx,
    indices: &mut [BuildPrim],
    rb: RangeBounds,
    base: usize,
    depth: usize,
    out: &mut Vec<BvhNode>,
) {
    let me = out.len();
    match decide(ctx, indices, rb, depth) {
        Decision::Leaf => out.push(leaf(rb.bounds.to_aabb(), base, indices.len())),
        Decision::Split {
            mid,
            axis,
            left,
            right,
        } => {
            out.push(interior(rb.bounds.to_aabb(), axis as u16));
            let (l, r) = indices.split_at_mut(mid);
            build_seq(ctx, l, left, base, depth + 1, out);
            out[me].offset = out.len() as u32;
            build_seq(ctx, r, right, base + mid, depth + 1, out);
        }
    }
}

fn flatten(top: Top, out: &mut Vec<BvhNode>) {
    match top {
        Top::Interior {
            bounds,
            axis,
            children,
        } => {
            let me = out.len();
            out.push(interior(bounds, axis));
            let (l, r) = *children;
            flatten(l, out);
            out[me].offset = out.len() as u32;
            flatten(r, out);
        }
        Top::Chunk(v) => {
            let base = out.len() as u32;
            out.extend(v.into_iter().map(|mut n| {
                if !n.is_leaf() {
                    n.offset += base;
                }
                n
            }));
        }
    }
}

fn leaf(b: Aabb, first: usize, count: usize) -> BvhNode {
    debug_assert!(count > 0 && count <= u16::MAX as usize);
    BvhNode {
        min: b.min.into(),
        max: b.max.into(),
        offset: first as u32,
        count: count as u16,
        axis: 0,
    }
}

fn interior(b: Aabb, axis: u16) -> BvhNode {
    BvhNode {
        min: b.min.into(),
        max: b.max.into(),
        offset: 0,
        count: 0,
        axis,
    }
}

/// Bounds of the primitives and of their centroids, by a scan of the range.
fn range_bounds(indices: &[BuildPrim]) -> RangeBounds {
    let (bounds, centroids) = scan_bounds(indices);
    RangeBounds { bounds, centroids }
}

fn scan_bounds(indices: &[BuildPrim]) -> (Box4, Box4) {
    let scan = |idx: &[BuildPrim]| {
        idx.iter().fold((Box4::EMPTY, Box4::EMPTY), |(b, c), p| {
            (b.union(p.bounds), c.include(p.centroid()))
        })
    };
    if indices.len() > PARALLEL_SCAN {
        indices.par_chunks(PARALLEL_SCAN / 4).map(scan).reduce(
            || (Box4::EMPTY, Box4::EMPTY),
            |a, b| (a.0.union(b.0), a.1.union(b.1)),
        )
    } else {
        scan(indices)
    }
}

/// Chooses leaf or split for a range and, for a split, partitions it in place.
fn decide(ctx: &Ctx, idx: &mut [BuildPrim], rb: RangeBounds, depth: usize) -> Decision {
    let o = &ctx.opts;
    let cb = rb.centroids.to_aabb();
    let n = idx.len();
    if n == 1 {
        return Decision::Leaf;
    }
    let axis = cb.largest_axis();
    let extent = cb.extent()[axis];
    // `extent > 0` is false for NaN too: never recurse on something that cannot shrink.
    if extent.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        // All centroids coincide: no plane separates them. Keep a leaf while it is small, otherwise
        // halve the range in whatever order it is in, so recursion always ends.
        return if n <= o.max_leaf.clamp(1, 255) {
            Decision::Leaf
        } else {
            split_at(idx, n / 2, axis)
        };
    }
    let split = if depth >= FORCE_MEDIAN_DEPTH {
        BvhSplit::Median
    } else {
        o.split
    };
    match split {
        BvhSplit::Median => {
            if n <= o.leaf_size.clamp(1, 255) {
                return Decision::Leaf;
            }
            median(idx, axis)
        }
        BvhSplit::Midpoint => {
            if n <= o.leaf_size.clamp(1, 255) {
                return Decision::Leaf;
            }
            let mid_plane = 0.5 * (cb.min[axis] + cb.max[axis]);
            let (mid, _) = partition(idx, |p| p.centroid()[axis] < mid_plane);
            if mid == 0 || mid == n {
                median(idx, axis)
            } else {
                split_at(idx, mid, axis)
            }
        }
        BvhSplit::Sah => sah(ctx, idx, rb),
    }
}

fn median(idx: &mut [BuildPrim], axis: usize) -> Decision {
    let mid = idx.len() / 2;
    idx.select_nth_unstable_by(mid, |a, b| {
        a.centroid()[axis].total_cmp(&b.centroid()[axis])
    });
    split_at(idx, mid, axis)
}

/// A split of an already partitioned range, its children's bounds found by scanning them (the
/// fallbacks; the SAH split gets them for free).
fn split_at(idx: &[BuildPrim], mid: usize, axis: usize) -> Decision {
    let (l, r) = idx.split_at(mid);
    Decision::Split {
        mid,
        axis,
        left: range_bounds(l),
        right: range_bounds(r),
    }
}

/// Partitions `idx` so the elements satisfying `left` come first, swapping from both ends (Hoare),
/// which moves each misplaced record once; returns how many satisfy it and the centroid bounds of
/// both sides, gathered on the way.
fn partition(idx: &mut [BuildPrim], left: impl Fn(&BuildPrim) -> bool) -> (usize, [Box4; 2]) {
    let (mut i, mut j) = (0, idx.len());
    let (mut cl, mut cr) = (Box4::EMPTY, Box4::EMPTY);
    loop {
        while i < j && left(&idx[i]) {
            cl = cl.include(idx[i].centroid());
            i += 1;
        }
        while i < j && !left(&idx[j - 1]) {
            cr = cr.include(idx[j - 1].centroid());
            j -= 1;
        }
        if i == j {
            return (i, [cl, cr]);
        }
        // idx[i] belongs right and idx[j - 1] left.
        idx.swap(i, j - 1);
        cl = cl.include(idx[i].centroid());
        cr = cr.include(idx[j - 1].centroid());
        i += 1;
        j -= 1;
    }
}

/// [`partition`] for large ranges: chunks partitioned in parallel, then the right-hand runs lying
/// below the split swapped with the left-hand runs lying above it. Near the root a node's range is
/// most of the input, and when its split is lopsided (teapot-in-stadium: the stadium's few
/// triangles against the teapot's million) `rayon::join` gives the other thread almost nothing,
/// so a serial partition there ran on one core. The chunks are fixed, so the order, and the tree,
/// do not depend on the thread count.
fn partition_par(
    idx: &mut [BuildPrim],
    left: impl Fn(&BuildPrim) -> bool + Sync,
) -> (usize, [Box4; 2]) {
    let n = idx.len();
    if n <= PARALLEL_SCAN {
        return partition(idx, left);
    }
    let chunk = PARALLEL_SCAN / 4;
    let parts: Vec<(usize, [Box4; 2])> = idx
        .par_chunks_mut(chunk)
        .map(|c| partition(c, &left))
        .collect();
    let mid: usize = parts.iter().map(|p| p.0).sum();
    let (mut low, mut high) = (Vec::new(), Vec::new());
    let mut bounds = [Box4::EMPTY; 2];
    for (k, (count, b)) in parts.iter().enumerate() {
        let (start, end) = (k * chunk, ((k + 1) * chunk).min(n));
        let split = start + count;
        bounds = [bounds[0].union(b[0]), bounds[1].union(b[1])];
        // Right-hand elements below `mid`, left-hand ones at or above it: as many of each.
        if split < mid {
            low.push(split..end.min(mid));
        }
        if split > mid {
            high.push(start.max(mid)..split);
        }
    }
    for (i, j) in low.into_iter().flatten().zip(high.into_iter().flatten()) {
        idx.swap(i, j);
    }
    (mid, bounds)
}

/// Bins along the three axes, `B` at least the bin count in use (so small ranges set up and sweep
/// small arrays): the bounds of each bin, and apart from them its count, so that a bin's bounds
/// are 32 bytes (a shift to index) and the counts of all bins fit in a few cache lines.
#[derive(Clone, Copy)]
struct Bins<const B: usize> {
    bounds: [[Box4; B]; 3],
    counts: [[u32; B]; 3],
}

impl<const B: usize> Bins<B> {
    const EMPTY: Self = Self {
        bounds: [[Box4::EMPTY; B]; 3],
        counts: [[0; B]; 3],
    };

    /// Adds the primitives of `chunk`. The bin indices are below `B` already (the binner clamps
    /// them to the last bin in use); masking them with `B - 1` tells the compiler so, which
    /// removes a bounds check per axis and primitive.
    #[inline(always)]
    fn fill(&mut self, binner: &Binner, chunk: &[BuildPrim]) {
        const { assert!(B.is_power_of_two()) };
        for p in chunk {
            let b = p.bounds;
            let ks = binner.bins(p.centroid());
            for (a, &k) in ks.iter().enumerate() {
                let k = k & (B - 1);
                self.bounds[a][k] = self.bounds[a][k].union(b);
                self.counts[a][k] += 1;
            }
        }
    }

    fn merge(mut self, o: &Self, nb: usize) -> Self {
        for a in 0..3 {
            for k in 0..nb {
                self.bounds[a][k] = self.bounds[a][k].union(o.bounds[a][k]);
                self.counts[a][k] += o.counts[a][k];
            }
        }
        self
    }
}

/// Maps centroids to bins along all three axes at once.
#[derive(Clone, Copy)]
struct Binner {
    lo: Vec4,
    scale: Vec4,
    /// The last bin's index, as a float.
    top: Vec4,
}

impl Binner {
    /// The bins of a centroid on the three axes: the same formula for binning and partitioning, so
    /// the partition agrees exactly with the counts the cost was computed from. The clamp comes
    /// before the conversion, so the conversion is a plain truncation (`cvttps2dq`) rather than
    /// Rust's saturating float-to-integer cast, whose range and NaN checks would sit in the
    /// binning's innermost loop.
    #[inline(always)]
    fn bins(&self, c: Vec4) -> [usize; 3] {
        let f = ((c - self.lo) * self.scale).max(Vec4::ZERO).min(self.top);
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{__m128i, _mm_cvttps_epi32};
            // SAFETY: SSE2 is part of x86_64; __m128i and [i32; 4] have the same size, and every
            // bit pattern is an i32.
            let k: [i32; 4] = unsafe {
                let v: __m128i = _mm_cvttps_epi32(f.into());
                std::mem::transmute::<__m128i, [i32; 4]>(v)
            };
            [k[0] as usize, k[1] as usize, k[2] as usize]
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            [f.x as usize, f.y as usize, f.z as usize]
        }
    }

    /// The bin of coordinate `x` on axis `a`: lane `a` of [`Self::bins`], the very same operations.
    #[inline(always)]
    fn bin(&self, x: f32, a: usize) -> usize {
        self.bins(Vec4::splat(x))[a]
    }

    /// The plane that sends a centroid left exactly when its bin on axis `a` is at most `k`:
    /// `t` such that `bin(x, a) <= k` if and only if [`left_of`]`(x, t)` (NaN counts as bin 0, which
    /// `bins` gives it, and goes left). [`Self::bins`] is monotone in `x` (a subtraction, a
    /// multiplication by a non-negative scale, a clamp and a truncation, each non-decreasing), so
    /// such a plane exists: the smallest float whose bin exceeds `k`, found by searching the
    /// floats in their order, starting from where the plane should be. The partition then compares
    /// one coordinate instead of binning every centroid again.
    fn plane(&self, a: usize, k: usize) -> f32 {
        // Floats in their order as integers: -inf is the smallest key, +inf the largest.
        let key = |x: f32| {
            let b = x.to_bits();
            if b >> 31 == 1 {
                !b
            } else {
                b | 1 << 31
            }
        };
        let float = |u: u32| {
            if u >> 31 == 1 {
                f32::from_bits(u & !(1 << 31))
            } else {
                f32::from_bits(!u)
            }
        };
        let right = |u: u32| self.bin(float(u), a) > k;
        // `lo` has bin <= k, `hi` bin > k.
        let (mut lo, mut hi) = (key(f32::NEG_INFINITY), key(f32::INFINITY));
        if !right(hi) {
            return f32::NAN; // every centroid goes left
        }
        if right(lo) {
            return f32::NEG_INFINITY;
        }
        // Gallop from the estimate, usually within a few ulps of the plane, then bisect.
        let guess = self.lo[a] + (k + 1) as f32 / self.scale[a];
        if !guess.is_nan() {
            let g = key(guess).clamp(lo + 1, hi - 1);
            let mut step = 1u32;
            if right(g) {
                hi = g;
                while hi - lo > 1 {
                    let t = hi.saturating_sub(step).max(lo + 1);
                    if right(t) {
                        hi = t;
                    } else {
                        lo = t;
                        break;
                    }
                    step = step.saturating_mul(2);
                }
            } else {
                lo = g;
                while hi - lo > 1 {
                    let t = lo.saturating_add(step).min(hi - 1);
                    if right(t) {
                        hi = t;
                        break;
                    }
                    lo = t;
                    step = step.saturating_mul(2);
                }
            }
        }
        while hi - lo > 1 {
            let m = lo + (hi - lo) / 2;
            if right(m) {
                hi = m;
            } else {
                lo = m;
            }
        }
        float(hi)
    }
}

/// Whether coordinate `x` lies left of `plane` (see [`Binner::plane`]); NaN does, as it is in bin 0.
#[inline(always)]
#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x >= plane)` is meant: true for NaN
fn left_of(x: f32, plane: f32) -> bool {
    !(x >= plane)
}

fn sah(ctx: &Ctx, idx: &mut [BuildPrim], rb: RangeBounds) -> Decision {
    let o = &ctx.opts;
    let n = idx.len();
    // A range that may be a leaf and costs no more as one than a node's traversal alone is a leaf
    // whatever the planes: splitting it costs `traversal_cost + intersect_cost * (non-negative)`.
    // With the wide layouts (blocks of 4, `C_trav = 2`) that is every range of up to 8, most calls
    // here; binning them only to confirm it would be a large share of the build's work.
    if n <= o.max_leaf.clamp(1, 255)
        && o.intersect_cost >= 0.0
        && o.intersect_cost * BlockCount::new(o).of(n as u32) <= o.traversal_cost
    {
        return Decision::Leaf;
    }
    // A bin per primitive is as fine as binning can resolve; fewer bins for small ranges keep the
    // per-node setup and sweep, which would otherwise dominate near the leaves, proportional to the
    // range: clearing every bin at every node would cost more than the binning near the leaves.
    let nb = o.bins.clamp(2, MAX_BINS).min(n.max(2));
    match nb {
        0..=4 => sah_bins::<4>(ctx, idx, rb, nb),
        5..=8 => sah_bins::<8>(ctx, idx, rb, nb),
        9..=16 => sah_bins::<16>(ctx, idx, rb, nb),
        _ => sah_bins::<MAX_BINS>(ctx, idx, rb, nb),
    }
}

fn sah_bins<const B: usize>(
    ctx: &Ctx,
    idx: &mut [BuildPrim],
    rb: RangeBounds,
    nb: usize,
) -> Decision {
    let o = &ctx.opts;
    let n = idx.len();
    let (bounds, cb) = (rb.bounds, rb.centroids.to_aabb());
    let ext = cb.extent();
    // An axis whose centroids all coincide gets scale 0: everything in bin 0, never a candidate.
    let scale: [f32; 3] = std::array::from_fn(|a| {
        if ext[a] > 0.0 {
            nb as f32 / ext[a]
        } else {
            0.0
        }
    });
    let binner = Binner {
        lo: cb.min.extend(0.0),
        scale: Vec4::new(scale[0], scale[1], scale[2], 0.0),
        top: Vec4::splat((nb - 1) as f32),
    };
    // Filled where it lies: returning the filled bins from a block copied them (1.7 KB).
    let mut bins = Bins::<B>::EMPTY;
    if n > PARALLEL_SCAN {
        bins = idx
            .par_chunks(PARALLEL_SCAN / 4)
            .map(|c| {
                let mut b = Bins::<B>::EMPTY;
                b.fill(&binner, c);
                b
            })
            .reduce(|| Bins::<B>::EMPTY, |x, y| x.merge(&y, nb));
    } else {
        bins.fill(&binner, idx);
    }

    // The best plane minimises `n_l A_l + n_r A_r`; the cost proper (divided by the node's area) is
    // formed once, for the winner, and so are the winner's bounds (unions are exact, so gathering
    // them again gives the very boxes the sweep measured).
    let area = bounds.area();
    let blocks = BlockCount::new(o);
    let mut best: Option<(f32, usize, usize)> = None; // (weighted area, axis, last left bin)
    if area > 0.0 {
        #[allow(clippy::needless_range_loop)] // indexing compiled to 1.7% fewer instructions
        for a in 0..3 {
            if scale[a] == 0.0 {
                continue;
            }
            let (bb, bc) = (&bins.bounds[a], &bins.counts[a]);
            // Sweep from the right, then from the left (Wald 2007, section 4.2). The right-hand
            // boxes' areas are taken in the left sweep, only for planes with both sides occupied.
            let mut right_box = [Box4::EMPTY; B];
            let mut right_count = [0u32; B];
            let (mut acc, mut count) = (Box4::EMPTY, 0);
            for k in (1..nb).rev() {
                acc = acc.union(bb[k]);
                count += bc[k];
                right_box[k] = acc;
                right_count[k] = count;
            }
            let (mut left, mut count) = (Box4::EMPTY, 0);
            for k in 0..nb - 1 {
                left = left.union(bb[k]);
                count += bc[k];
                let rc = right_count[k + 1];
                // A plane after an empty bin splits exactly as the plane before it, which was
                // measured first and, being no worse, keeps its place: skipping it changes nothing
                // (a third of the planes of the nodes of 9 to 16, which have a bin each).
                if bc[k] == 0 || count == 0 || rc == 0 {
                    continue;
                }
                let weighted =
                    blocks.of(count) * left.area() + blocks.of(rc) * right_box[k + 1].area();
                if best.is_none_or(|b| weighted < b.0) {
                    best = Some((weighted, a, k));
                }
            }
        }
    }
    let max_leaf = o.max_leaf.clamp(1, 255);
    let leaf_cost = o.intersect_cost * blocks.of(n as u32);
    match best {
        Some((weighted, a, k))
            if !(n <= max_leaf
                && leaf_cost <= o.traversal_cost + o.intersect_cost * weighted / area) =>
        {
            let t = binner.plane(a, k);
            let (mid, [lc, rc]) = match a {
                0 => partition_par(idx, |p| left_of(p.centroid().x, t)),
                1 => partition_par(idx, |p| left_of(p.centroid().y, t)),
                _ => partition_par(idx, |p| left_of(p.centroid().z, t)),
            };
            if mid == 0 || mid == n {
                median(idx, a)
            } else {
                // The same unions in the same order as the sweep's.
                let bb = &bins.bounds[a];
                let lb = bb[..=k].iter().fold(Box4::EMPTY, |acc, &b| acc.union(b));
                let rbounds = bb[k + 1..nb]
                    .iter()
                    .rev()
                    .fold(Box4::EMPTY, |acc, &b| acc.union(b));
                Decision::Split {
                    mid,
                    axis: a,
                    left: RangeBounds {
                        bounds: lb,
                        centroids: lc,
                    },
                    right: RangeBounds {
                        bounds: rbounds,
                        centroids: rc,
                    },
                }
            }
        }
        _ if n <= max_leaf => Decision::Leaf,
        // No usable plane (a zero-area node): split by count instead.
        _ => median(idx, cb.largest_axis()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tiny xorshift generator, so the tests need no crate.
    struct Rng(u32);

    impl Rng {
        fn next(&mut self) -> u32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 17;
            self.0 ^= self.0 << 5;
            self.0
        }

        fn unit(&mut self) -> f32 {
            (self.next() >> 8) as f32 / (1u32 << 24) as f32
        }
    }

    /// The partition plane sends a coordinate left exactly when its bin is at most `k`: checked on
    /// both sides of every plane (the plane itself and the floats next to it), on random
    /// coordinates, and on NaN, infinities and both zeros, for binners of all scales and offsets.
    #[test]
    fn partition_plane_agrees_with_bins() {
        let mut rng = Rng(0x9e37_79b9);
        let next_up = |x: f32| {
            f32::from_bits(if x >= 0.0 {
                x.to_bits() + 1
            } else {
                x.to_bits() - 1
            })
        };
        let next_down = |x: f32| {
            f32::from_bits(if x > 0.0 {
                x.to_bits() - 1
            } else {
                x.to_bits() + 1
            })
        };
        for case in 0..300 {
            let nb = 2 + (rng.next() % 31) as usize;
            let mag = [1e-30f32, 1e-3, 1.0, 1e3, 1e6, 1e20][case % 6];
            let lo = Vec4::new(rng.unit() - 0.5, rng.unit() * 1e4, -rng.unit(), 0.0) * mag;
            let ext = Vec4::new(
                rng.unit() + 1e-6,
                rng.unit() * 1e-3 + 1e-9,
                rng.unit() * 5.0,
                1.0,
            ) * mag;
            let binner = Binner {
                lo,
                scale: (Vec4::splat(nb as f32) / ext).with_w(0.0),
                top: Vec4::splat((nb - 1) as f32),
            };
            for a in 0..3 {
                for k in 0..nb - 1 {
                    let t = binner.plane(a, k);
                    let left = |x: f32| left_of(x, t);
                    let mut xs = vec![
                        f32::NAN,
                        f32::INFINITY,
                        f32::NEG_INFINITY,
                        0.0,
                        -0.0,
                        f32::MAX,
                        f32::MIN,
                    ];
                    if t.is_finite() {
                        xs.extend([t, next_up(t), next_down(t), next_down(next_down(t))]);
                    }
                    for _ in 0..20 {
                        xs.push(lo[a] + (rng.unit() * 1.2 - 0.1) * ext[a]);
                    }
                    for x in xs {
                        assert_eq!(
                            binner.bin(x, a) <= k,
                            left(x),
                            "nb {nb} axis {a} k {k} x {x:e} plane {t:e} lo {} scale {}",
                            lo[a],
                            binner.scale[a]
                        );
                    }
                }
            }
        }
    }

    /// Ranges of at most `max_leaf` whose leaf cost is at most a traversal's become leaves
    /// without binning (`sah`); binning them (`sah_bins`) confirms it on random small ranges, for
    /// the blocks of four of the wide layouts (up to 8 primitives) and the binary layout's single
    /// primitives (up to 2).
    #[test]
    fn small_ranges_skipped_by_sah_are_leaves_when_binned() {
        let mut rng = Rng(12345);
        for (block, largest) in [(4, 8), (1, 2)] {
            let ctx = Ctx {
                opts: BvhOptions {
                    width: 2,
                    block,
                    ..BvhOptions::default()
                },
            };
            for case in 0..2000 {
                let n = 2 + case % (largest - 1);
                let mut prims: Vec<BuildPrim> = (0..n as u32)
                    .map(|i| {
                        // Some thin or flat boxes, some far apart: splitting them would look cheap.
                        let c = glam::Vec3::new(rng.unit(), rng.unit(), rng.unit()) * 100.0;
                        let s = glam::Vec3::new(rng.unit(), rng.unit() * 0.01, rng.unit())
                            * if i % 2 == 0 { 1e-3 } else { 1.0 };
                        BuildPrim::new(Aabb::new(c - s, c + s), i)
                    })
                    .collect();
                let rb = range_bounds(&prims);
                assert!(matches!(sah(&ctx, &mut prims, rb), Decision::Leaf));
                let nb = ctx.opts.bins.min(n);
                let binned = match nb {
                    0..=4 => sah_bins::<4>(&ctx, &mut prims, rb, nb),
                    _ => sah_bins::<8>(&ctx, &mut prims, rb, nb),
                };
                assert!(
                    matches!(binned, Decision::Leaf),
                    "block {block}, {n} primitives"
                );
            }
            // One more primitive than a traversal's worth is binned and may split.
            let ok = ctx.opts.intersect_cost * BlockCount::new(&ctx.opts).of(largest as u32 + 1)
                > ctx.opts.traversal_cost;
            assert!(ok);
        }
    }

    /// The parallel partition leaves every element satisfying the predicate before every other,
    /// moves nothing in or out, and returns the sides' centroid bounds; on lopsided and balanced
    /// splits of ranges several chunks long.
    #[test]
    fn parallel_partition_partitions() {
        let n = 3 * PARALLEL_SCAN + 12_345;
        let prims: Vec<BuildPrim> = (0..n as u32)
            .map(|i| {
                // A scrambled coordinate, so both sides are spread over every chunk.
                let x = (i.wrapping_mul(2_654_435_761) >> 8) as f32 / (1u32 << 24) as f32;
                let b = Aabb::new(
                    glam::Vec3::new(x, 0.0, 1.0),
                    glam::Vec3::new(x + 0.01, 1.0, 2.0),
                );
                BuildPrim::new(b, i)
            })
            .collect();
        for cut in [0.001f32, 0.3, 0.5, 0.97] {
            let mut v = prims.clone();
            let is_left = |p: &BuildPrim| p.centroid().x < cut;
            let (mid, [lb, rb]) = partition_par(&mut v, is_left);
            assert_eq!(mid, prims.iter().filter(|p| is_left(p)).count());
            assert!(v[..mid].iter().all(is_left) && !v[mid..].iter().any(is_left));
            let mut ids: Vec<u32> = v.iter().map(|p| p.id()).collect();
            ids.sort_unstable();
            assert!(ids.iter().enumerate().all(|(i, &id)| id == i as u32));
            let scan = |s: &[BuildPrim]| s.iter().fold(Box4::EMPTY, |b, p| b.include(p.centroid()));
            let same = |a: Box4, b: Box4| a.lo == b.lo && a.hi == b.hi;
            assert!(same(lb, scan(&v[..mid])) && same(rb, scan(&v[mid..])));
        }
    }
}
