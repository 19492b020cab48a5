//! The rays of a path tracer's deeper bounces, for `appel bench`: unlike the one-bounce incoherent
//! rays, their origins are spread over the whole scene and their directions owe nothing to the
//! camera, which is the traffic a path tracer (`integrator = "path"`) sends after its first bounce.

use super::BenchTarget;
use appel::accel::{Accel, TraversalStats};
use appel::geometry::procedural::SplitMix64;
use appel::math::{offset_ray_origin, orthonormal_basis, Ray, Vec2};
use appel::shading::bsdf::warp::square_to_cosine_hemisphere;

/// The bounces a walk keeps: each camera hit gives the ray of bounce 2, 3 or 4 in turn (bounce 1
/// being the incoherent kind), so there are at most as many path rays as camera rays, evenly
/// mixed in depth.
const KEPT_BOUNCES: [usize; 3] = [2, 3, 4];

/// From each camera hit, a random walk over Lambertian surfaces: each bounce leaves on the side
/// the walk arrived from, in a cosine-weighted direction (the importance sampling of a diffuse
/// BSDF, pbrt-v4 section 9.2), from the error-bound offset of the hit. The walk stops when a ray
/// escapes; the ray of its kept bounce ([`KEPT_BOUNCES`]) is recorded. Fixed seed.
pub fn path_rays(target: &BenchTarget, accel: &Accel, primary: &[Ray]) -> Vec<Ray> {
    let g = &target.geometry;
    let mut rng = SplitMix64(0x9a7b);
    let mut stats = TraversalStats::default();
    let mut out = Vec::with_capacity(primary.len());
    for (i, camera_ray) in primary.iter().enumerate() {
        let keep = KEPT_BOUNCES[i % KEPT_BOUNCES.len()];
        let mut ray = *camera_ray;
        for bounce in 1..=keep {
            let Some(hit) = accel.intersect(g, &ray, f32::INFINITY, &mut stats) else {
                break;
            };
            let si = g.interaction(&ray, &g.scene_hit(hit));
            let n = if si.n.dot(ray.dir) > 0.0 { -si.n } else { si.n };
            let local = square_to_cosine_hemisphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            let (s, t) = orthonormal_basis(n);
            let dir = (local.x * s + local.y * t + local.z * n).normalize();
            ray = Ray::new(offset_ray_origin(si.p, si.p_error, si.n, dir), dir);
            if bounce == keep {
                out.push(ray);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench_scene;
    use appel::accel::AccelKind;

    /// In a closed room every walk reaches its kept bounce, the rays leave from the room's
    /// surfaces, and they point every which way: their mean direction is near zero, where camera
    /// rays share one direction.
    #[test]
    fn walks_reach_their_bounce_and_scatter() {
        let target = bench_scene("teapot-in-stadium", 2000, 40, 30).unwrap();
        let accel = Accel::build(AccelKind::Bvh, &target.geometry);
        let primary = crate::camera_rays(&target.camera);
        let rays = path_rays(&target, &accel, &primary);
        assert!(!rays.is_empty() && rays.len() <= primary.len());
        let mean = rays.iter().map(|r| r.dir).sum::<appel::math::Vec3>() / rays.len() as f32;
        let camera_mean =
            primary.iter().map(|r| r.dir).sum::<appel::math::Vec3>() / primary.len() as f32;
        assert!(camera_mean.length() > 0.9, "{camera_mean}");
        assert!(mean.length() < 0.5, "{mean}");
        let bounds = target.geometry.bounds();
        let spread = appel::math::Aabb::from_points(rays.iter().map(|r| r.origin));
        assert!(
            spread.extent().length() > 0.5 * bounds.extent().length(),
            "origins span {spread:?} of {bounds:?}"
        );
    }
}
