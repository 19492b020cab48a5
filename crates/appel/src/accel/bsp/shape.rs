//! What the BSP builder knows of a primitive: its three vertices if it is a triangle
//! ([`Primitives::watertight_triangle`]), otherwise its bounding box; and on which sides of a
//! plane it lies. The distance to a plane is linear, so over a triangle it is extreme at a vertex,
//! and over a box at a corner: a primitive is on a side exactly when one of these points is.

use crate::accel::Primitives;
use crate::math::{Aabb, Vec3};
use glam::DVec3;
use rayon::prelude::*;

#[derive(Clone, Copy, Debug)]
pub(super) enum Shape {
    Triangle([Vec3; 3]),
    Box(Aabb),
}

pub(super) fn shapes<P: Primitives>(prims: &P) -> Vec<Shape> {
    (0..prims.count())
        .into_par_iter()
        .map(|i| match prims.watertight_triangle(i) {
            Some(t) => Shape::Triangle(t),
            None => Shape::Box(prims.bounds(i)),
        })
        .collect()
}

impl Shape {
    pub(super) fn bounds(&self) -> Aabb {
        match self {
            Shape::Triangle(t) => Aabb::from_points(t.iter().copied()),
            Shape::Box(b) => *b,
        }
    }

    /// The extent of `n . x` over the primitive, in f32 (for binning).
    #[inline]
    pub(super) fn extent(&self, n: Vec3) -> (f32, f32) {
        match self {
            Shape::Triangle(t) => {
                let (a, b, c) = (n.dot(t[0]), n.dot(t[1]), n.dot(t[2]));
                (a.min(b).min(c), a.max(b).max(c))
            }
            Shape::Box(b) => {
                let lo = Vec3::select(n.cmpge(Vec3::ZERO), b.min, b.max);
                let hi = Vec3::select(n.cmpge(Vec3::ZERO), b.max, b.min);
                (n.dot(lo), n.dot(hi))
            }
        }
    }

    /// Whether the primitive reaches the side `n . x <= d + margin` and the side
    /// `n . x >= d - margin` of the plane (`n`, `d` as stored, evaluated in f64).
    #[inline]
    pub(super) fn sides(&self, n: Vec3, d: f32, margin: f64) -> (bool, bool) {
        let n64 = n.as_dvec3();
        let dist = |p: Vec3| n64.dot(p.as_dvec3()) - d as f64;
        let (lo, hi) = match self {
            Shape::Triangle(t) => {
                let (a, b, c) = (dist(t[0]), dist(t[1]), dist(t[2]));
                (a.min(b).min(c), a.max(b).max(c))
            }
            Shape::Box(b) => {
                let lo = DVec3::select(n64.cmpge(DVec3::ZERO), b.min.as_dvec3(), b.max.as_dvec3());
                let hi = DVec3::select(n64.cmpge(DVec3::ZERO), b.max.as_dvec3(), b.min.as_dvec3());
                (n64.dot(lo) - d as f64, n64.dot(hi) - d as f64)
            }
        };
        (lo <= margin, hi >= -margin)
    }
}
