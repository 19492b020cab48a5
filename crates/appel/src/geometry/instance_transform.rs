//! Where one instance of a mesh sits: the affine map from the mesh's object space to the world and
//! back, with the rounding-error bounds that keep secondary rays off the surface they leave.
//!
//! Unlike [`super::ObjectTransform`] (one per implicit surface, a few per scene) this is stored once
//! per instance, possibly millions of times, so it keeps only the two affine maps (128 bytes) and
//! derives the normal matrix when a hit needs it.

use super::SurfaceInteraction;
use crate::math::{gamma, Aabb, Ray};
use glam::{Affine3A, Mat3, Mat4, Vec3, Vec3A};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceTransform {
    pub to_world: Affine3A,
    pub to_object: Affine3A,
}

/// `|M|`: the element-wise absolute value, which bounds how a transform grows rounding errors.
fn abs3(m: Mat3) -> Mat3 {
    Mat3::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs())
}

impl InstanceTransform {
    /// `None` when `to_world` is not an invertible, finite affine map (a zero scale, a NaN, or a
    /// projective last row).
    pub fn new(to_world: Mat4) -> Option<Self> {
        let affine_row = to_world.row(3) == glam::Vec4::W;
        let det = to_world.determinant();
        if !affine_row || !det.is_finite() || det == 0.0 || !to_world.is_finite() {
            return None;
        }
        let to_world = Affine3A::from_mat4(to_world);
        let to_object = to_world.inverse();
        to_object.is_finite().then_some(Self {
            to_world,
            to_object,
        })
    }

    /// The ray in object space. The direction is not renormalized, so a hit's `t` is the same in
    /// both spaces and hits in different instances compare directly.
    #[inline]
    pub fn ray_to_object(&self, r: &Ray) -> Ray {
        Ray::new(
            self.to_object.transform_point3(r.origin),
            self.to_object.transform_vector3(r.dir),
        )
    }

    /// World bounds of an object-space box: the box of its eight transformed corners, grown by the
    /// rounding of that transform (pbrt-v4 section 6.8.6, `gamma(3) (|M| |p| + |t|)`), so that no
    /// ray reaching the mesh in object space is culled by the box in world space.
    pub fn bounds_to_world(&self, b: Aabb) -> Aabb {
        if b.is_empty() {
            return b;
        }
        let abs_linear = abs3(Mat3::from(self.to_world.matrix3));
        let t = Vec3::from(self.to_world.translation).abs();
        let mut out = Aabb::EMPTY;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { b.min.x } else { b.max.x },
                if i & 2 == 0 { b.min.y } else { b.max.y },
                if i & 4 == 0 { b.min.z } else { b.max.z },
            );
            let p = self.to_world.transform_point3(c);
            let err = gamma(3) * (abs_linear * c.abs() + t);
            out = out.include(p - err).include(p + err);
        }
        out
    }

    /// A unit normal in object space as a unit normal in world space.
    #[inline]
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        // Normals transform by the inverse transpose of the linear part.
        (Mat3::from(self.to_object.matrix3).transpose() * n).normalize_or(n)
    }

    /// The interaction in world space. The point's error bound has three parts (pbrt-v4 6.8.6):
    /// the object-space bound carried through the linear part; the rounding of `to_world` itself;
    /// and, because a ray leaving this point re-enters object space through `to_object` (for the
    /// shadow ray and for the next bounce in this same instance), that transform's rounding of the
    /// new origin, carried back to world space. Offsetting by the sum keeps the origin on the right
    /// side of the surface in object space too, where the triangle test runs.
    pub fn interaction_to_world(&self, si: &SurfaceInteraction) -> SurfaceInteraction {
        let linear = Mat3::from(self.to_world.matrix3);
        let abs_linear = abs3(linear);
        let abs_inverse = abs3(Mat3::from(self.to_object.matrix3));
        let t = Vec3::from(self.to_world.translation).abs();
        let t_inv = Vec3::from(self.to_object.translation).abs();
        let p = self.to_world.transform_point3(si.p);
        let forward =
            (1.0 + gamma(3)) * (abs_linear * si.p_error) + gamma(3) * (abs_linear * si.p.abs() + t);
        // The origin the next ray starts from lies within `forward` of `p` (plus the offset, which
        // is of the same size): bound its coordinates by twice that, conservatively.
        let origin = p.abs() + 2.0 * forward;
        let back = (1.0 + gamma(3)) * (abs_linear * (gamma(3) * (abs_inverse * origin + t_inv)));
        let normal = |n: Vec3| self.normal_to_world(n);
        SurfaceInteraction {
            p,
            p_error: forward + back,
            n: normal(si.n),
            ns: normal(si.ns),
            uv: si.uv,
            dpdu: linear * si.dpdu,
            dpdv: linear * si.dpdv,
            tangent: si.tangent.map(|t| super::FileTangent {
                dir: linear * t.dir,
                // A mirroring transform turns the bitangent the other way round relative to
                // n x s (cross(Ma, Mb) = det(M) M^-T (a x b)).
                sign: if linear.determinant() < 0.0 {
                    -t.sign
                } else {
                    t.sign
                },
            }),
        }
    }

    /// The world position of an object-space point (for tools that flatten instances).
    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        Vec3::from(self.to_world.transform_point3a(Vec3A::from(p)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    fn placed() -> (Mat4, InstanceTransform) {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 1.0, 0.5),
            Quat::from_axis_angle(Vec3::new(1.0, 1.0, 0.0).normalize(), 0.7),
            Vec3::new(3.0, -1.0, 2.0),
        );
        (m, InstanceTransform::new(m).unwrap())
    }

    #[test]
    fn rays_round_trip_and_t_is_preserved() {
        let (_, x) = placed();
        let r = Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.3, -0.2, 0.9));
        let o = x.ray_to_object(&r);
        let t = 1.7;
        assert!((x.point_to_world(o.at(t)) - r.at(t)).length() < 1e-5);
    }

    #[test]
    fn world_bounds_contain_every_transformed_corner_and_a_bit_more() {
        let (m, x) = placed();
        let b = x.bounds_to_world(Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)));
        for c in [Vec3::new(1.0, -1.0, 1.0), Vec3::new(-1.0, 1.0, -1.0)] {
            let p = m.transform_point3(c);
            assert!(b.contains(p));
            // Strictly inside: the box was grown by the rounding bound.
            assert!((p - b.min).min_element() > 0.0 && (b.max - p).min_element() > 0.0);
        }
        assert!(x.bounds_to_world(Aabb::EMPTY).is_empty());
    }

    #[test]
    fn singular_projective_and_non_finite_maps_are_refused() {
        assert!(InstanceTransform::new(Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
        assert!(InstanceTransform::new(Mat4::from_scale(Vec3::splat(f32::NAN))).is_none());
        let mut projective = Mat4::IDENTITY;
        projective.x_axis.w = 0.5;
        assert!(InstanceTransform::new(projective).is_none());
        assert!(InstanceTransform::new(Mat4::IDENTITY).is_some());
    }

    #[test]
    fn normals_stay_perpendicular_and_the_error_bound_covers_the_round_trip() {
        let x = InstanceTransform::new(Mat4::from_scale_rotation_translation(
            Vec3::new(4.0, 1.0, 1.0),
            Quat::from_rotation_z(0.3),
            Vec3::new(1e4, -3e3, 7.0),
        ))
        .unwrap();
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        let si = SurfaceInteraction {
            p: Vec3::new(0.25, -0.25, 0.5),
            p_error: Vec3::ZERO,
            n,
            ns: n,
            uv: glam::Vec2::ZERO,
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            tangent: None,
        };
        let w = x.interaction_to_world(&si);
        let tangent = x.to_world.transform_vector3(Vec3::new(1.0, -1.0, 0.0));
        assert!(w.n.dot(tangent).abs() < 1e-5 * tangent.length());
        assert!((w.n.length() - 1.0).abs() < 1e-6);
        // The world point, taken back to object space, lies within the bound mapped back.
        let back = x.to_object.transform_point3(w.p);
        let bound = abs3(Mat3::from(x.to_object.matrix3)) * w.p_error;
        assert!(((back - si.p).abs() - bound).max_element() <= 0.0);
        assert!(w.p_error.min_element() > 0.0);
    }
}
