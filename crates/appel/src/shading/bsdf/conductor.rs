//! A smooth conductor (an ideal mirror with the Fresnel reflectance of a complex IOR), Mitsuba's
//! `conductor`.

use super::fresnel::{fresnel_conductor, reflect};
use super::{BsdfFlags, BsdfSample};
use crate::math::{Vec2, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    /// Real part of the relative IOR, per channel (see [`crate::shading::spectra::conductor`]).
    pub eta: Vec3,
    /// Imaginary part (absorption coefficient).
    pub k: Vec3,
    /// A factor on the Fresnel reflectance (1 is physical).
    pub specular_reflectance: Vec3,
}

impl Conductor {
    pub fn new(eta: Vec3, k: Vec3, specular_reflectance: Vec3) -> Self {
        Conductor {
            eta,
            k,
            specular_reflectance,
        }
    }

    #[inline]
    pub fn eval(&self, _wo: Vec3, _wi: Vec3) -> Vec3 {
        Vec3::ZERO
    }

    #[inline]
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    #[inline]
    pub fn eval_pdf(&self, _wo: Vec3, _wi: Vec3) -> (Vec3, f32) {
        (Vec3::ZERO, 0.0)
    }

    #[inline]
    pub fn sample(&self, wo: Vec3, _u1: f32, _u2: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: reflect(wo),
            weight: self.specular_reflectance * fresnel_conductor(wo.z, self.eta, self.k),
            pdf: 1.0,
            eta: 1.0,
            lobe: BsdfFlags::DELTA_REFLECTION,
        })
    }

    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::DELTA_REFLECTION
    }
}
