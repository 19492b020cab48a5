//! Mitsuba's `directional` emitter: parallel light of a given irradiance, from infinitely far.

use super::EmitterSample;
use glam::Vec3;
use std::f32::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction the light travels along.
    pub direction: Vec3,
    /// Irradiance on a surface facing the light (W/m² per channel).
    pub irradiance: Vec3,
    /// Radius of the scene's bounding sphere, through whose cross-section the power is counted.
    pub scene_radius: f32,
}

impl DirectionalLight {
    pub fn new(direction: Vec3, irradiance: Vec3) -> Self {
        Self {
            direction: direction.normalize(),
            irradiance,
            scene_radius: 1.0,
        }
    }

    pub fn sample_li(&self) -> Option<EmitterSample> {
        Some(EmitterSample {
            wi: -self.direction,
            dist: f32::INFINITY,
            weight: self.irradiance,
            pdf: 1.0,
            delta: true,
        })
    }

    /// The flux through the scene's bounding disc: Φ = π r² E.
    pub fn power(&self) -> Vec3 {
        PI * self.scene_radius * self.scene_radius * self.irradiance
    }
}

impl super::EmitterPlugin for DirectionalLight {
    const NAME: &'static str = "directional";
    const DELTA: bool = true;
    const INFINITE: bool = true;

    #[inline]
    fn sample_li(&self, _p: glam::Vec3, _u: glam::Vec2) -> Option<super::EmitterSample> {
        DirectionalLight::sample_li(self)
    }

    fn power(&self) -> glam::Vec3 {
        DirectionalLight::power(self)
    }

    fn set_scene_bounds(&mut self, _center: glam::Vec3, radius: f32) {
        self.scene_radius = radius;
    }
}
