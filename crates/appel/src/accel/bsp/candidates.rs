//! The split planes a BSP node considers, and their cost. Two families:
//! - the 13 directions of a 26-DOP (Klosowski et al. 1998: the three axes, the six face diagonals
//!   and the four body diagonals), each with `bins` planes binned over the extent of the node's
//!   primitives along it and the two extremes, which cut the empty space beside the primitives
//!   off (binned counts, as a binned kd-tree build takes them: exact only at the bin edges);
//! - the supporting planes of `triangle_planes` of the node's triangles (Fuchs, Kedem & Naylor
//!   1980), their counts exact.
//! The cost is the surface area heuristic (MacDonald & Booth 1990) over the convex cells:
//! `C_trav + C_isect (A_below N_below + A_above N_above) / A`, the areas those of the polytopes
//! the plane cuts the node's cell into (`polytope.rs`).

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
            let o = self.opts;
            let cost = o.traversal_cost as f64
                + o.intersect_cost as f64 * (ab * nb as f64 + aa * na as f64) / area;
            if best.is_none_or(|b| cost < b.cost) {
                best = Some(Plane { n: normal, d, cost });
            }
        };
        let bins = self.opts.bins;
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
            if !(normal.length_squared() > 0.0) {
                continue;
            }
            let normal = (normal / normal.length()).as_vec3();
            let d = (normal.as_dvec3().dot(a)) as f32;
            offer(normal, d, self.count(ids, normal, d));
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
