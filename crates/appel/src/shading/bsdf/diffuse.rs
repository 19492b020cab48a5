//! Ideal diffuse (Lambertian) reflection, Mitsuba's `diffuse`.

use super::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use super::{BsdfFlags, BsdfSample};
use crate::math::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse {
    pub reflectance: Vec3,
}

impl Diffuse {
    pub fn new(reflectance: Vec3) -> Self {
        Diffuse { reflectance }
    }

    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.reflectance * (FRAC_1_PI * wi.z)
    }

    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        square_to_cosine_hemisphere_pdf(wi)
    }

    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        (self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// Cosine-weighted: the weight is the reflectance.
    #[inline]
    pub fn sample(&self, wo: Vec3, _u1: f32, u2: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = square_to_cosine_hemisphere(u2);
        let pdf = square_to_cosine_hemisphere_pdf(wi);
        (pdf > 0.0).then_some(BsdfSample {
            wi,
            weight: self.reflectance,
            pdf,
            eta: 1.0,
            lobe: BsdfFlags::DIFFUSE_REFLECTION,
        })
    }

    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
}
