//! A smooth conductor (an ideal mirror with the Fresnel reflectance of a complex IOR), Mitsuba's
//! `conductor`.

use super::fresnel::{fresnel_conductor, reflect};
use super::{AnyBsdf, Bsdf, BsdfFlags, BsdfSample, Microfacet, Phong, RoughConductor};
use crate::math::{Vec2, Vec3};
use super::{BsdfMaterial, TextureSource};
use crate::error::{Error, Result};
use crate::description::ConductorDesc;
use crate::shading::spectra;
use crate::shading::texture::{TexPoint, Texture};

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
}

impl Bsdf for Conductor {
    /// A mirror tinted by the specular reflectance.
    fn whitted(&self) -> Phong {
        Phong::mirror(self.specular_reflectance)
    }

    #[inline]
    fn sample(&self, wo: Vec3, _u1: f32, _u2: Vec2) -> Option<BsdfSample> {
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

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DELTA_REFLECTION
    }

    /// The rough conductor of the same Fresnel, GGX of roughness 0.1 (pbrt-v4's
    /// `ConductorBxDF::Regularize` of a smooth metal).
    fn regularized(&self) -> AnyBsdf {
        AnyBsdf::RoughConductor(RoughConductor::new(
            Microfacet::regularized_smooth(),
            self.eta,
            self.k,
            self.specular_reflectance,
        ))
    }
}

/// [`Conductor`] with its reflectance factor textured.
#[derive(Clone, Debug)]
pub struct ConductorMaterial {
    pub eta: Vec3,
    pub k: Vec3,
    pub specular: Texture,
}

impl BsdfMaterial for ConductorMaterial {
    type Desc = ConductorDesc;
    type Bsdf = Conductor;

    fn build(d: &ConductorDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        let (eta, k) = metal(d.material.as_deref(), d.eta, d.k)?;
        Ok(ConductorMaterial {
            eta,
            k,
            specular: textures.texture(&d.specular_reflectance)?,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> Conductor {
        Conductor::new(self.eta, self.k, self.specular.eval_at(p))
    }
}

/// A metal's complex index: `eta` and `k` where given, the rest from the named metal (none: a
/// perfect mirror).
pub(crate) fn metal(
    material: Option<&str>,
    eta: Option<[f32; 3]>,
    k: Option<[f32; 3]>,
) -> Result<(Vec3, Vec3)> {
    if let (Some(eta), Some(k)) = (eta, k) {
        return Ok((eta.into(), k.into()));
    }
    let name = material.unwrap_or(spectra::NO_CONDUCTOR);
    let (e, kk) = spectra::conductor(name).ok_or_else(|| {
        Error::Invalid(format!(
            "unknown conductor `{name}`, expected one of: {}",
            spectra::CONDUCTOR_NAMES.join(", ")
        ))
    })?;
    Ok((eta.map_or(e, Vec3::from), k.map_or(kk, Vec3::from)))
}
