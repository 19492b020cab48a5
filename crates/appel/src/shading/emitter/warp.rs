//! Warps of the unit square onto the shapes that lights are sampled on, each with a constant
//! density (pbrt-v4 section A.5). Disks use the BSDFs' concentric map
//! ([`crate::shading::bsdf::warp::square_to_uniform_disk_concentric`]).

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Uniform directions on the unit sphere: z uniform in [-1, 1], the azimuth uniform. Density 1 / 4π.
pub fn square_to_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

pub const SPHERE_PDF: f32 = 1.0 / (4.0 * PI);

/// Uniform barycentrics (b1, b2) on a triangle: the square folded by the square root of one
/// coordinate (pbrt-v4 equation A.12's mapping, as Mitsuba's `square_to_uniform_triangle`).
pub fn square_to_triangle(u: Vec2) -> Vec2 {
    let t = (1.0 - u.x).max(0.0).sqrt();
    Vec2::new(1.0 - t, t * u.y)
}
