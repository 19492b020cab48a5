//! Smooth plastic: a diffuse base under a smooth dielectric coating, with the internal
//! scattering between them (Weidlich and Wilkie 2007, "Arbitrarily layered micro-facet surfaces";
//! the model of Mitsuba's `plastic`).

use super::fresnel::{fresnel_dielectric, fresnel_diffuse_reflectance, reflect};
use super::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use super::roughplastic::CoatingTables;
use super::{AnyBsdf, Bsdf, BsdfFlags, BsdfSample, Microfacet, Phong};
use crate::math::{Vec2, Vec3};
use super::{ior_ratio, texture_mean, BsdfMaterial, TextureSource};
use crate::error::Result;
use crate::description::PlasticDesc;
use crate::shading::texture::{TexPoint, Texture};

/// What a plastic material computes once at scene load from its constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlasticParams {
    pub eta: f32,
    pub nonlinear: bool,
    /// Diffuse Fresnel reflectance of the coating seen from inside (`eta` inverted).
    pub fdr_int: f32,
    /// Share of the specular lobe in sampling, before Fresnel weighting.
    pub specular_sampling_weight: f32,
    /// The rough coating of the regularized twin ([`Bsdf::regularized`]).
    pub regularized_coating: &'static CoatingTables,
}

impl PlasticParams {
    /// `eta` is the coating's interior IOR over the exterior's. `diffuse_mean` and
    /// `specular_mean` are the means of the reflectance textures over the whole texture and the
    /// three channels (Mitsuba's `Texture::mean`), `specular_mean = 1` when there is none: they
    /// steer lobe selection as `specular / (diffuse + specular)`, as Mitsuba does.
    pub fn precompute(eta: f32, nonlinear: bool, diffuse_mean: f32, specular_mean: f32) -> Self {
        PlasticParams {
            eta,
            nonlinear,
            fdr_int: fresnel_diffuse_reflectance(1.0 / eta),
            specular_sampling_weight: specular_mean / (diffuse_mean + specular_mean),
            regularized_coating: regularized_coating(eta),
        }
    }
}

/// The coating a smooth one of relative index `eta` regularizes to: GGX of roughness 0.1
/// ([`Microfacet::regularized_smooth`]).
fn regularized_coating(eta: f32) -> &'static CoatingTables {
    let d = Microfacet::regularized_smooth();
    CoatingTables::of(d.kind, d.alpha_u, eta)
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    pub eta: f32,
    pub nonlinear: bool,
    pub fdr_int: f32,
    pub specular_sampling_weight: f32,
    pub regularized_coating: &'static CoatingTables,
    pub diffuse_reflectance: Vec3,
    pub specular_reflectance: Vec3,
}

impl Plastic {
    pub fn new(
        params: &PlasticParams,
        diffuse_reflectance: Vec3,
        specular_reflectance: Vec3,
    ) -> Self {
        Plastic {
            eta: params.eta,
            nonlinear: params.nonlinear,
            fdr_int: params.fdr_int,
            specular_sampling_weight: params.specular_sampling_weight,
            regularized_coating: params.regularized_coating,
            diffuse_reflectance,
            specular_reflectance,
        }
    }

    /// Probability of sampling the specular lobe: the sampling weight times the Fresnel
    /// reflectance, against the diffuse share times the transmittance.
    #[inline]
    fn prob_specular(&self, f_o: f32) -> f32 {
        let s = f_o * self.specular_sampling_weight;
        let d = (1.0 - f_o) * (1.0 - self.specular_sampling_weight);
        s / (s + d)
    }

    /// The diffuse base's albedo after the infinite series of internal reflections at the
    /// coating: `ρ / (1 - F_dr)`, or `ρ / (1 - ρ F_dr)` for the nonlinear colour shift.
    #[inline]
    fn base(&self) -> Vec3 {
        let d = self.diffuse_reflectance;
        if self.nonlinear {
            d / (Vec3::ONE - d * self.fdr_int)
        } else {
            d / (1.0 - self.fdr_int)
        }
    }
}

impl Bsdf for Plastic {
    /// The diffuse base with the smooth coating as a sharp highlight.
    fn whitted(&self) -> Phong {
        Phong::coated(self.diffuse_reflectance, 200.0)
    }

    /// Only the diffuse lobe: light enters the coating (`1 - F(θi)`), is diffused, leaves it
    /// (`1 - F(θo)`), and the radiance leaving is that inside scaled by `1 / η²` (Veach 1997,
    /// section 5.2: the solid angle widens on the way out).
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let f_o = fresnel_dielectric(wo.z, self.eta).0;
        let f_i = fresnel_dielectric(wi.z, self.eta).0;
        self.base()
            * (square_to_cosine_hemisphere_pdf(wi) / (self.eta * self.eta)
                * (1.0 - f_o)
                * (1.0 - f_i))
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let f_o = fresnel_dielectric(wo.z, self.eta).0;
        square_to_cosine_hemisphere_pdf(wi) * (1.0 - self.prob_specular(f_o))
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        (self.eval(wo, wi), self.pdf(wo, wi))
    }

    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let f_o = fresnel_dielectric(wo.z, self.eta).0;
        let prob_specular = self.prob_specular(f_o);
        if u1 < prob_specular {
            return Some(BsdfSample {
                wi: reflect(wo),
                weight: self.specular_reflectance * (f_o / prob_specular),
                pdf: prob_specular,
                eta: 1.0,
                lobe: BsdfFlags::DELTA_REFLECTION,
            });
        }
        let prob_diffuse = 1.0 - prob_specular;
        let wi = square_to_cosine_hemisphere(u2);
        let pdf = prob_diffuse * square_to_cosine_hemisphere_pdf(wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f_i = fresnel_dielectric(wi.z, self.eta).0;
        let weight =
            self.base() * ((1.0 - f_o) * (1.0 - f_i) / (self.eta * self.eta * prob_diffuse));
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            eta: 1.0,
            lobe: BsdfFlags::DIFFUSE_REFLECTION,
        })
    }

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DELTA_REFLECTION | BsdfFlags::DIFFUSE_REFLECTION
    }

    /// The rough plastic of the same base and interface under a GGX coating of roughness 0.1
    /// (Mitsuba's `roughplastic`, the rough twin of this model; pbrt-v4 has no plastic, but
    /// regularizes its `coateddiffuse`'s smooth interface the same way), with the same lobe
    /// sampling weight and colour shift, and this coating's internal reflectance, so that the
    /// diffuse base stays as bright (see [`CoatingTables::rough_plastic`]).
    fn regularized(&self) -> AnyBsdf {
        AnyBsdf::RoughPlastic(self.regularized_coating.rough_plastic(
            true,
            self.nonlinear,
            self.specular_sampling_weight,
            self.fdr_int,
            self.diffuse_reflectance,
            self.specular_reflectance,
        ))
    }
}

/// [`Plastic`] with its reflectances textured and its constants precomputed.
#[derive(Clone, Debug)]
pub struct PlasticMaterial {
    pub params: PlasticParams,
    pub diffuse: Texture,
    pub specular: Texture,
}

impl BsdfMaterial for PlasticMaterial {
    type Desc = PlasticDesc;
    type Bsdf = Plastic;

    fn build(d: &PlasticDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        let diffuse = textures.texture(&d.diffuse_reflectance)?;
        let specular = textures.texture(&d.specular_reflectance)?;
        Ok(PlasticMaterial {
            params: PlasticParams::precompute(
                ior_ratio(&d.int_ior, &d.ext_ior)?,
                d.nonlinear,
                texture_mean(&diffuse),
                texture_mean(&specular),
            ),
            diffuse,
            specular,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> Plastic {
        Plastic::new(&self.params, self.diffuse.eval_at(p), self.specular.eval_at(p))
    }
}
