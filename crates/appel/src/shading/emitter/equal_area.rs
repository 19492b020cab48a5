//! The equal-area octahedral mapping between the unit square and the sphere (Clarberg 2008, "Fast
//! Equal-Area Mapping of the (Hemi)Sphere using SIMD"), in which pbrt-v4 stores environment
//! images (pbrt-v4 section 3.8.3). The square's four corner triangles fold onto the lower
//! hemisphere and its inner diamond onto the upper one; equal areas of the square cover equal
//! solid angles, so a uniform point of the square is a uniform direction (density 1 / 4π).

use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_PI_4;

/// The direction of point `p` of `[0, 1]²`.
pub fn square_to_sphere(p: Vec2) -> Vec3 {
    let (u, v) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
    let (au, av) = (u.abs(), v.abs());
    // Signed distance from the diamond |u| + |v| = 1: positive inside (the upper hemisphere).
    let signed = 1.0 - (au + av);
    let r = 1.0 - signed.abs();
    // The angle within the quadrant grows along the diamond's edge from the u axis to the v axis.
    let phi = if r == 0.0 { 1.0 } else { (av - au) / r + 1.0 } * FRAC_PI_4;
    let z = (1.0 - r * r).copysign(signed);
    let (sin_phi, cos_phi) = phi.sin_cos();
    let radial = r * (2.0 - r * r).max(0.0).sqrt();
    Vec3::new(
        cos_phi.copysign(u) * radial,
        sin_phi.copysign(v) * radial,
        z,
    )
}

/// The inverse of [`square_to_sphere`] for a unit direction `d`.
pub fn sphere_to_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    // The distance from the centre (upper hemisphere) or the corners (lower) of the square.
    let r = (1.0 - z).max(0.0).sqrt();
    let (a, b) = (x.max(y), x.min(y));
    let ratio = if a == 0.0 { 0.0 } else { b / a };
    let mut phi = ratio.atan() / FRAC_PI_4 * 0.5;
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        // The lower hemisphere: the corner triangle, mirrored across the diamond's edge.
        (u, v) = (1.0 - v, 1.0 - u);
    }
    Vec2::new((u.copysign(d.x) + 1.0) * 0.5, (v.copysign(d.y) + 1.0) * 0.5)
}

#[cfg(test)]
mod tests {
    use super::super::chi2_sphere::Rng;
    use super::*;

    #[test]
    fn directions_are_unit_and_the_maps_are_inverse() {
        let mut rng = Rng::new(3);
        for _ in 0..100_000 {
            let p = rng.vec2();
            let d = square_to_sphere(p);
            assert!((d.length() - 1.0).abs() < 1e-5, "{p} -> {d}");
            let q = sphere_to_square(d);
            assert!((q - p).abs().max_element() < 2e-4, "{p} -> {d} -> {q}");
        }
        // The centre is the pole, the corners the other pole, the edges' midpoints the equator.
        assert!((square_to_sphere(Vec2::splat(0.5)) - Vec3::Z).length() < 1e-6);
        for c in [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE] {
            assert!((square_to_sphere(c) + Vec3::Z).length() < 1e-6, "{c}");
        }
        assert!((square_to_sphere(Vec2::new(1.0, 0.5)) - Vec3::X).length() < 1e-6);
        assert!((square_to_sphere(Vec2::new(0.5, 1.0)) - Vec3::Y).length() < 1e-6);
    }

    /// Equal areas: the fraction of uniform points of the square landing in a region of the
    /// sphere is its solid angle over 4π. Caps around each axis, and a lune, each of known
    /// solid angle; 200,000 points give a standard error below 0.0011.
    #[test]
    fn equal_areas_of_the_square_are_equal_solid_angles() {
        let mut rng = Rng::new(11);
        let n = 200_000;
        let dirs: Vec<Vec3> = (0..n).map(|_| square_to_sphere(rng.vec2())).collect();
        let fraction =
            |f: &dyn Fn(Vec3) -> bool| dirs.iter().filter(|&&d| f(d)).count() as f64 / n as f64;
        // A cap of half-angle θ covers (1 - cos θ) / 2 of the sphere.
        for (axis, cos) in [
            (Vec3::Z, 0.5),
            (-Vec3::Z, 0.8),
            (Vec3::X, 0.3),
            (Vec3::Y, 0.9),
        ] {
            let f = fraction(&|d: Vec3| d.dot(axis) > cos);
            let expected = (1.0 - cos as f64) / 2.0;
            assert!(
                (f - expected).abs() < 0.005,
                "{axis} {cos}: {f} vs {expected}"
            );
        }
        // The lune 0 < φ < 1 rad covers 1 / 2π.
        let f = fraction(&|d: Vec3| {
            let phi = d.y.atan2(d.x);
            (0.0..1.0).contains(&phi)
        });
        assert!((f - 1.0 / std::f64::consts::TAU).abs() < 0.005, "{f}");
    }
}
