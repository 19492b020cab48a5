use super::{triangle::TriangleTest, PrimHit, SurfaceInteraction};
use crate::math::{gamma, Aabb, Ray, Vec2, Vec3};

/// An indexed triangle mesh, stored flat: f32 positions, u32 index triples, and optional per-vertex
/// normals and texture coordinates.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
}

impl TriangleMesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Bytes of its arrays (their lengths, not capacities).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(self.positions.as_slice())
            + size_of_val(self.indices.as_slice())
            + self.normals.as_deref().map_or(0, size_of_val)
            + self.uvs.as_deref().map_or(0, size_of_val)
    }

    #[inline]
    pub fn vertices(&self, tri: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[tri];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    pub fn triangle_bounds(&self, tri: usize) -> Aabb {
        Aabb::from_points(self.vertices(tri))
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().copied())
    }

    #[inline]
    pub fn intersect(
        &self,
        tri: usize,
        ray: &Ray,
        t_max: f32,
        test: TriangleTest,
    ) -> Option<PrimHit> {
        let [p0, p1, p2] = self.vertices(tri);
        test.intersect(ray, t_max, p0, p1, p2)
    }

    /// The unit geometric normal at barycentrics `(u, v)` of triangle `tri`, turned as
    /// [`Self::interaction`] turns it (toward the vertex normals where the mesh has them): its
    /// `n` without the rest of the interaction, for queries that report nothing else.
    #[inline]
    pub fn geometric_normal(&self, tri: usize, u: f32, v: f32) -> Vec3 {
        self.normals_at(self.vertices(tri), tri, 1.0 - u - v, u, v)
            .0
    }

    /// The geometric normal and the shading normal (the geometric one without vertex normals).
    #[inline(always)]
    fn normals_at(
        &self,
        [p0, p1, p2]: [Vec3; 3],
        tri: usize,
        b0: f32,
        b1: f32,
        b2: f32,
    ) -> (Vec3, Vec3) {
        let cross = (p1 - p0).cross(p2 - p0);
        let mut n = if cross.length_squared() > 0.0 {
            cross.normalize()
        } else {
            // Only reachable for a triangle too small for f32 to express its normal; any unit vector
            // keeps shading finite.
            Vec3::Z
        };
        let [i0, i1, i2] = self.indices[tri].map(|i| i as usize);
        let ns = match &self.normals {
            Some(ns) => {
                let s = b0 * ns[i0] + b1 * ns[i1] + b2 * ns[i2];
                if s.length_squared() > 0.0 && s.is_finite() {
                    // Vertex normals say where the outside is more reliably than a file's winding.
                    let s = s.normalize();
                    if s.dot(n) < 0.0 {
                        n = -n;
                    }
                    s
                } else {
                    n
                }
            }
            None => n,
        };
        (n, ns)
    }

    /// The hit point is recomputed from the barycentrics, whose error bound (pbrt-v4 eq. 6.30) does not
    /// grow with the length of the ray.
    pub fn interaction(&self, tri: usize, hit: &PrimHit) -> SurfaceInteraction {
        let [p0, p1, p2] = self.vertices(tri);
        let (b1, b2) = (hit.u, hit.v);
        let b0 = 1.0 - b1 - b2;
        let p = b0 * p0 + b1 * p1 + b2 * p2;
        let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());
        let (n, ns) = self.normals_at([p0, p1, p2], tri, b0, b1, b2);
        let [i0, i1, i2] = self.indices[tri].map(|i| i as usize);
        // Without texture coordinates, (u, v) are the barycentrics (b1, b2): vertex uvs (0,0),
        // (1,0), (0,1), which give dp/du = p1 - p0 below, as Mitsuba 3's meshes do.
        let uvs = match &self.uvs {
            Some(uv) => [uv[i0], uv[i1], uv[i2]],
            None => [Vec2::ZERO, Vec2::X, Vec2::Y],
        };
        let uv = b0 * uvs[0] + b1 * uvs[1] + b2 * uvs[2];
        let (dpdu, dpdv) = dpduv([p0, p1, p2], uvs);
        SurfaceInteraction {
            p,
            p_error,
            n,
            ns,
            uv,
            dpdu,
            dpdv,
            tangent: None,
        }
    }
}

/// dp/du and dp/dv of a triangle from its vertices and texture coordinates: the solution of
/// `[dp02 dp12] = [dpdu dpdv] [duv02 duv12]` (pbrt-v4 section 6.5.3). Zero when the texture
/// coordinates are degenerate.
fn dpduv(p: [Vec3; 3], uv: [Vec2; 3]) -> (Vec3, Vec3) {
    let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
    let (dp02, dp12) = (p[0] - p[2], p[1] - p[2]);
    let det = duv02.x * duv12.y - duv02.y * duv12.x;
    let dpdu = (duv12.y * dp02 - duv02.y * dp12) / det;
    let dpdv = (duv02.x * dp12 - duv12.x * dp02) / det;
    if det != 0.0 && dpdu.is_finite() && dpdv.is_finite() {
        (dpdu, dpdv)
    } else {
        (Vec3::ZERO, Vec3::ZERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dpdu_follows_the_texture_u_axis() {
        let p = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 3.0, 0.0),
        ];
        let uv = [Vec2::ZERO, Vec2::X, Vec2::Y];
        assert_eq!(
            dpduv(p, uv),
            (Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0))
        );
        // u running along the second edge, at half the rate.
        let uv = [Vec2::ZERO, Vec2::Y, Vec2::new(0.5, 0.0)];
        assert_eq!(dpduv(p, uv).0, Vec3::new(0.0, 6.0, 0.0));
        // Degenerate texture coordinates: no direction.
        assert_eq!(dpduv(p, [Vec2::ONE; 3]), (Vec3::ZERO, Vec3::ZERO));
    }
}
