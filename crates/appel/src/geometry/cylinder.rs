//! Mitsuba's `cylinder`: the open tube `x^2 + y^2 = 1`, `0 <= z <= 1` (no caps) in its own space,
//! placed by an affine `to_world`. Texture coordinates and derivatives are Mitsuba 3's:
//! `u = phi / 2 pi` (phi = atan2(y, x) in [0, 2 pi)), `v = z`, `dp/du = 2 pi (-y, x, 0)`,
//! `dp/dv = (0, 0, 1)`, carried to the world by the transform; the normal points away from the
//! axis (inward with `flip_normals`).

use super::{ObjectTransform, PrimHit, SurfaceInteraction};
use crate::math::{gamma, Aabb, Ray, Vec2, Vec3};
use glam::{DMat4, DVec3, Mat4};
use std::f64::consts::TAU;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    transform: ObjectTransform,
    /// The inverse in f64: rays far from a small cylinder keep their precision in object space.
    to_object: DMat4,
    flip_normals: bool,
}

impl Cylinder {
    /// `None` when `to_world` cannot be inverted.
    pub fn new(to_world: Mat4, flip_normals: bool) -> Option<Self> {
        let transform = ObjectTransform::new(to_world)?;
        let to_object = to_world.as_dmat4().inverse();
        to_object.is_finite().then_some(Self {
            transform,
            to_object,
            flip_normals,
        })
    }

    pub fn to_world(&self) -> Mat4 {
        self.transform.to_world
    }

    pub fn flip_normals(&self) -> bool {
        self.flip_normals
    }

    /// The box of the transformed box around the tube.
    pub fn bounds(&self) -> Aabb {
        let b = self
            .transform
            .bounds_to_world(Aabb::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::ONE));
        // Widened by a few ulps: the transform rounds, and the box must contain the surface.
        let pad = (b.max - b.min).abs().max(b.min.abs().max(b.max.abs())) * (4.0 * f32::EPSILON);
        Aabb::new(b.min - pad, b.max + pad)
    }

    /// Nearest `t` in `(0, t_max)` where the ray meets the tube between its rims: the roots of
    /// `(ox + t dx)^2 + (oy + t dy)^2 = 1` in object space (where `t` is the world ray's, the
    /// direction not being renormalised), solved in f64 with the stable quadratic formula, the
    /// discriminant written as `a - (o x d)_z^2` (the squared distance of the line from the axis,
    /// pbrt-v4 eq. 6.12's idea for the sphere), which does not cancel for rays far away.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<PrimHit> {
        let o = self.to_object.transform_point3(ray.origin.as_dvec3());
        let d = self.to_object.transform_vector3(ray.dir.as_dvec3());
        let a = d.x * d.x + d.y * d.y;
        if a == 0.0 {
            return None;
        }
        let half_b = o.x * d.x + o.y * d.y;
        let c = o.x * o.x + o.y * o.y - 1.0;
        let cross = o.x * d.y - o.y * d.x;
        let disc = a - cross * cross;
        if disc < 0.0 {
            return None;
        }
        let root = disc.sqrt();
        let q = if half_b < 0.0 {
            -half_b + root
        } else {
            -half_b - root
        };
        let (mut t0, mut t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q / a) };
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        for t in [t0, t1] {
            let t32 = t as f32;
            if !(t > 0.0 && t32 > 0.0 && t32 < t_max) {
                continue;
            }
            let z = o.z + t * d.z;
            if (0.0..=1.0).contains(&z) {
                return Some(PrimHit {
                    t: t32,
                    u: 0.0,
                    v: 0.0,
                    sub: 0,
                });
            }
        }
        None
    }

    pub fn interaction(&self, ray: &Ray, hit: &PrimHit) -> SurfaceInteraction {
        let o = self.to_object.transform_point3(ray.origin.as_dvec3());
        let d = self.to_object.transform_vector3(ray.dir.as_dvec3());
        let hit_local = o + hit.t as f64 * d;
        let local = local_point(hit_local);
        let si = local_interaction(local, self.flip_normals);
        self.transform.interaction_to_world(&si)
    }
}

/// The object-space point re-projected onto the tube (pbrt-v4 section 6.8.5), so that its error
/// does not grow with the distance the ray travelled.
fn local_point(p: DVec3) -> DVec3 {
    let r = p.x.hypot(p.y);
    if r > 0.0 {
        DVec3::new(p.x / r, p.y / r, p.z.clamp(0.0, 1.0))
    } else {
        DVec3::new(1.0, 0.0, p.z.clamp(0.0, 1.0))
    }
}

/// Mitsuba's parameterisation at a point of the unit tube.
pub(crate) fn local_interaction(p: DVec3, flip: bool) -> SurfaceInteraction {
    let mut phi = p.y.atan2(p.x);
    if phi < 0.0 {
        phi += TAU;
    }
    let n = Vec3::new(p.x as f32, p.y as f32, 0.0).normalize();
    let n = if flip { -n } else { n };
    let pf = p.as_vec3();
    SurfaceInteraction {
        p: pf,
        p_error: gamma(5) * pf.abs(),
        n,
        ns: n,
        uv: Vec2::new((phi / TAU) as f32, p.z as f32),
        dpdu: (TAU * DVec3::new(-p.y, p.x, 0.0)).as_vec3(),
        dpdv: Vec3::Z,
        tangent: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::offset_ray_origin;
    use glam::{Quat, Vec3};

    fn placed() -> Cylinder {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(1.5, 1.5, 2.0),
            Quat::from_axis_angle(Vec3::new(1.0, 0.3, -0.2).normalize(), 0.8),
            Vec3::new(0.5, -2.0, 1.0),
        );
        Cylinder::new(m, false).unwrap()
    }

    /// Hits lie on the tube (radius and height checked in object space), uv follows Mitsuba's
    /// parameterisation, the normal is perpendicular to dp/du and dp/dv and points away from the
    /// axis, and a ray through the middle hits the near wall at the analytic distance.
    #[test]
    fn hits_are_on_the_tube_with_mitsubas_uv() {
        let c = Cylinder::new(Mat4::IDENTITY, false).unwrap();
        let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.5), Vec3::X);
        let h = c.intersect(&ray, f32::INFINITY).unwrap();
        assert!((h.t - 4.0).abs() < 1e-6);
        let si = c.interaction(&ray, &h);
        assert!((si.n - -Vec3::X).length() < 1e-6);
        assert!((si.uv - Vec2::new(0.5, 0.5)).length() < 1e-6);
        // Above the rim and along the axis: misses.
        assert!(c
            .intersect(
                &Ray::new(Vec3::new(-5.0, 0.0, 1.01), Vec3::X),
                f32::INFINITY
            )
            .is_none());
        assert!(c
            .intersect(&Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z), f32::INFINITY)
            .is_none());
        // From inside: the far wall, facing away from the ray's origin side.
        let inner = Ray::new(Vec3::new(0.0, 0.0, 0.5), Vec3::Y);
        let h = c.intersect(&inner, f32::INFINITY).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);

        let c = placed();
        let to_object = c.to_world().inverse();
        let mut hits = 0;
        let mut rng = 1u64;
        let mut next = || {
            rng = rng
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (rng >> 40) as f32 / (1u64 << 24) as f32
        };
        for _ in 0..2000 {
            let o = Vec3::new(next(), next(), next()) * 12.0 - 6.0;
            let target = c.to_world().transform_point3(Vec3::new(
                next() * 2.0 - 1.0,
                next() * 2.0 - 1.0,
                next() * 1.2 - 0.1,
            ));
            let ray = Ray::new(o, target - o);
            let Some(h) = c.intersect(&ray, f32::INFINITY) else {
                continue;
            };
            hits += 1;
            let si = c.interaction(&ray, &h);
            let l = to_object.transform_point3(si.p);
            assert!((l.x.hypot(l.y) - 1.0).abs() < 1e-4, "{l:?}");
            assert!((-1e-4..=1.0 + 1e-4).contains(&l.z));
            assert!((si.p - ray.at(h.t)).length() < 1e-3);
            let mut phi = l.y.atan2(l.x);
            if phi < 0.0 {
                phi += std::f32::consts::TAU;
            }
            assert!((si.uv.x - phi / std::f32::consts::TAU).abs() < 1e-4);
            assert!((si.uv.y - l.z).abs() < 1e-4);
            assert!(si.n.dot(si.dpdu).abs() < 1e-4 * si.dpdu.length());
            assert!(si.n.dot(si.dpdv).abs() < 1e-4 * si.dpdv.length());
            // Outward: the normal points away from the axis point at the hit's height.
            let axis = c.to_world().transform_point3(Vec3::new(0.0, 0.0, l.z));
            assert!(si.n.dot(si.p - axis) > 0.0);
            // A ray leaving the surface does not hit it again at once.
            let w = si.n + 0.3 * si.dpdu.normalize();
            let out = Ray::new(offset_ray_origin(si.p, si.p_error, si.n, w), w);
            if let Some(again) = c.intersect(&out, f32::INFINITY) {
                assert!(again.t > 1e-3, "self-hit at {}", again.t);
            }
        }
        assert!(hits > 1000, "{hits}");
    }

    #[test]
    fn bounds_contain_the_tube_and_flip_turns_the_normal() {
        let c = placed();
        let b = c.bounds();
        for i in 0..64 {
            let phi = i as f32 * 0.1;
            for z in [0.0, 0.5, 1.0] {
                let p = c
                    .to_world()
                    .transform_point3(Vec3::new(phi.cos(), phi.sin(), z));
                assert!(b.contains(p), "{p:?}");
            }
        }
        let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.5), Vec3::X);
        let flipped = Cylinder::new(Mat4::IDENTITY, true).unwrap();
        let h = flipped.intersect(&ray, f32::INFINITY).unwrap();
        assert!((flipped.interaction(&ray, &h).n - Vec3::X).length() < 1e-6);
    }
}
