//! A rough conductor: Cook-Torrance microfacet reflection with conductor Fresnel (Walter et al.
//! 2007, eq. 20), Mitsuba's `roughconductor`.

use super::fresnel::{fresnel_conductor, reflect_about};
use super::microfacet::Microfacet;
use super::{AnyBsdf, Phong, Bsdf, BsdfFlags, BsdfSample};
use crate::math::{Vec2, Vec3};
use super::conductor::metal;
use super::{BsdfMaterial, Roughness, TextureSource};
use crate::error::Result;
use crate::description::RoughConductorDesc;
use crate::shading::texture::{TexPoint, Texture};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughConductor {
    pub distribution: Microfacet,
    pub eta: Vec3,
    pub k: Vec3,
    pub specular_reflectance: Vec3,
}

impl RoughConductor {
    pub fn new(distribution: Microfacet, eta: Vec3, k: Vec3, specular_reflectance: Vec3) -> Self {
        RoughConductor {
            distribution,
            eta,
            k,
            specular_reflectance,
        }
    }

    #[inline]
    fn fresnel(&self, cos_theta: f32) -> Vec3 {
        self.specular_reflectance * fresnel_conductor(cos_theta, self.eta, self.k)
    }
}

impl Bsdf for RoughConductor {
    /// A mirror tinted by the specular reflectance: Whitted's recursion follows delta
    /// directions only.
    fn whitted(&self) -> Phong {
        Phong::mirror(self.specular_reflectance)
    }

    /// `F D G / (4 cos θo)`: the `cos θi` of the convention cancels the denominator's.
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (wo + wi).normalize();
        let d = self.distribution.d(h);
        if d == 0.0 {
            return Vec3::ZERO;
        }
        let g = self.distribution.g(wo, wi, h);
        self.fresnel(wo.dot(h)) * (d * g / (4.0 * wo.z))
    }

    /// The microfacet density times the Jacobian `1 / (4 wi·h)` of the reflection about `h`.
    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let h = (wo + wi).normalize();
        // The sides must agree, as smith_g1 demands in eval and sample.
        if wo.z <= 0.0 || wi.z <= 0.0 || wo.dot(h) <= 0.0 || wi.dot(h) <= 0.0 {
            return 0.0;
        }
        let d = &self.distribution;
        if d.sample_visible {
            d.d(h) * d.smith_g1(wo, h) / (4.0 * wo.z)
        } else {
            d.pdf(wo, h) / (4.0 * wi.dot(h))
        }
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let h = (wo + wi).normalize();
        if wo.z <= 0.0 || wi.z <= 0.0 || wo.dot(h) <= 0.0 || wi.dot(h) <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let dist = &self.distribution;
        let d = dist.d(h);
        if d == 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let g1_o = dist.smith_g1(wo, h);
        let value = self.fresnel(wo.dot(h)) * (d * g1_o * dist.smith_g1(wi, h) / (4.0 * wo.z));
        let pdf = if dist.sample_visible {
            d * g1_o / (4.0 * wo.z)
        } else {
            dist.pdf(wo, h) / (4.0 * wi.dot(h))
        };
        (value, pdf)
    }

    #[inline]
    fn sample(&self, wo: Vec3, _u1: f32, u2: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let d = &self.distribution;
        let (m, pdf_m) = d.sample(wo, u2);
        let wi = reflect_about(wo, m);
        if pdf_m == 0.0 || wi.z <= 0.0 {
            return None;
        }
        // eval / pdf: for visible normals D G1(wo) cancels, leaving G1(wi) (Heitz 2014, eq. 19).
        let g = if d.sample_visible {
            d.smith_g1(wi, m)
        } else {
            d.g(wo, wi, m) * wo.dot(m) / (wo.z * m.z)
        };
        if g <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.fresnel(wo.dot(m)) * g,
            pdf: pdf_m / (4.0 * wi.dot(m)),
            eta: 1.0,
            lobe: BsdfFlags::GLOSSY_REFLECTION,
        })
    }

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::GLOSSY_REFLECTION
    }

    /// The same BSDF with its roughness widened by pbrt-v4's rule ([`Microfacet::regularized`]);
    /// unchanged where both roughnesses are 0.3 or more.
    fn regularized(&self) -> AnyBsdf {
        AnyBsdf::RoughConductor(RoughConductor {
            distribution: self.distribution.regularized(),
            ..*self
        })
    }
}

/// [`RoughConductor`] with its roughness and reflectance factor textured.
#[derive(Clone, Debug)]
pub struct RoughConductorMaterial {
    pub roughness: Roughness,
    pub eta: Vec3,
    pub k: Vec3,
    pub specular: Texture,
}

impl BsdfMaterial for RoughConductorMaterial {
    type Desc = RoughConductorDesc;
    type Bsdf = RoughConductor;

    fn build(d: &RoughConductorDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        let (eta, k) = metal(d.material.as_deref(), d.eta, d.k)?;
        Ok(RoughConductorMaterial {
            roughness: Roughness::build(d.distribution.into(), d.alphas(), d.sample_visible, textures)?,
            eta,
            k,
            specular: textures.texture(&d.specular_reflectance)?,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> RoughConductor {
        RoughConductor::new(self.roughness.at(p), self.eta, self.k, self.specular.eval_at(p))
    }
}
