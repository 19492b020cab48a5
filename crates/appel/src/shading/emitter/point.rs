//! Mitsuba's `point` emitter: an isotropic point of radiant intensity.

use super::emission::uniform_sphere;
use super::{EmitterRay, EmitterSample};
use glam::Vec3;
use std::f32::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    /// Radiant intensity (W/sr per channel).
    pub intensity: Vec3,
}

impl PointLight {
    pub fn sample_li(&self, p: Vec3) -> Option<EmitterSample> {
        let to = self.position - p;
        let dist2 = to.length_squared();
        if dist2.is_nan() || dist2 <= 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        Some(EmitterSample {
            wi: to / dist,
            dist,
            weight: self.intensity / dist2,
            pdf: 1.0,
            delta: true,
        })
    }

    /// Φ = 4π I.
    pub fn power(&self) -> Vec3 {
        4.0 * PI * self.intensity
    }
}

impl super::EmitterPlugin for PointLight {
    const NAME: &'static str = "point";
    const DELTA: bool = true;
    const INFINITE: bool = false;

    #[inline]
    fn position(&self) -> Option<Vec3> {
        Some(self.position)
    }

    fn sample_li(&self, p: glam::Vec3, _u: glam::Vec2) -> Option<super::EmitterSample> {
        PointLight::sample_li(self, p)
    }

    fn pdf_ray_dir(&self, _normal: Vec3, _dir: Vec3) -> f32 {
        1.0 / (4.0 * PI)
    }

    /// Uniform directions: the ray carries `4π I`.
    fn sample_ray(&self, _u_pos: glam::Vec2, u_dir: glam::Vec2) -> Option<EmitterRay> {
        let (dir, pdf_dir) = uniform_sphere(u_dir);
        Some(EmitterRay {
            origin: self.position,
            origin_error: Vec3::ZERO,
            dir,
            normal: Vec3::ZERO,
            uv: glam::Vec2::ZERO,
            weight: self.intensity / pdf_dir,
            pdf_pos: 1.0,
            pdf_dir,
        })
    }

    fn power(&self) -> glam::Vec3 {
        PointLight::power(self)
    }
}
