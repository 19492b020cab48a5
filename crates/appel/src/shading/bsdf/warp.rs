//! Warps of the unit square used by the BSDFs' samplers, as Mitsuba 3's `warp.h` defines them,
//! so that the same random numbers give the same directions.

use crate::math::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4};

/// Shirley and Chiu's concentric map (1997) of the square onto the unit disk, in Dave Cline's
/// single-branch form: square rings go to circles, so strata stay compact.
#[inline]
pub fn square_to_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let x = 2.0 * u.x - 1.0;
    let y = 2.0 * u.y - 1.0;
    if x == 0.0 && y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, phi) = if x.abs() < y.abs() {
        (y, FRAC_PI_2 - FRAC_PI_4 * x / y)
    } else {
        (x, FRAC_PI_4 * y / x)
    };
    let (s, c) = phi.sin_cos();
    Vec2::new(r * c, r * s)
}

/// Cosine-weighted direction on the upper hemisphere (Malley's method: the concentric disk
/// point lifted onto the hemisphere).
#[inline]
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let p = square_to_uniform_disk_concentric(u);
    let z = (1.0 - p.length_squared()).max(0.0).sqrt();
    Vec3::new(p.x, p.y, z)
}

/// Density of [`square_to_cosine_hemisphere`]: `cos θ / π` (its value below the horizon is
/// negative, as in Mitsuba; callers test the side first).
#[inline]
pub fn square_to_cosine_hemisphere_pdf(w: Vec3) -> f32 {
    FRAC_1_PI * w.z
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::chi2::{Chi2Test, Config};

    #[test]
    fn concentric_disk_corners_and_mitsuba() {
        assert_eq!(
            square_to_uniform_disk_concentric(Vec2::splat(0.5)),
            Vec2::ZERO
        );
        for (u, p) in [
            (Vec2::new(1.0, 0.5), Vec2::new(1.0, 0.0)),
            (Vec2::new(0.5, 1.0), Vec2::new(0.0, 1.0)),
            (Vec2::new(0.0, 0.5), Vec2::new(-1.0, 0.0)),
            // mi.warp.square_to_uniform_disk_concentric([0.3, 0.7]) = [-0.28284271, 0.28284271],
            // ([0.9, 0.2]) = [0.66517562, -0.44445622]
            (Vec2::new(0.3, 0.7), Vec2::new(-0.282_842_7, 0.282_842_7)),
            (Vec2::new(0.9, 0.2), Vec2::new(0.665_175_6, -0.444_456_2)),
        ] {
            let got = square_to_uniform_disk_concentric(u);
            assert!((got - p).length() < 1e-6, "{u}: {got}");
        }
    }

    #[test]
    fn cosine_hemisphere_follows_its_pdf() {
        let o = Chi2Test::new(Config::default()).run(
            |_, u| Some(square_to_cosine_hemisphere(u)),
            |w| square_to_cosine_hemisphere_pdf(w).max(0.0),
        );
        assert!(o.passed, "{o}");
    }
}
