//! The split planes a BSP node considers, and their cost. Two families:
//! - the 13 directions of a 26-DOP (Klosowski et al. 1998: the three axes, the six face diagonals
//!   and the four body diagonals), each with `bins` planes binned over the extent of the node's
//!   primitives along it and the two extremes, which cut the empty space beside the primitives
//!   off (binned counts, as a binned kd-tree build takes them: exact only at the bin edges);
//! - the supporting planes of `triangle_planes` of the node's triangles (Fuchs, Kedem & Naylor
//!   1980), their counts exact.
//!
//! The cost is the surface area heuristic (MacDonald & Booth 1990) over the convex cells:
//! `C_trav + sum over the non-empty sides (A_side / A) (C_visit + C_isect N_side)`, the areas
//! those of the polytopes the plane cuts the node's cell into (`polytope.rs`), against a leaf's
//! `C_visit + C_isect N`.

use super::polytope::Polytope;
use super::shape::Shape;
use super::BspOptions;
use crate::math::Vec3;

/// The 26-DOP's directions (unnormalised).
const DIRECTIONS: [[f32; 3]; 13] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, 1.0, -1.0],
    [1.0, 1.0, 1.0],
    [1.0, 1.0, -1.0],
    [1.0, -1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// The least fraction of the cell's area a plane with an empty side must cut away.
const EMPTY_MIN: f64 = 0.25;

/// The most planes per direction a node of many primitives takes.
pub(super) const MAX_BINS: usize = 64;

/// A plane `n . x = d` and its cost.
#[derive(Clone, Copy, Debug)]
pub(super) struct Plane {
    pub(super) n: Vec3,
    pub(super) d: f32,
    pub(super) cost: f64,
}

pub(super) struct Chooser<'a> {
    pub(super) shapes: &'a [Shape],
    pub(super) opts: BspOptions,
    pub(super) margin: f64,
}

impl Chooser<'_> {
    /// The cheapest candidate plane for the node `cell` listing `ids`, if any cuts the cell.
    pub(super) fn best(&self, cell: &Polytope, ids: &[u32]) -> Option<Plane> {
        let area = cell.area();
        if area.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let n = ids.len();
        let mut best: Option<Plane> = None;
        let mut offer = |normal: Vec3, d: f32, (nb, na): (usize, usize)| {
            if nb == n && na == n {
                return;
            }
            let (ab, aa) = cell.split_areas(normal.as_dvec3(), d as f64);
            // A plane with an empty side must cut a quarter of the cell away: any sliver of
            // empty space lowers the cost a little, and without this rule the build carved every
            // leaf into a 26-DOP around its triangles, one plane at a time, down to the depth
            // limit (811,463 nodes for 83,008 triangles on the teapot in the stadium).
            let empty = if nb == 0 {
                ab
            } else if na == 0 {
                aa
            } else {
                area
            };
            if empty < EMPTY_MIN * area {
                return;
            }
            let o = self.opts;
            let child = |a: f64, k: usize| {
                if k == 0 {
                    0.0
                } else {
                    a / area * (o.visit_cost as f64 + o.intersect_cost as f64 * k as f64)
                }
            };
            let cost = o.traversal_cost as f64 + child(ab, nb) + child(aa, na);
            if best.is_none_or(|b| cost < b.cost) {
                best = Some(Plane { n: normal, d, cost });
            }
        };
        // Large nodes take more bins: with 8, a small dense mesh in a large scene (the teapot in
        // the stadium) falls into one bin and takes a dozen levels to isolate, each copying
        // the large triangles around it.
        let bins = if self.opts.bins == 0 {
            0
        } else {
            (n / 64).clamp(self.opts.bins, MAX_BINS)
        };
        if bins > 0 {
            let mut ext = Vec::with_capacity(n);
            let mut starts = vec![0usize; bins];
            let mut ends = vec![0usize; bins];
            for dir in DIRECTIONS {
                let dir = Vec3::from(dir).normalize();
                ext.clear();
                ext.extend(ids.iter().map(|&i| self.shapes[i as usize].extent(dir)));
                let (g0, g1) = ext
                    .iter()
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), e| {
                        (l.min(e.0), h.max(e.1))
                    });
                if g1.partial_cmp(&g0) != Some(std::cmp::Ordering::Greater) {
                    continue;
                }
                let inv_w = bins as f32 / (g1 - g0);
                let bin = |x: f32| (((x - g0) * inv_w).max(0.0) as usize).min(bins - 1);
                starts.fill(0);
                ends.fill(0);
                for &(lo, hi) in &ext {
                    starts[bin(lo)] += 1;
                    ends[bin(hi)] += 1;
                }
                // Plane k between bins k - 1 and k: primitives starting below it are below,
                // those ending at or above it above. The extremes are moved off the primitives
                // by twice the margin, so that the side beyond them is empty.
                let shift = 2.0 * self.margin as f32;
                let (mut nb, mut na) = (0, n);
                for k in 0..=bins {
                    if k > 0 {
                        nb += starts[k - 1];
                        na -= ends[k - 1];
                    }
                    let x = match k {
                        0 => g0 - shift,
                        k if k == bins => g1 + shift,
                        k => g0 + k as f32 * (g1 - g0) / bins as f32,
                    };
                    offer(dir, x, (nb, na));
                }
            }
        }
        let k = self.opts.triangle_planes.min(n);
        for j in 0..k {
            let i = ids[(2 * j + 1) * n / (2 * k)];
            let Shape::Triangle(t) = self.shapes[i as usize] else {
                continue;
            };
            let [a, b, c] = t.map(|p| p.as_dvec3());
            let normal = (b - a).cross(c - a);
            if normal.length_squared().partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            let normal = (normal / normal.length()).as_vec3();
            // Moved off the triangle by twice the margin, to either side: on the plane itself,
            // the triangle and every neighbour sharing a vertex with it would lie within the
            // margin of it and go to both sides (on a closed mesh, about a dozen copies per
            // plane: 443,003 references for 20,480 triangles in the teapot in the stadium).
            let d = normal.as_dvec3().dot(a);
            for shift in [-2.0 * self.margin, 2.0 * self.margin] {
                let d = (d + shift) as f32;
                offer(normal, d, self.count(ids, normal, d));
            }
        }
        best
    }

    /// How many of `ids` go below and above the plane (those within the margin of it to both).
    pub(super) fn count(&self, ids: &[u32], n: Vec3, d: f32) -> (usize, usize) {
        ids.iter().fold((0, 0), |(b, a), &i| {
            let (lb, la) = self.shapes[i as usize].sides(n, d, self.margin);
            (b + lb as usize, a + la as usize)
        })
    }
}

/// Whether `n` is one of the coordinate axes (the plane a kd-tree could have taken).
pub(super) fn is_axis(n: Vec3) -> bool {
    n.abs().max_element() == 1.0 && n.abs().min_element() == 0.0 && {
        let a = n.abs();
        a.x + a.y + a.z == 1.0
    }
}
