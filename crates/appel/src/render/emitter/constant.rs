//! Mitsuba's `constant` emitter: the same radiance from every direction, sampled uniformly over
//! the sphere.

use super::warp::{square_to_sphere, SPHERE_PDF};
use super::EmitterSample;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct ConstantEnvironment {
    pub radiance: Vec3,
    /// Radius of the scene's bounding sphere, through whose cross-section the power is counted.
    pub scene_radius: f32,
}

impl ConstantEnvironment {
    pub fn new(radiance: Vec3) -> Self {
        Self {
            radiance,
            scene_radius: 1.0,
        }
    }

    pub fn sample_li(&self, u: Vec2) -> Option<EmitterSample> {
        Some(EmitterSample {
            wi: square_to_sphere(u),
            dist: f32::INFINITY,
            weight: self.radiance / SPHERE_PDF,
            pdf: SPHERE_PDF,
            delta: false,
        })
    }

    pub fn pdf_li(&self) -> f32 {
        SPHERE_PDF
    }

    /// The flux entering the scene's bounding sphere: Φ = π r² · 4π L.
    pub fn power(&self) -> Vec3 {
        PI * self.scene_radius * self.scene_radius * 4.0 * PI * self.radiance
    }
}
