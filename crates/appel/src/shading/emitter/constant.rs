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

impl super::EmitterPlugin for ConstantEnvironment {
    const NAME: &'static str = "constant";
    const DELTA: bool = false;
    const INFINITE: bool = true;

    #[inline]
    fn sample_li(&self, _p: glam::Vec3, u: glam::Vec2) -> Option<super::EmitterSample> {
        ConstantEnvironment::sample_li(self, u)
    }

    #[inline]
    fn pdf_li(&self, _p: glam::Vec3, _wi: glam::Vec3, _light_point: glam::Vec3, _light_normal: glam::Vec3) -> f32 {
        ConstantEnvironment::pdf_li(self)
    }

    #[inline]
    fn radiance_env(&self, _d: glam::Vec3) -> glam::Vec3 {
        self.radiance
    }

    fn power(&self) -> glam::Vec3 {
        ConstantEnvironment::power(self)
    }

    fn set_scene_bounds(&mut self, _center: glam::Vec3, radius: f32) {
        self.scene_radius = radius;
    }
}

#[cfg(test)]
mod tests {
    use super::super::Emitter;
    use super::*;
    use crate::shading::chi2::{Chi2Test, Config};

    #[test]
    fn uniform_over_the_sphere() {
        let l = Vec3::new(0.5, 1.0, 2.0);
        let mut e = Emitter::Constant(ConstantEnvironment::new(l));
        let outcome = Chi2Test::new(Config {
            samples: 100_000,
            ..Default::default()
        })
        .run(
            |_, u| e.sample_li(Vec3::ZERO, u).map(|s| s.wi),
            |wi| e.pdf_li(Vec3::ZERO, wi, Vec3::ZERO, Vec3::ZERO),
        );
        assert!(outcome.passed, "{outcome}");
        assert!((outcome.pdf_integral - 1.0).abs() < 1e-4, "{outcome}");
        let s = e.sample_li(Vec3::ONE, Vec2::new(0.2, 0.7)).unwrap();
        assert_eq!(s.weight, e.radiance_env(s.wi) / s.pdf);
        assert!(s.dist.is_infinite() && e.is_infinite());
        e.set_scene_bounds(Vec3::ZERO, 2.0);
        assert!((e.power() - PI * 4.0 * 4.0 * PI * 3.5 / 3.0).abs() < 1e-3);
    }
}
