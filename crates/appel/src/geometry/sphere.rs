use super::{PrimHit, SurfaceInteraction};
use crate::math::{gamma, Aabb, F64x2, Lanes, Ray, RayF64, Vec2, Vec3};
#[cfg(target_arch = "x86_64")]
use crate::math::{F64x4, Mask4, RayF64x4};
use glam::DVec3;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

impl Sphere {
    pub fn new(center: Vec3, radius: f32) -> Self {
        Self { center, radius }
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::new(
            self.center - Vec3::splat(self.radius),
            self.center + Vec3::splat(self.radius),
        )
    }

    /// Closest root in `(0, t_max)` of `|o + t d - c|^2 = r^2`.
    ///
    /// Solved in f64 with the discriminant in the form of pbrt-v4 eq. 6.12 (`r^2 - |l|^2`, with `l` the
    /// offset from the centre to the closest point on the line), which does not cancel catastrophically
    /// for rays far from a small sphere, and the stable quadratic formula (Press et al.).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<PrimHit> {
        self.intersect_f64(&RayF64::new(ray), t_max)
    }

    /// [`Self::intersect`] of a ray already converted to f64 (the same result).
    #[inline(always)]
    pub fn intersect_f64(&self, ray: &RayF64, t_max: f32) -> Option<PrimHit> {
        let o = ray.origin - self.center.as_dvec3();
        let d = ray.dir;
        let r = self.radius as f64;
        let a = ray.dir_length_squared;
        if a == 0.0 {
            return None;
        }
        let half_b = o.dot(d);
        let o2 = o.length_squared();
        let c = o2 - r * r;
        if misses_early(a, half_b, o2, r) {
            return None;
        }
        let l = o - (half_b / a) * d;
        let disc = a * (r * r - l.length_squared());
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
        // Decide in f32, the precision callers compare in: a root that rounds to `t_max` is not nearer.
        let inside = |t: f64| {
            let t = t as f32;
            t > 0.0 && t < t_max
        };
        let t = if inside(t0) {
            t0
        } else if inside(t1) {
            t1
        } else {
            return None;
        };
        Some(PrimHit {
            t: t as f32,
            u: 0.0,
            v: 0.0,
            sub: 0,
        })
    }

    /// [`Self::intersect_f64`] of four rays at once (lanes with bit `k` of `active`), each lane
    /// bounded by its own `t_max`: bit `k` of the result is set where lane `k` hits, and `t[k]`
    /// is then its hit distance, the scalar test's bit for bit (the same operations in the same
    /// order on each lane, its branches taken as masks).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub fn intersect_f64x4(
        &self,
        ray: &RayF64x4,
        active: u32,
        t_max: &[f32; 4],
        t: &mut [f32; 4],
    ) -> u32 {
        let a = ray.dir_length_squared;
        let zero = a.splat_as(0.0);
        let c = self.center.as_dvec3();
        let [dx, dy, dz] = ray.dir;
        let x = ray.origin[0] - a.splat_as(c.x);
        let y = ray.origin[1] - a.splat_as(c.y);
        let z = ray.origin[2] - a.splat_as(c.z);
        let r = a.splat_as(self.radius as f64);
        let half_b = x * dx + y * dy + z * dz;
        let o2 = x * x + y * y + z * z;
        let c = o2 - r * r;
        let early = misses_early_x4(a, half_b, o2, r);
        let s = half_b / a;
        let (lx, ly, lz) = (x - s * dx, y - s * dy, z - s * dz);
        let disc = a * (r * r - (lx * lx + ly * ly + lz * lz));
        let root = disc.sqrt();
        let q = F64x4::select(half_b.lt(zero), -half_b + root, -half_b - root);
        let miss = a.eq(zero) | early | disc.lt(zero) | q.eq(zero);
        let mut lanes = active & !miss.bits() & 0xf;
        if lanes == 0 {
            return 0;
        }
        let (t0, t1) = (c / q, q / a);
        let swap = t0.gt(t1);
        let (near, far) = (F64x4::select(swap, t1, t0), F64x4::select(swap, t0, t1));
        let (in_near, in_far) = (near.f32_inside(t_max), far.f32_inside(t_max));
        lanes &= in_near | in_far;
        let (near, far) = (near.to_f32(), far.to_f32());
        for k in 0..4 {
            t[k] = if in_near & (1 << k) != 0 {
                near[k]
            } else {
                far[k]
            };
        }
        lanes
    }

    pub fn interaction(&self, ray: &Ray, hit: &PrimHit) -> SurfaceInteraction {
        self.interaction_with(ray, hit, true)
    }

    /// [`Self::interaction`], with `uv` left at zero unless `with_uv`: the texture coordinates take an
    /// `atan2` and an `acos`, the larger part of the cost, and only textured materials read them.
    /// Inlined into [`crate::scene::Geometry::interaction_with`] (see there).
    #[inline(always)]
    pub fn interaction_with(&self, ray: &Ray, hit: &PrimHit, with_uv: bool) -> SurfaceInteraction {
        // Re-project the hit point onto the surface (pbrt-v4 section 6.8.5), so its error no longer
        // depends on how far the ray travelled.
        let c = self.center.as_dvec3();
        let p_hit = ray.origin.as_dvec3() + hit.t as f64 * ray.dir.as_dvec3();
        let mut local = p_hit - c;
        let len = local.length();
        local = if len > 0.0 {
            local * (self.radius as f64 / len)
        } else {
            DVec3::new(0.0, self.radius as f64, 0.0)
        };
        let p = (c + local).as_vec3();
        let local = local.as_vec3();
        let p_error = gamma(5) * (local.abs() + p.abs());
        let n = (local / self.radius).normalize();
        let uv = if with_uv {
            // Arc lengths along longitude and latitude: texture units are scene units, as on planes.
            let phi = n.z.atan2(n.x) + std::f32::consts::PI;
            let theta = n.y.clamp(-1.0, 1.0).acos();
            Vec2::new(phi, theta) * self.radius
        } else {
            Vec2::ZERO
        };
        SurfaceInteraction {
            p,
            p_error,
            n,
            ns: n,
            uv,
            // u and v are arc lengths: dp/du and dp/dv are the unit tangents along longitude phi
            // and colatitude theta (zero at the poles, where they are undefined).
            dpdu: Vec3::new(-n.z, 0.0, n.x),
            dpdv: {
                let sin_theta = (n.x * n.x + n.z * n.z).sqrt();
                if sin_theta > 0.0 {
                    Vec3::new(n.y * n.x / sin_theta, -sin_theta, n.y * n.z / sin_theta)
                } else {
                    Vec3::ZERO
                }
            },
            tangent: None,
        }
    }
}

/// Two early-outs of [`Sphere::intersect`] (from `a = |d|^2`, `half_b = o.d`, `o2 = |o|^2` with
/// `o` the origin's offset from the centre, and the radius `r`) that return exactly what its solve
/// would, without its division and square root (most tests in a scene of a few spheres are misses):
/// - An origin outside the sphere (`c = o2 - r^2 > 0`) with the ray pointing away (`half_b >= 0`):
///   both roots are <= 0 (their product `c / a` is positive, their sum `-2 half_b / a` is not), and
///   the solve computes them as such (`q <= 0`, so `c / q < 0` and `q / a <= 0`).
/// - The textbook discriminant `half_b^2 - a c` equals `a (r^2 - |l|^2)` in exact arithmetic. Both
///   are computed with a rounding error of a few f64 ulps of `S = half_b^2 + a |o|^2 + a r^2`
///   (Goldberg 1991; Haines et al., Ray Tracing Gems ch. 7, on why the textbook form cancels), so
///   when it is below `-1e-9 S`, far beyond that error, the robust form is negative too and the ray
///   misses. Near-tangent rays fall through to the robust form.
///
/// Written once for a scalar and for [`SphereBlock`]'s lanes, without branches (`&`, `|` on the
/// comparisons: the answer is that of the short-circuit form).
#[inline(always)]
fn misses_early<T: Lanes>(a: T, half_b: T, o2: T, r: T) -> T::Mask {
    let c = o2 - r * r;
    let scale = half_b * half_b + a * (o2 + r * r);
    (c.gt(T::splat(0.0)) & half_b.ge(T::splat(0.0)))
        | (half_b * half_b - a * c).lt(T::splat(-1e-9) * scale)
}

/// [`misses_early`] on four lanes, the same operations.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn misses_early_x4(a: F64x4, half_b: F64x4, o2: F64x4, r: F64x4) -> Mask4 {
    let zero = a.splat_as(0.0);
    let c = o2 - r * r;
    let scale = half_b * half_b + a * (o2 + r * r);
    (c.gt(zero) & half_b.ge(zero)) | (half_b * half_b - a * c).lt(a.splat_as(-1e-9) * scale)
}

/// Two spheres in f64, structure of arrays: a ray is tested against both at once by the
/// early-outs of [`Sphere::intersect`] (where most tests end), in the same operations on two
/// lanes ([`F64x2`]); only the spheres that pass need the full solve ([`Sphere::intersect_f64`]
/// of [`SphereBlock::get`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct SphereBlock {
    cx: [f64; 2],
    cy: [f64; 2],
    cz: [f64; 2],
    r: [f64; 2],
    spheres: [Sphere; 2],
    ids: [u32; 2],
    len: usize,
}

impl SphereBlock {
    /// Adds `sphere`, to be reported as primitive `id`; `false` if the block is full.
    pub fn push(&mut self, sphere: Sphere, id: u32) -> bool {
        let k = self.len;
        if k == 2 {
            return false;
        }
        let c = sphere.center.as_dvec3();
        (self.cx[k], self.cy[k], self.cz[k]) = (c.x, c.y, c.z);
        self.r[k] = sphere.radius as f64;
        self.spheres[k] = sphere;
        self.ids[k] = id;
        self.len += 1;
        true
    }

    /// How many spheres the block holds (one or two).
    #[inline(always)]
    pub fn count(&self) -> usize {
        self.len
    }

    /// Sphere `k` and its primitive id.
    #[inline(always)]
    pub fn get(&self, k: usize) -> (&Sphere, u32) {
        (&self.spheres[k], self.ids[k])
    }

    /// Bit `k` set for each sphere `k` that the early-outs of [`Sphere::intersect`] do not rule out.
    #[inline(always)]
    pub fn candidates(&self, ray: &RayF64) -> u32 {
        let (o, d) = (ray.origin, ray.dir);
        let splat = F64x2::splat;
        // `o - c`, `o.d` and `|o|^2` as `DVec3` computes them (x, then y, then z).
        let x = splat(o.x) - F64x2::new(self.cx);
        let y = splat(o.y) - F64x2::new(self.cy);
        let z = splat(o.z) - F64x2::new(self.cz);
        let half_b = x * splat(d.x) + y * splat(d.y) + z * splat(d.z);
        let o2 = x * x + y * y + z * z;
        let a = splat(ray.dir_length_squared);
        let miss = misses_early(a, half_b, o2, F64x2::new(self.r));
        (!miss).bits() & ((1 << self.len) - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Sphere {
        Sphere::new(Vec3::ZERO, 1.0)
    }

    #[test]
    fn ray_from_outside_hits_the_near_side() {
        let h = unit()
            .intersect(&Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z), f32::INFINITY)
            .unwrap();
        assert!((h.t - 4.0).abs() < 1e-6);
    }

    #[test]
    fn ray_from_inside_hits_the_far_side() {
        let h = unit()
            .intersect(&Ray::new(Vec3::new(0.0, 0.5, 0.0), Vec3::Y), f32::INFINITY)
            .unwrap();
        assert!((h.t - 0.5).abs() < 1e-6);
    }

    #[test]
    fn sphere_behind_the_ray_is_missed() {
        assert!(unit()
            .intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z), f32::INFINITY)
            .is_none());
    }

    #[test]
    fn grazing_ray_touches_once_and_a_ray_just_outside_misses() {
        let graze = unit()
            .intersect(&Ray::new(Vec3::new(1.0, 0.0, -5.0), Vec3::Z), f32::INFINITY)
            .unwrap();
        assert!((graze.t - 5.0).abs() < 1e-5);
        assert!(unit()
            .intersect(
                &Ray::new(Vec3::new(1.0001, 0.0, -5.0), Vec3::Z),
                f32::INFINITY
            )
            .is_none());
    }

    #[test]
    fn t_max_excludes_farther_hits() {
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        assert!(unit().intersect(&r, 3.9).is_none());
    }

    #[test]
    fn small_sphere_far_away_is_hit_with_relative_precision() {
        let s = Sphere::new(Vec3::new(0.0, 0.0, 1.0e5), 1.0e-3);
        let h = s
            .intersect(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY)
            .unwrap();
        assert!(((h.t as f64) - (1.0e5 - 1.0e-3)).abs() < 1e-2);
    }

    #[test]
    fn interaction_lies_on_the_surface_with_outward_normal() {
        let s = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 2.0);
        let r = Ray::new(Vec3::new(1.0, 2.0, -10.0), Vec3::Z);
        let h = s.intersect(&r, f32::INFINITY).unwrap();
        let si = s.interaction(&r, &h);
        assert!(((si.p - s.center).length() - 2.0).abs() < 1e-5);
        assert!(si.n.dot(-Vec3::Z) > 0.999);
        // Without texture coordinates, everything else is the same to the bit.
        let bare = s.interaction_with(&r, &h, false);
        assert_eq!(
            (bare.p, bare.p_error, bare.n, bare.ns),
            (si.p, si.p_error, si.n, si.ns)
        );
        assert_eq!(bare.uv, Vec2::ZERO);
        assert!(si.uv.x > 0.0 && si.uv.y > 0.0);
    }
}
