//! Mitsuba's `null` BSDF: the surface is only the boundary of a medium. Every ray goes straight
//! through with weight 1 (the lobe [`BsdfFlags::NULL`], which the volumetric path tracer does
//! not count as a bounce and lets shadow rays cross); the other integrators see a delta
//! transmission of index 1.

use super::{Bsdf, BsdfFlags, BsdfMaterial, BsdfSample, Phong, TextureSource};
use crate::description::NullDesc;
use crate::error::Result;
use crate::math::{Vec2, Vec3};
use crate::shading::texture::TexPoint;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Null;

impl Bsdf for Null {
    #[inline]
    fn sample(&self, wo: Vec3, _u1: f32, _u2: Vec2) -> Option<BsdfSample> {
        Some(BsdfSample {
            wi: -wo,
            weight: Vec3::ONE,
            pdf: 1.0,
            eta: 1.0,
            lobe: BsdfFlags::NULL,
        })
    }

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::NULL
    }

    /// Refraction of index 1 with no Fresnel reflection: straight through.
    fn whitted(&self) -> Phong {
        Phong {
            fresnel: false,
            ..Phong::glass(1.0)
        }
    }

    #[inline]
    fn null_transmission(&self, _wo: Vec3) -> Vec3 {
        Vec3::ONE
    }
}

#[derive(Clone, Debug)]
pub struct NullMaterial;

impl BsdfMaterial for NullMaterial {
    type Desc = NullDesc;
    type Bsdf = Null;

    fn build(_d: &NullDesc, _textures: &mut dyn TextureSource) -> Result<Self> {
        Ok(NullMaterial)
    }

    #[inline]
    fn at(&self, _p: &TexPoint) -> Null {
        Null
    }
}
