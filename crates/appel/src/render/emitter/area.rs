//! Mitsuba's `area` emitter: a shape whose surface emits radiance (a texture over its uv) from the
//! side its normal points to only.

use super::shape_sampler::ShapeSampler;
use super::EmitterSample;
use crate::render::texture::Texture;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub struct AreaEmitter {
    pub radiance: Texture,
    pub shape: ShapeSampler,
}

impl AreaEmitter {
    pub fn new(radiance: Texture, shape: ShapeSampler) -> Self {
        Self { radiance, shape }
    }

    /// One-sided: `w` must leave the side `n` points to.
    pub fn radiance(&self, n: Vec3, uv: Vec2, w: Vec3) -> Vec3 {
        if n.dot(w) > 0.0 {
            self.radiance.eval(uv)
        } else {
            Vec3::ZERO
        }
    }

    /// A point of the shape as the shape sampler picks it, kept only if `p` sees its emitting side.
    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<EmitterSample> {
        let s = self.shape.sample_direction(p, u)?;
        if s.wi.dot(s.shape.normal) >= 0.0 || !(s.pdf > 0.0) {
            return None;
        }
        Some(EmitterSample {
            wi: s.wi,
            dist: s.dist,
            weight: self.radiance.eval(s.shape.uv) / s.pdf,
            pdf: s.pdf,
            delta: false,
        })
    }

    /// Zero for directions reaching the back of the surface, which [`sample_li`](Self::sample_li)
    /// never returns.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, light_point: Vec3, light_normal: Vec3) -> f32 {
        if wi.dot(light_normal) >= 0.0 {
            return 0.0;
        }
        self.shape.pdf_direction(p, wi, light_point, light_normal)
    }

    /// Φ = π A L̄ for a one-sided Lambertian emitter, L̄ the texture's mean.
    pub fn power(&self) -> Vec3 {
        PI * self.shape.area() * self.radiance.mean()
    }
}
