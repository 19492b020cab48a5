use super::{PrimHit, SurfaceInteraction};
#[cfg(target_arch = "x86_64")]
use crate::math::RayF64x4;
use crate::math::{gamma, Aabb, Ray, RayF64, Vec2, Vec3};

/// The plane `dot(normal, p) = offset`, infinite or limited to a rectangle centred on `point`.
/// Infinite planes have no finite bounds, so they stay outside the acceleration structures and are
/// tested on their own; rectangles are ordinary bounded primitives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub normal: Vec3,
    pub offset: f32,
    pub point: Vec3,
    /// Half the rectangle's side along `tangent` and `bitangent`; `None` for an infinite plane.
    pub half_size: Option<Vec2>,
    /// Texture axes in the plane: `uv = (dot(p, tangent), dot(p, bitangent))`, in scene units.
    tangent: Vec3,
    bitangent: Vec3,
}

impl Plane {
    /// The infinite plane through `point` with (not necessarily unit) `normal`.
    pub fn new(point: Vec3, normal: Vec3) -> Self {
        Self::rectangle(point, normal, None)
    }

    /// A `size.x` by `size.y` rectangle centred on `point`, its sides along the texture axes (world x
    /// and the direction perpendicular to it in the plane, or world z for planes facing x).
    pub fn rectangle(point: Vec3, normal: Vec3, size: Option<Vec2>) -> Self {
        let normal = normal.normalize();
        // Prefer world x as the first texture axis, so a floor's checkerboard follows x and z.
        let reference = if normal.x.abs() < 0.9 {
            Vec3::X
        } else {
            Vec3::Z
        };
        let tangent = (reference - normal * normal.dot(reference)).normalize();
        let bitangent = normal.cross(tangent).normalize();
        Self {
            normal,
            offset: normal.dot(point),
            point,
            half_size: size.map(|s| 0.5 * s),
            tangent,
            bitangent,
        }
    }

    /// Bounds of a rectangle; `None` for an infinite plane.
    pub fn bounds(&self) -> Option<Aabb> {
        let h = self.half_size?;
        let (a, b) = (h.x * self.tangent, h.y * self.bitangent);
        Some(Aabb::from_points([
            self.point + a + b,
            self.point + a - b,
            self.point - a + b,
            self.point - a - b,
        ]))
    }

    /// Computed in f64 so that the hit parameter is accurate to f32 precision even for an origin far
    /// from the plane and a grazing direction.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<PrimHit> {
        self.intersect_f64(&RayF64::new(ray), t_max)
    }

    /// [`Self::intersect`] of a ray already converted to f64 (the same result).
    #[inline(always)]
    pub fn intersect_f64(&self, ray: &RayF64, t_max: f32) -> Option<PrimHit> {
        let n = self.normal.as_dvec3();
        let denom = n.dot(ray.dir);
        if denom == 0.0 {
            return None;
        }
        let num = self.offset as f64 - n.dot(ray.origin);
        // `t = num / denom` is positive only when both have the same sign: the division (and the
        // rectangle test) is skipped for rays leaving the plane's side, with the same answer.
        if num == 0.0 || (num < 0.0) != (denom < 0.0) {
            return None;
        }
        let t = num / denom;
        // Decided in f32, the precision callers compare in.
        let tf = t as f32;
        if !(tf > 0.0 && tf < t_max) {
            return None;
        }
        if let Some(h) = self.half_size {
            let local = ray.origin + t * ray.dir - self.point.as_dvec3();
            if local.dot(self.tangent.as_dvec3()).abs() > h.x as f64
                || local.dot(self.bitangent.as_dvec3()).abs() > h.y as f64
            {
                return None;
            }
        }
        Some(PrimHit {
            t: t as f32,
            u: 0.0,
            v: 0.0,
            sub: 0,
        })
    }

    /// [`Self::intersect_f64`] of four rays at once, as [`super::Sphere::intersect_f64x4`]: bit
    /// `k` of the result where lane `k` (active in `active`) hits, its distance in `t[k]`, bit for
    /// bit the scalar test's.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub fn intersect_f64x4(
        &self,
        ray: &RayF64x4,
        active: u32,
        t_max: &[f32; 4],
        t: &mut [f32; 4],
    ) -> u32 {
        let [ox, oy, oz] = ray.origin;
        let [dx, dy, dz] = ray.dir;
        let zero = ox.splat_as(0.0);
        let n = self.normal.as_dvec3();
        let (nx, ny, nz) = (ox.splat_as(n.x), ox.splat_as(n.y), ox.splat_as(n.z));
        let denom = nx * dx + ny * dy + nz * dz;
        let num = ox.splat_as(self.offset as f64) - (nx * ox + ny * oy + nz * oz);
        let miss = denom.eq(zero) | num.eq(zero) | num.lt(zero).xor(denom.lt(zero));
        let tv = num / denom;
        let mut lanes = active & !miss.bits() & tv.f32_inside(t_max);
        if lanes == 0 {
            return 0;
        }
        if let Some(h) = self.half_size {
            let p = self.point.as_dvec3();
            let lx = ox + tv * dx - ox.splat_as(p.x);
            let ly = oy + tv * dy - ox.splat_as(p.y);
            let lz = oz + tv * dz - ox.splat_as(p.z);
            let (u, v) = (self.tangent.as_dvec3(), self.bitangent.as_dvec3());
            let along_u = lx * ox.splat_as(u.x) + ly * ox.splat_as(u.y) + lz * ox.splat_as(u.z);
            let along_v = lx * ox.splat_as(v.x) + ly * ox.splat_as(v.y) + lz * ox.splat_as(v.z);
            let outside = along_u.abs().gt(ox.splat_as(h.x as f64))
                | along_v.abs().gt(ox.splat_as(h.y as f64));
            lanes &= !outside.bits();
        }
        *t = tv.to_f32();
        lanes
    }

    /// Inlined into [`crate::scene::Geometry::interaction_with`] (see there).
    #[inline(always)]
    pub fn interaction(&self, ray: &Ray, hit: &PrimHit) -> SurfaceInteraction {
        let n = self.normal.as_dvec3();
        let p = ray.origin.as_dvec3() + hit.t as f64 * ray.dir.as_dvec3();
        // Project onto the plane: what remains is the rounding of the f64 -> f32 conversion and of the
        // plane's own stored offset.
        let p = (p - (n.dot(p) - self.offset as f64) * n).as_vec3();
        let p_error = gamma(4) * (p.abs() + Vec3::splat(self.offset.abs()));
        SurfaceInteraction {
            p,
            p_error,
            n: self.normal,
            ns: self.normal,
            uv: Vec2::new(p.dot(self.tangent), p.dot(self.bitangent)),
            dpdu: self.tangent,
            dpdv: self.bitangent,
            tangent: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_hits_plane_at_analytic_distance() {
        let pl = Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y);
        let r = Ray::new(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
        assert!((pl.intersect(&r, f32::INFINITY).unwrap().t - 3.0).abs() < 1e-6);
        let r = Ray::new(
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0).normalize(),
        );
        let t = pl.intersect(&r, f32::INFINITY).unwrap().t;
        assert!((t - 3.0 * 2f32.sqrt()).abs() < 1e-5);
    }

    #[test]
    fn parallel_and_receding_rays_miss() {
        let pl = Plane::new(Vec3::ZERO, Vec3::Y);
        assert!(pl
            .intersect(&Ray::new(Vec3::Y, Vec3::X), f32::INFINITY)
            .is_none());
        assert!(pl
            .intersect(&Ray::new(Vec3::Y, Vec3::Y), f32::INFINITY)
            .is_none());
    }

    #[test]
    fn hits_from_below_count_too() {
        let pl = Plane::new(Vec3::ZERO, Vec3::Y);
        let h = pl.intersect(&Ray::new(-Vec3::Y, Vec3::Y), f32::INFINITY);
        assert!((h.unwrap().t - 1.0).abs() < 1e-6);
    }

    #[test]
    fn rectangle_is_hit_inside_and_missed_outside() {
        let r = Plane::rectangle(Vec3::ZERO, Vec3::Y, Some(Vec2::new(2.0, 4.0)));
        let down = |x: f32, z: f32| Ray::new(Vec3::new(x, 1.0, z), -Vec3::Y);
        assert!(r.intersect(&down(0.9, 1.9), f32::INFINITY).is_some());
        assert!(r.intersect(&down(1.1, 0.0), f32::INFINITY).is_none());
        assert!(r.intersect(&down(0.0, 2.1), f32::INFINITY).is_none());
        let b = r.bounds().unwrap();
        assert!((b.extent() - Vec3::new(2.0, 0.0, 4.0)).abs().max_element() < 1e-6);
        assert!(Plane::new(Vec3::ZERO, Vec3::Y).bounds().is_none());
    }

    #[test]
    fn interaction_is_on_the_plane_with_floor_uv_along_x_and_z() {
        let pl = Plane::new(Vec3::ZERO, Vec3::Y);
        let r = Ray::new(Vec3::new(3.0, 5.0, -2.0), -Vec3::Y);
        let si = pl.interaction(&r, &pl.intersect(&r, f32::INFINITY).unwrap());
        assert_eq!(si.p.y, 0.0);
        assert!((si.uv.x.abs() - 3.0).abs() < 1e-6 && (si.uv.y.abs() - 2.0).abs() < 1e-6);
    }
}
