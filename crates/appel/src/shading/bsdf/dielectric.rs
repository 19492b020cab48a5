//! A smooth dielectric interface (glass, water): Fresnel-weighted delta reflection and
//! refraction, Mitsuba's `dielectric`.

use super::fresnel::{fresnel_dielectric, reflect, refract};
use super::{AnyBsdf, Bsdf, BsdfFlags, BsdfSample, Microfacet, Phong, RoughDielectric};
use crate::math::{Vec2, Vec3};
use super::{ior_ratio, BsdfMaterial, TextureSource};
use crate::error::Result;
use crate::description::DielectricDesc;
use crate::shading::texture::{TexPoint, Texture};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Interior IOR over exterior IOR.
    pub eta: f32,
    pub specular_reflectance: Vec3,
    pub specular_transmittance: Vec3,
}

impl Dielectric {
    pub fn new(eta: f32, specular_reflectance: Vec3, specular_transmittance: Vec3) -> Self {
        Dielectric {
            eta,
            specular_reflectance,
            specular_transmittance,
        }
    }
}

impl Bsdf for Dielectric {
    /// Fresnel-weighted reflection and refraction.
    fn whitted(&self) -> Phong {
        Phong::glass(self.eta)
    }

    /// Reflection with probability `F`, else refraction, so the weight carries no Fresnel factor;
    /// refracted radiance is scaled by `1 / eta²` of the crossing (Veach 1997, section 5.2: radiance
    /// is compressed into the smaller solid angle of the denser medium).
    #[inline]
    fn sample(&self, wo: Vec3, u1: f32, _u2: Vec2) -> Option<BsdfSample> {
        let (r, cos_theta_t, eta_it, eta_ti) = fresnel_dielectric(wo.z, self.eta);
        Some(if u1 <= r {
            BsdfSample {
                wi: reflect(wo),
                weight: self.specular_reflectance,
                pdf: r,
                eta: 1.0,
                lobe: BsdfFlags::DELTA_REFLECTION,
            }
        } else {
            BsdfSample {
                wi: refract(wo, cos_theta_t, eta_ti),
                weight: self.specular_transmittance * (eta_ti * eta_ti),
                pdf: 1.0 - r,
                eta: eta_it,
                lobe: BsdfFlags::DELTA_TRANSMISSION,
            }
        })
    }

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DELTA_REFLECTION | BsdfFlags::DELTA_TRANSMISSION
    }

    /// The rough dielectric of the same interface, GGX of roughness 0.1 (pbrt-v4's
    /// `DielectricBxDF::Regularize` of a smooth interface). An index-matched interface
    /// (`eta == 1`) stays as it is, as pbrt-v4 keeps it specular at any roughness: light crosses
    /// it undeviated, and the rough form's generalized half vector would vanish.
    fn regularized(&self) -> AnyBsdf {
        if self.eta == 1.0 {
            return AnyBsdf::Dielectric(*self);
        }
        AnyBsdf::RoughDielectric(RoughDielectric::new(
            Microfacet::regularized_smooth(),
            self.eta,
            self.specular_reflectance,
            self.specular_transmittance,
        ))
    }
}

/// [`Dielectric`] with its reflectance and transmittance factors textured.
#[derive(Clone, Debug)]
pub struct DielectricMaterial {
    /// Interior IOR over exterior IOR.
    pub eta: f32,
    pub reflectance: Texture,
    pub transmittance: Texture,
}

impl BsdfMaterial for DielectricMaterial {
    type Desc = DielectricDesc;
    type Bsdf = Dielectric;

    fn build(d: &DielectricDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        Ok(DielectricMaterial {
            eta: ior_ratio(&d.int_ior, &d.ext_ior)?,
            reflectance: textures.texture(&d.specular_reflectance)?,
            transmittance: textures.texture(&d.specular_transmittance)?,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> Dielectric {
        Dielectric::new(self.eta, self.reflectance.eval_at(p), self.transmittance.eval_at(p))
    }
}
