//! Point-in-mesh by ray parity: a point is inside a closed surface if a ray from it crosses the surface
//! an odd number of times (the Jordan-Brouwer separation theorem). A single ray can be fooled where it
//! grazes an edge or a vertex tangentially (counting one crossing where the surface merely touches), so
//! three rays in unrelated directions vote and the majority wins. Where the vote cannot be trusted
//! (the rays disagree, or one meets the surface so near its start that the crossing may lie within
//! the hit's rounding error, as for a point a millionth inside a vertex) the generalized winding
//! number decides instead (`winding.rs`).

use super::closest::ClosestPoint;
use super::winding::winding_number;
use crate::accel::{Accel, AccelKind, MeshPrimitives, TraversalStats};
use crate::geometry::{PrimHit, TriangleMesh};
use crate::math::{offset_ray_origin, Aabb, Ray, Vec3};
use rayon::prelude::*;
use std::borrow::Cow;

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
    mesh: Cow<'a, TriangleMesh>,
    accel: Accel,
    closest: ClosestPoint,
    bounds: Aabb,
    /// A point nearer than this to the surface goes to the winding number.
    near: f32,
}

/// A point nearer the surface than this fraction of the mesh's size (plus of the point's distance
/// from the origin, which sets its own rounding) may see its rays' crossings lost in their
/// rounding (the triangle test rejects hits within its error bound of the origin, so a ray from
/// a millionth inside a vertex crosses nothing). The margin is generous by orders of magnitude
/// over the float error: the winding number it hands such points to is right everywhere, only
/// slower.
const NEAR_FRACTION: f32 = 1e-4;

impl<'a> InsideTester<'a> {
    pub fn new(mesh: &'a TriangleMesh) -> Self {
        Self::with_mesh(Cow::Borrowed(mesh))
    }

    /// A tester that keeps the mesh.
    pub fn owning(mesh: TriangleMesh) -> InsideTester<'static> {
        InsideTester::with_mesh(Cow::Owned(mesh))
    }

    fn with_mesh(mesh: Cow<'a, TriangleMesh>) -> Self {
        let accel = Accel::build(AccelKind::default(), &MeshPrimitives::new(&mesh));
        let closest = ClosestPoint::new(&mesh);
        let bounds = mesh.bounds();
        let near = NEAR_FRACTION * (bounds.max - bounds.min).length();
        Self {
            mesh,
            accel,
            closest,
            bounds,
            near,
        }
    }

    pub fn mesh(&self) -> &TriangleMesh {
        &self.mesh
    }

    /// The nearest point of the mesh to `p`.
    pub fn closest(&self, p: glam::DVec3) -> Option<super::Closest> {
        self.closest.closest(&self.mesh, p)
    }

    /// Number of times the ray from `p` along `dir` crosses the surface. Each crossing is followed by a
    /// new ray from the hit point, offset past the surface by its error bound, so a ray through a
    /// shared edge counts the crossing once, not once per triangle.
    fn crossings(&self, p: Vec3, dir: Vec3) -> usize {
        let prims = MeshPrimitives::new(&self.mesh);
        let mut ray = Ray::new(p, dir);
        let mut stats = TraversalStats::default();
        for count in 0..MAX_CROSSINGS {
            let Some(hit) = self
                .accel
                .intersect(&prims, &ray, f32::INFINITY, &mut stats)
            else {
                return count;
            };
            let si = self.mesh.interaction(
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
        let near = (self.near + NEAR_FRACTION * p.abs().max_element()) as f64;
        let far = self
            .closest
            .closest(&self.mesh, p.as_dvec3())
            .is_some_and(|c| c.distance > near);
        if far {
            let votes: usize = directions()
                .into_iter()
                .map(|d| self.crossings(p, d) % 2)
                .sum();
            // A split vote means some ray grazed an edge or a vertex: the winding number settles it.
            if votes == 0 || votes == 3 {
                return votes == 3;
            }
        }
        winding_number(&self.mesh, p.as_dvec3()) > 0.5
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
