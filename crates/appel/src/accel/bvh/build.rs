//! Top-down BVH construction over primitive bounds and centroids.
//!
//! Binned SAH after Wald 2007 ("On fast construction of SAH-based bounding volume hierarchies"):
//! centroids are binned along all three axes in one pass and every bin boundary is a candidate plane.
//! Build memory is flat: one array of (bounds, centroid, id) records that the build partitions in
//! place - moving the records rather than indices into them keeps every pass sequential in memory -
//! so a leaf ends up a contiguous range of it. Large ranges are built in parallel
//! (`rayon::join`) into separate node arrays, each copied once into the final depth-first array.

use super::node::BvhNode;
use crate::math::{Aabb, Vec3};
use rayon::prelude::*;

/// How an interior node chooses its split.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BvhSplit {
    /// Binned surface area heuristic (Goldsmith & Salmon 1987, MacDonald & Booth 1990).
    #[default]
    Sah,
    /// Split the centroid bounds at the middle of their largest axis.
    Midpoint,
    /// Split into two halves of equal count along the largest centroid axis.
    Median,
}

/// Build parameters. The SAH cost of a node is `traversal_cost + intersect_cost * (n_l * A_l + n_r *
/// A_r) / A` against `intersect_cost * n` for making it a leaf.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhOptions {
    pub split: BvhSplit,
    /// SAH bins per axis, clamped to `2..=32`.
    pub bins: usize,
    /// The largest leaf SAH may keep (it splits larger sets whatever the cost); at most 255.
    pub max_leaf: usize,
    /// Midpoint and median splits stop at this many primitives.
    pub leaf_size: usize,
    pub traversal_cost: f32,
    pub intersect_cost: f32,
    /// Ranges larger than this build their two children in parallel.
    pub parallel_threshold: usize,
}

impl Default for BvhOptions {
    fn default() -> Self {
        Self {
            split: BvhSplit::Sah,
            bins: 16,
            max_leaf: 8,
            leaf_size: 4,
            // A node visit weighs twice a triangle test. Measured on a 327k-triangle mesh (see
            // docs/accel.md): 1:1 gave 1.7 triangles per leaf, 60% more memory and slower traversal;
            // 4:1 even fewer nodes but slower camera rays.
            traversal_cost: 2.0,
            intersect_cost: 1.0,
            parallel_threshold: 32 * 1024,
        }
    }
}

const MAX_BINS: usize = 32;
/// Beyond this depth every split is a median split, which halves the count: the tree is then at most
/// `FORCE_MEDIAN_DEPTH + 33` deep for up to 2^32 primitives, so traversal's fixed stack always suffices.
const FORCE_MEDIAN_DEPTH: usize = 64;
/// Ranges larger than this bin and bound their centroids in parallel chunks.
const PARALLEL_SCAN: usize = 128 * 1024;

pub(super) struct Ctx {
    pub opts: BvhOptions,
}

/// What the build knows of a primitive: 40 bytes.
#[derive(Clone, Copy, Debug)]
pub(super) struct BuildPrim {
    pub bounds: Aabb,
    pub centroid: Vec3,
    pub id: u32,
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

enum Decision {
    Leaf,
    /// The range was partitioned: `[..mid]` goes left.
    Split {
        mid: usize,
        axis: usize,
    },
}

/// Builds the flattened tree; `indices` (all primitives, in any order) is reordered so that each leaf
/// is a contiguous range of it.
pub(super) fn build(ctx: &Ctx, indices: &mut [BuildPrim]) -> Vec<BvhNode> {
    if indices.is_empty() {
        return Vec::new();
    }
    let top = build_top(ctx, indices, 0, 0);
    let mut out = Vec::new();
    flatten(top, &mut out);
    out
}

fn build_top(ctx: &Ctx, indices: &mut [BuildPrim], base: usize, depth: usize) -> Top {
    if indices.len() <= ctx.opts.parallel_threshold {
        let mut v = Vec::with_capacity(indices.len());
        build_seq(ctx, indices, base, depth, &mut v);
        return Top::Chunk(v);
    }
    let (bounds, cbounds) = range_bounds(indices);
    match decide(ctx, indices, bounds, cbounds, depth) {
        Decision::Leaf => Top::Chunk(vec![leaf(bounds, base, indices.len())]),
        Decision::Split { mid, axis } => {
            let (l, r) = indices.split_at_mut(mid);
            let children = rayon::join(
                || build_top(ctx, l, base, depth + 1),
                || build_top(ctx, r, base + mid, depth + 1),
            );
            Top::Interior {
                bounds,
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
    base: usize,
    depth: usize,
    out: &mut Vec<BvhNode>,
) {
    let (bounds, cbounds) = range_bounds(indices);
    let me = out.len();
    match decide(ctx, indices, bounds, cbounds, depth) {
        Decision::Leaf => out.push(leaf(bounds, base, indices.len())),
        Decision::Split { mid, axis } => {
            out.push(interior(bounds, axis as u16));
            let (l, r) = indices.split_at_mut(mid);
            build_seq(ctx, l, base, depth + 1, out);
            out[me].offset = out.len() as u32;
            build_seq(ctx, r, base + mid, depth + 1, out);
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

/// Bounds of the primitives and of their centroids.
fn range_bounds(indices: &[BuildPrim]) -> (Aabb, Aabb) {
    let scan = |idx: &[BuildPrim]| {
        idx.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), p| {
            (b.union(p.bounds), c.include(p.centroid))
        })
    };
    if indices.len() > PARALLEL_SCAN {
        indices.par_chunks(PARALLEL_SCAN / 4).map(scan).reduce(
            || (Aabb::EMPTY, Aabb::EMPTY),
            |a, b| (a.0.union(b.0), a.1.union(b.1)),
        )
    } else {
        scan(indices)
    }
}

/// Chooses leaf or split for a range and, for a split, partitions it in place.
fn decide(ctx: &Ctx, idx: &mut [BuildPrim], bounds: Aabb, cb: Aabb, depth: usize) -> Decision {
    let o = &ctx.opts;
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
            Decision::Split { mid: n / 2, axis }
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
            let mid = partition(idx, |p| p.centroid[axis] < mid_plane);
            if mid == 0 || mid == n {
                median(idx, axis)
            } else {
                Decision::Split { mid, axis }
            }
        }
        BvhSplit::Sah => sah(ctx, idx, bounds, cb),
    }
}

fn median(idx: &mut [BuildPrim], axis: usize) -> Decision {
    let mid = idx.len() / 2;
    idx.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
    Decision::Split { mid, axis }
}

/// Partitions `idx` so the elements satisfying `left` come first; returns how many do.
fn partition(idx: &mut [BuildPrim], left: impl Fn(&BuildPrim) -> bool) -> usize {
    let mut mid = 0;
    for j in 0..idx.len() {
        if left(&idx[j]) {
            idx.swap(mid, j);
            mid += 1;
        }
    }
    mid
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
}

type Bins = [[Bin; MAX_BINS]; 3];

/// The bin of a centroid coordinate: the same formula for binning and partitioning, so the partition
/// agrees exactly with the counts the cost was computed from.
#[inline]
fn bin_of(c: f32, lo: f32, scale: f32, nb: usize) -> usize {
    (((c - lo) * scale) as usize).min(nb - 1)
}

fn sah(ctx: &Ctx, idx: &mut [BuildPrim], bounds: Aabb, cb: Aabb) -> Decision {
    let o = &ctx.opts;
    let n = idx.len();
    let nb = o.bins.clamp(2, MAX_BINS);
    let ext = cb.extent();
    // An axis whose centroids all coincide gets scale 0: everything in bin 0, never a candidate.
    let scale: [f32; 3] = std::array::from_fn(|a| {
        if ext[a] > 0.0 {
            nb as f32 / ext[a]
        } else {
            0.0
        }
    });
    let lo = cb.min;
    let fill = |chunk: &[BuildPrim]| {
        let mut bins: Bins = [[Bin {
            bounds: Aabb::EMPTY,
            count: 0,
        }; MAX_BINS]; 3];
        for p in chunk {
            let (b, c) = (p.bounds, p.centroid);
            for a in 0..3 {
                let k = bin_of(c[a], lo[a], scale[a], nb);
                bins[a][k].bounds = bins[a][k].bounds.union(b);
                bins[a][k].count += 1;
            }
        }
        bins
    };
    let bins = if n > PARALLEL_SCAN {
        idx.par_chunks(PARALLEL_SCAN / 4).map(fill).reduce(
            || {
                [[Bin {
                    bounds: Aabb::EMPTY,
                    count: 0,
                }; MAX_BINS]; 3]
            },
            |mut x, y| {
                for a in 0..3 {
                    for k in 0..nb {
                        x[a][k].bounds = x[a][k].bounds.union(y[a][k].bounds);
                        x[a][k].count += y[a][k].count;
                    }
                }
                x
            },
        )
    } else {
        fill(idx)
    };

    let area = bounds.surface_area();
    let leaf_cost = o.intersect_cost * n as f32;
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, last bin on the left)
    if area > 0.0 {
        for a in 0..3 {
            if scale[a] == 0.0 {
                continue;
            }
            // Sweep from the right, then from the left (Wald 2007, section 4.2).
            let mut right_area = [0.0f32; MAX_BINS];
            let mut acc = Aabb::EMPTY;
            let mut cnt = 0u32;
            let mut right_count = [0u32; MAX_BINS];
            for k in (1..nb).rev() {
                acc = acc.union(bins[a][k].bounds);
                cnt += bins[a][k].count;
                right_area[k] = acc.surface_area();
                right_count[k] = cnt;
            }
            let mut acc = Aabb::EMPTY;
            let mut cnt = 0u32;
            for k in 0..nb - 1 {
                acc = acc.union(bins[a][k].bounds);
                cnt += bins[a][k].count;
                let (nl, nr) = (cnt, right_count[k + 1]);
                if nl == 0 || nr == 0 {
                    continue;
                }
                let cost = o.traversal_cost
                    + o.intersect_cost
                        * (nl as f32 * acc.surface_area() + nr as f32 * right_area[k + 1])
                        / area;
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, a, k));
                }
            }
        }
    }
    let max_leaf = o.max_leaf.clamp(1, 255);
    match best {
        Some((cost, a, k)) if !(n <= max_leaf && leaf_cost <= cost) => {
            let mid = partition(idx, |p| bin_of(p.centroid[a], lo[a], scale[a], nb) <= k);
            if mid == 0 || mid == n {
                median(idx, a)
            } else {
                Decision::Split { mid, axis: a }
            }
        }
        _ if n <= max_leaf => Decision::Leaf,
        // No usable plane (a zero-area node): split by count instead.
        _ => median(idx, cb.largest_axis()),
    }
}
