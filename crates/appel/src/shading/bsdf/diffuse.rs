//! Ideal diffuse (Lambertian) reflection, Mitsuba's `diffuse`.

use super::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use super::{Phong, Bsdf, BsdfFlags, BsdfSample};
use crate::math::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;
use super::BsdfMaterial;
use super::TextureSource;
use crate::error::Result;
use crate::description::DiffuseDesc;
use crate::shading::texture::{TexPoint, Texture};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse {
    pub reflectance: Vec3,
}

impl Diffuse {
    pub fn new(reflectance: Vec3) -> Self {
        Diffuse { reflectance }
    }
}

impl Bsdf for Diffuse {
    /// Lambertian reflection is Whitted's diffuse lobe.
    fn whitted(&self) -> Phong {
        Phong::matte(self.reflectance)
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.reflectance * (FRAC_1_PI * wi.z)
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        square_to_cosine_hemisphere_pdf(wi)
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        (self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// Cosine-weighted: the weight is the reflectance.
    #[inline]
    fn sample(&self, wo: Vec3, _u1: f32, u2: Vec2) -> Option<BsdfSample> {
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

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
}

/// [`Diffuse`] with its reflectance textured.
#[derive(Clone, Debug)]
pub struct DiffuseMaterial {
    pub reflectance: Texture,
}

impl BsdfMaterial for DiffuseMaterial {
    type Desc = DiffuseDesc;
    type Bsdf = Diffuse;

    fn build(d: &DiffuseDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        Ok(DiffuseMaterial {
            reflectance: textures.texture(&d.reflectance)?,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> Diffuse {
        Diffuse::new(self.reflectance.eval_at(p).clamp(Vec3::ZERO, Vec3::ONE))
    }
}
