//! Placing a surface defined in its own object space into the world: rays go into object space, hits
//! come back out, with the rounding error of the transform added to the hit point's error bound.

use super::SurfaceInteraction;
use crate::math::{gamma, Aabb, Ray};
use glam::{Mat3, Mat4, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectTransform {
    pub to_world: Mat4,
    pub to_object: Mat4,
    /// Inverse transpose of the linear part: how normals transform.
    normal_to_world: Mat3,
}

impl ObjectTransform {
    /// `None` when `to_world` is not invertible or not finite.
    pub fn new(to_world: Mat4) -> Option<Self> {
        let det = to_world.determinant();
        if !det.is_finite() || det == 0.0 {
            return None;
        }
        let to_object = to_world.inverse();
        to_object.is_finite().then(|| Self {
            to_world,
            to_object,
            normal_to_world: Mat3::from_mat4(to_object).transpose(),
        })
    }

    /// The ray in object space. The direction is not renormalized, so a hit's `t` is the same in both
    /// spaces and hits of transformed and untransformed surfaces compare directly.
    #[inline]
    pub fn ray_to_object(&self, r: &Ray) -> Ray {
        Ray::new(
            self.to_object.transform_point3(r.origin),
            self.to_object.transform_vector3(r.dir),
        )
    }

    /// World bounds of an object-space box: the box of its eight transformed corners.
    pub fn bounds_to_world(&self, b: Aabb) -> Aabb {
        Aabb::from_points((0..8).map(|i| {
            let corner = Vec3::new(
                if i & 1 == 0 { b.min.x } else { b.max.x },
                if i & 2 == 0 { b.min.y } else { b.max.y },
                if i & 4 == 0 { b.min.z } else { b.max.z },
            );
            self.to_world.transform_point3(corner)
        }))
    }

    /// The interaction in world space. The point's error bound is the object-space bound carried
    /// through the linear part, plus the rounding of the transform itself (pbrt-v4 section 6.8.6:
    /// `gamma(3) (|M| |p| + |t|)`).
    pub fn interaction_to_world(&self, si: &SurfaceInteraction) -> SurfaceInteraction {
        let linear = Mat3::from_mat4(self.to_world);
        let abs_linear = Mat3::from_cols(
            linear.x_axis.abs(),
            linear.y_axis.abs(),
            linear.z_axis.abs(),
        );
        let translation = self.to_world.w_axis.truncate();
        let p = self.to_world.transform_point3(si.p);
        let p_error = (1.0 + gamma(3)) * (abs_linear * si.p_error)
            + gamma(3) * (abs_linear * si.p.abs() + translation.abs());
        let normal = |n: Vec3| (self.normal_to_world * n).normalize_or(n);
        SurfaceInteraction {
            p,
            p_error,
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn rays_and_bounds_round_trip_and_t_is_preserved() {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 1.0, 0.5),
            Quat::from_axis_angle(Vec3::new(1.0, 1.0, 0.0).normalize(), 0.7),
            Vec3::new(3.0, -1.0, 2.0),
        );
        let x = ObjectTransform::new(m).unwrap();
        let r = Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.3, -0.2, 0.9));
        let o = x.ray_to_object(&r);
        let t = 1.7;
        assert!((x.to_world.transform_point3(o.at(t)) - r.at(t)).length() < 1e-5);
        let b = x.bounds_to_world(Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)));
        assert!(b.contains(m.transform_point3(Vec3::new(1.0, -1.0, 1.0))));
        assert!(ObjectTransform::new(Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
    }

    #[test]
    fn normals_stay_perpendicular_under_non_uniform_scale() {
        let x = ObjectTransform::new(Mat4::from_scale(Vec3::new(4.0, 1.0, 1.0))).unwrap();
        // The plane x + y = 0 in object space; tangent (1, -1, 0) maps to (4, -1, 0).
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        let si = SurfaceInteraction {
            p: Vec3::ZERO,
            p_error: Vec3::ZERO,
            n,
            ns: n,
            uv: glam::Vec2::ZERO,
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            tangent: None,
        };
        let w = x.interaction_to_world(&si);
        assert!(w.n.dot(Vec3::new(4.0, -1.0, 0.0)).abs() < 1e-6);
        assert!((w.n.length() - 1.0).abs() < 1e-6);
    }
}
