//! Point-in-mesh by ray parity: a point is inside a closed surface if a ray from it crosses the surface
//! an odd number of times (the Jordan-Brouwer separation theorem). A single ray can be fooled where it
//! grazes an edge or a vertex tangentially (counting one crossing where the surface merely touches), so
//! three rays in unrelated directions vote and the majority wins.

use crate::accel::{Accel, AccelKind, MeshPrimitives, TraversalStats};
use crate::geometry::{PrimHit, TriangleMesh};
use crate::math::{offset_ray_origin, Aabb, Ray, Vec3};
use rayon::prelude::*;

/// Three directions far from the axes and from each other, so that no two rays of a vote are likely to
/// graze the same edge of an axis-aligned or regular mesh.
fn directions() -> [Vec3; 3] {
    [
        Vec3::new(1.0, 0.3711, 0.1579),
        Vec3::new(-0.2713, 1.0, 0.4317),
        Vec3::new(0.3119, -0.5531, 1.0),
    ]
    .map(Vec3::normalize)
}

/// Upper bound on crossings followed along one ray; a ray through a broken mesh cannot loop forever.
const MAX_CROSSINGS: usize = 1 << 16;

/// Answers inside/outside queries for one closed (watertight, manifold) mesh. Built once, queried many
/// times; the answer for a mesh with holes is the majority parity, which is well-defined but not
/// meaningful.
pub struct InsideTester<'a> {
    prims: MeshPrimitives<'a>,
    accel: Accel,
    bounds: Aabb,
}

impl<'a> InsideTester<'a> {
    pub fn new(mesh: &'a TriangleMesh) -> Self {
        let prims = MeshPrimitives::new(mesh);
        let accel = Accel::build(AccelKind::default(), &prims);
        Self {
            prims,
            accel,
            bounds: mesh.bounds(),
        }
    }

    /// Number of times the ray from `p` along `dir` crosses the surface. Each crossing is followed by a
    /// new ray from the hit point, offset past the surface by its error bound, so a ray through a
    /// shared edge counts the crossing once, not once per triangle.
    fn crossings(&self, p: Vec3, dir: Vec3) -> usize {
        let mut ray = Ray::new(p, dir);
        let mut stats = TraversalStats::default();
        for count in 0..MAX_CROSSINGS {
            let Some(hit) = self
                .accel
                .intersect(&self.prims, &ray, f32::INFINITY, &mut stats)
            else {
                return count;
            };
            let si = self.prims.mesh.interaction(
                hit.prim as usize,
                &PrimHit {
                    t: hit.t,
                    u: hit.u,
                    v: hit.v,
                    sub: hit.sub,
                },
            );
            ray.origin = offset_ray_origin(si.p, si.p_error, si.n, dir);
        }
        MAX_CROSSINGS
    }

    pub fn is_inside(&self, p: Vec3) -> bool {
        if !self.bounds.contains(p) || !p.is_finite() {
            return false;
        }
        let votes = directions()
            .into_iter()
            .filter(|&d| self.crossings(p, d) % 2 == 1)
            .count();
        votes >= 2
    }

    /// Answers for many points, in parallel.
    pub fn classify(&self, points: &[Vec3]) -> Vec<bool> {
        points.par_iter().map(|&p| self.is_inside(p)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_are_unit_length() {
        let d = directions();
        for (i, a) in d.iter().enumerate() {
            assert!((a.length() - 1.0).abs() < 1e-6);
            // Well apart from each other and from every axis.
            assert!(d[(i + 1) % 3].dot(*a).abs() < 0.5);
            assert!(a.abs().max_element() < 0.95);
        }
    }
}
