//! Rays leaving the lights, the first vertex of a light path (light tracing, Veach 1997 section
//! 10.2; Mitsuba 3's `Emitter::sample_ray`, pbrt-v4's `Light::SampleLe`): a position and a
//! direction, with the flux the ray carries as the emitted radiance (or intensity) over the
//! densities of both.

use super::Emitter;
use crate::math::gamma;
use crate::shading::bsdf::warp::square_to_uniform_disk_concentric;
use crate::shading::frame::ShadingFrame;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// A ray leaving a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmitterRay {
    pub origin: Vec3,
    /// A conservative bound on the rounding error of each coordinate of `origin`, by which the
    /// ray leaves the emitting surface (zero for lights that are no surface).
    pub origin_error: Vec3,
    /// Unit direction of travel.
    pub dir: Vec3,
    /// The unit normal of the emitting surface at `origin`, zero for lights at a point; for an
    /// infinite light, `dir` (the disk the ray enters through faces it).
    pub normal: Vec3,
    /// `Le |cos| / (pdf_pos pdf_dir)`: what the ray carries (for delta positions or directions
    /// the intensity or irradiance over the other density).
    pub weight: Vec3,
    /// The emitting surface's texture coordinates at `origin` (zero for lights that are no
    /// surface).
    pub uv: Vec2,
    /// Density of the origin by area (1 for a point light).
    pub pdf_pos: f32,
    /// Density of the direction by solid angle (1 for a directional light).
    pub pdf_dir: f32,
}

/// A point of an emitting surface, by area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PositionSample {
    pub point: Vec3,
    /// See [`EmitterRay::origin_error`].
    pub point_error: Vec3,
    /// Unit normal on the emitting side.
    pub normal: Vec3,
    pub uv: Vec2,
    /// Density by area.
    pub pdf: f32,
}

/// A bound on the rounding error of a point computed from a shape's parameters by a handful of
/// products and sums (a transform of a unit square or disk, barycentric interpolation, a centre
/// plus a scaled direction): each coordinate's error is at most a few roundings of the largest
/// terms, which the point's own magnitude and the shape's extent bound (pbrt-v4 section 6.8.5
/// bounds sampled triangle points by `gamma(6)` of the terms; `gamma(8)` covers the transforms).
pub(super) fn sampled_point_error(p: Vec3, extent: f32) -> Vec3 {
    gamma(8) * (p.abs() + Vec3::splat(extent))
}

/// The ray of an infinite light: the direction of its `sample_li` (which does not depend on the
/// reference point for a light at infinity) reversed, entering through a disk of the scene's
/// bounding sphere's radius facing it, so that every point of the scene is reached alike
/// (pbrt-v4's `UniformInfiniteLight::SampleLe`). The flux is the radiance over the direction's
/// density times the disk's area (for a directional light, its irradiance times the area).
pub(super) fn infinite_ray(
    e: &Emitter,
    u_pos: Vec2,
    u_dir: Vec2,
    (centre, radius): (Vec3, f32),
) -> Option<EmitterRay> {
    let s = e.sample_li(centre, u_dir)?;
    if s.pdf.is_nan() || s.pdf <= 0.0 || s.weight == Vec3::ZERO {
        return None;
    }
    let dir = -s.wi;
    let frame = ShadingFrame::from_normal(dir);
    let d = square_to_uniform_disk_concentric(u_pos) * radius;
    let origin = centre + radius * s.wi + d.x * frame.s + d.y * frame.t;
    let disk_area = PI * radius * radius;
    Some(EmitterRay {
        origin,
        origin_error: Vec3::ZERO,
        dir,
        normal: dir,
        uv: Vec2::ZERO,
        weight: s.weight * disk_area,
        pdf_pos: 1.0 / disk_area,
        pdf_dir: s.pdf,
    })
}

/// Uniform directions over the sphere, by `u`, and their density.
pub(super) fn uniform_sphere(u: Vec2) -> (Vec3, f32) {
    (super::warp::square_to_sphere(u), 1.0 / (4.0 * PI))
}

/// A direction in the cone of half-angle `acos(cos_max)` about +z, uniform by solid angle.
pub(super) fn uniform_cone(u: Vec2, cos_max: f32) -> (Vec3, f32) {
    let cos = 1.0 - u.x * (1.0 - cos_max);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let (sp, cp) = (2.0 * PI * u.y).sin_cos();
    (
        Vec3::new(sin * cp, sin * sp, cos),
        1.0 / (2.0 * PI * (1.0 - cos_max)),
    )
}
