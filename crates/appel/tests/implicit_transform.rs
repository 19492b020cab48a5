//! An implicit surface placed by a transform: the unit sphere's formula, scaled, rotated and moved,
//! must be the analytic ellipsoid it describes.

use appel::accel::TraversalStats;
use appel::description::description_from_str;
use appel::description::parse::Syntax;
use appel::geometry::procedural::SplitMix64;
use appel::math::{Ray, Vec3};
use appel::scene::Scene;
use std::path::Path;

fn scene(transform: &str) -> Scene {
    let text = format!(
        r#"
        [camera]
        eye = [3.0, 0.0, 10.0]
        look_at = [3.0, 0.0, 0.0]

        [[shape]]
        type = "implicit"
        f = "x^2 + y^2 + z^2 - 1"
        bounds = [[-1.1, -1.1, -1.1], [1.1, 1.1, 1.1]]
        transform = {transform}
        "#
    );
    let d = description_from_str(&text, Syntax::Toml, Path::new("t.toml")).unwrap();
    Scene::new(&d, Path::new(".")).unwrap()
}

/// Closest positive root of the ellipsoid `|A (p - c)| = 1` along the ray, `A` diagonal in the frame
/// given by `axes`.
fn ellipsoid_t(ray: &Ray, c: Vec3, axes: [Vec3; 3], radii: Vec3) -> Option<f32> {
    let o = ray.origin - c;
    let to_local = |v: Vec3| Vec3::new(v.dot(axes[0]), v.dot(axes[1]), v.dot(axes[2])) / radii;
    let (o, d) = (to_local(o).as_dvec3(), to_local(ray.dir).as_dvec3());
    let (a, b, cc) = (d.dot(d), 2.0 * o.dot(d), o.dot(o) - 1.0);
    let disc = b * b - 4.0 * a * cc;
    if disc < 0.0 {
        return None;
    }
    let roots = [
        (-b - disc.sqrt()) / (2.0 * a),
        (-b + disc.sqrt()) / (2.0 * a),
    ];
    roots.into_iter().find(|&t| t > 1e-6).map(|t| t as f32)
}

#[test]
fn scaled_rotated_and_moved_sphere_is_the_analytic_ellipsoid() {
    // Scale x by 2, then turn 90 degrees about z (the long axis becomes y), then move to (3, 0, 0).
    let s = scene("{ scale = [2.0, 1.0, 1.0], rotate = { axis = [0.0, 0.0, 1.0], degrees = 90.0 }, translate = [3.0, 0.0, 0.0] }");
    let mut stats = TraversalStats::default();
    let down = Ray::new(Vec3::new(3.0, 10.0, 0.0), -Vec3::Y);
    let hit = s.intersect(&down, f32::INFINITY, &mut stats).unwrap();
    assert!((hit.t - 8.0).abs() < 1e-4, "{}", hit.t);
    let si = s.geometry.interaction(&down, &hit);
    assert!((si.p - Vec3::new(3.0, 2.0, 0.0)).length() < 1e-4);
    assert!(si.n.dot(Vec3::Y) > 0.9999, "{}", si.n);

    let axes = [Vec3::Y, -Vec3::X, Vec3::Z];
    let radii = Vec3::new(2.0, 1.0, 1.0);
    let centre = Vec3::new(3.0, 0.0, 0.0);
    let mut rng = SplitMix64(11);
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..20_000 {
        let origin = rng.in_box(Vec3::new(-2.0, -5.0, -5.0), Vec3::new(8.0, 5.0, 5.0));
        let target = rng.in_box(Vec3::new(1.0, -2.5, -1.2), Vec3::new(5.0, 2.5, 1.2));
        let ray = Ray::new(origin, (target - origin).normalize());
        let expected = ellipsoid_t(&ray, centre, axes, radii);
        let got = s.intersect(&ray, f32::INFINITY, &mut stats).map(|h| h.t);
        match (expected, got) {
            (Some(e), Some(g)) => {
                assert!((e - g).abs() <= 1e-4 * e.max(1.0), "{ray:?}: {e} vs {g}");
                hits += 1;
            }
            (None, None) => misses += 1,
            (e, g) => {
                // Only a ray grazing the silhouette may disagree.
                let near = e.or(g).unwrap();
                let p = ray.at(near) - centre;
                let local = Vec3::new(p.dot(axes[0]), p.dot(axes[1]), p.dot(axes[2])) / radii;
                let grad = (local / radii).normalize();
                let cos = grad.dot(Vec3::new(
                    ray.dir.dot(axes[0]),
                    ray.dir.dot(axes[1]),
                    ray.dir.dot(axes[2]),
                ));
                assert!(cos.abs() < 1e-2, "{ray:?}: expected {e:?}, got {g:?}");
            }
        }
    }
    assert!(hits > 2000 && misses > 2000, "{hits} hits, {misses} misses");
}

#[test]
fn transformed_implicit_renders_the_same_at_any_scale() {
    let s = scene("{ scale = 1.5, translate = [3.0, 0.0, 0.0] }");
    let mut stats = TraversalStats::default();
    let ray = Ray::new(Vec3::new(3.0, 0.0, 10.0), -Vec3::Z);
    let hit = s.intersect(&ray, f32::INFINITY, &mut stats).unwrap();
    assert!((hit.t - 8.5).abs() < 1e-4);
    // Secondary rays leaving the surface do not hit it again.
    let si = s.geometry.interaction(&ray, &hit);
    let out = appel::math::offset_ray_origin(si.p, si.p_error, si.n, Vec3::Z);
    assert!(s
        .intersect(&Ray::new(out, Vec3::Z), f32::INFINITY, &mut stats)
        .is_none());
    let inward = appel::math::offset_ray_origin(si.p, si.p_error, si.n, -Vec3::Z);
    let through = s
        .intersect(&Ray::new(inward, -Vec3::Z), f32::INFINITY, &mut stats)
        .unwrap();
    assert!((through.t - 3.0).abs() < 1e-3, "{}", through.t);
}
