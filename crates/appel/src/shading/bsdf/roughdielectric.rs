//! A rough dielectric interface: microfacet reflection and refraction (Walter et al. 2007,
//! "Microfacet models for refraction through rough surfaces"), Mitsuba's `roughdielectric`.

use super::fresnel::{fresnel_dielectric, reflect_about, refract_about};
use super::microfacet::Microfacet;
use super::{AnyBsdf, Phong, mulsign, Bsdf, BsdfFlags, BsdfSample};
use crate::math::{Vec2, Vec3};
use super::{ior_ratio, BsdfMaterial, Roughness, TextureSource};
use crate::error::Result;
use crate::description::RoughDielectricDesc;
use crate::shading::texture::{TexPoint, Texture};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    pub distribution: Microfacet,
    /// Interior IOR over exterior IOR.
    pub eta: f32,
    pub specular_reflectance: Vec3,
    pub specular_transmittance: Vec3,
}

/// What eval and pdf share for one pair of directions.
struct Geometry {
    reflect: bool,
    /// Relative IOR of the crossing seen from `wo`'s side.
    eta: f32,
    /// The (generalized) half vector, on the outside (`m.z >= 0`).
    m: Vec3,
}

impl RoughDielectric {
    pub fn new(
        distribution: Microfacet,
        eta: f32,
        specular_reflectance: Vec3,
        specular_transmittance: Vec3,
    ) -> Self {
        RoughDielectric {
            distribution,
            eta,
            specular_reflectance,
            specular_transmittance,
        }
    }

    /// Walter et al.'s widening of the sampled roughness for sampling all normals (section 5.3);
    /// visible normals need none.
    #[inline]
    fn sample_distribution(&self, cos_theta_o: f32) -> Microfacet {
        if self.distribution.sample_visible {
            self.distribution
        } else {
            self.distribution
                .scaled(1.2 - 0.2 * cos_theta_o.abs().sqrt())
        }
    }

    /// The half vector of the pair: `wo + wi` for reflection, `wo + η wi` for refraction
    /// (Walter et al. 2007, eqs. 13 and 16), turned to the outside.
    #[inline]
    fn geometry(&self, wo: Vec3, wi: Vec3) -> Geometry {
        let reflect = wo.z * wi.z > 0.0;
        let eta = if wo.z > 0.0 { self.eta } else { 1.0 / self.eta };
        let m = (wo + wi * if reflect { 1.0 } else { eta }).normalize();
        Geometry {
            reflect,
            eta,
            m: mulsign(m, m.z),
        }
    }

    #[inline]
    fn value(&self, wo: Vec3, wi: Vec3, g: &Geometry) -> Vec3 {
        let dist = &self.distribution;
        let m = g.m;
        let d = dist.d(m);
        let f = fresnel_dielectric(wo.dot(m), self.eta).0;
        let gg = dist.g(wo, wi, m);
        if g.reflect {
            // Walter et al. 2007, eq. 20, times |cos θi|.
            self.specular_reflectance * (f * d * gg / (4.0 * wo.z.abs()))
        } else {
            // Eq. 21 times |cos θi|, with the radiance scaling 1 / η² of the crossing that the
            // paper leaves out (Veach 1997, section 5.2).
            let (om, im) = (wo.dot(m), wi.dot(m));
            let denom = om + g.eta * im;
            let scale = 1.0 / (g.eta * g.eta);
            let v = scale * (1.0 - f) * d * gg * g.eta * g.eta * om * im / (wo.z * denom * denom);
            self.specular_transmittance * v.abs()
        }
    }

    #[inline]
    fn density(&self, wo: Vec3, wi: Vec3, g: &Geometry) -> f32 {
        let m = g.m;
        let (om, im) = (wo.dot(m), wi.dot(m));
        // The sides must agree, as smith_g1 demands in eval and sample.
        if om * wo.z <= 0.0 || im * wi.z <= 0.0 {
            return 0.0;
        }
        // Jacobians of the half-vector maps (Walter et al. 2007, eqs. 14 and 17).
        let dwh_dwi = if g.reflect {
            1.0 / (4.0 * im)
        } else {
            let denom = om + g.eta * im;
            g.eta * g.eta * im / (denom * denom)
        };
        let prob = self.sample_distribution(wo.z).pdf(mulsign(wo, wo.z), m);
        let f = fresnel_dielectric(om, self.eta).0;
        prob * if g.reflect { f } else { 1.0 - f } * dwh_dwi.abs()
    }
}

impl Bsdf for RoughDielectric {
    /// Smooth glass of the same index: Whitted's recursion follows delta directions only.
    fn whitted(&self) -> Phong {
        Phong::glass(self.eta)
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z == 0.0 {
            return Vec3::ZERO;
        }
        self.value(wo, wi, &self.geometry(wo, wi))
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z == 0.0 {
            return 0.0;
        }
        self.density(wo, wi, &self.geometry(wo, wi))
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        if wo.z == 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let g = self.geometry(wo, wi);
        let pdf = self.density(wo, wi, &g);
        if pdf == 0.0 {
            // Where the sides disagree the shadowing term zeroes the value as well.
            return (Vec3::ZERO, 0.0);
        }
        (self.value(wo, wi, &g), pdf)
    }

    /// A microfacet normal from the distribution seen from `wo`'s side, then reflection about it
    /// with probability `F(wo · m)`, else refraction through it.
    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        let cos_theta_o = wo.z;
        if cos_theta_o == 0.0 {
            return None;
        }
        let dist = &self.distribution;
        let (m, pdf_m) = self
            .sample_distribution(cos_theta_o)
            .sample(mulsign(wo, cos_theta_o), u2);
        if pdf_m == 0.0 {
            return None;
        }
        let (f, cos_theta_t, eta_it, eta_ti) = fresnel_dielectric(wo.dot(m), self.eta);
        let (wi, mut weight, pdf, eta, lobe, dwh_dwi);
        if u1 <= f {
            wi = reflect_about(wo, m);
            weight = self.specular_reflectance;
            pdf = pdf_m * f;
            eta = 1.0;
            lobe = BsdfFlags::GLOSSY_REFLECTION;
            dwh_dwi = 1.0 / (4.0 * wi.dot(m));
        } else {
            wi = refract_about(wo, m, cos_theta_t, eta_ti);
            weight = self.specular_transmittance * (eta_ti * eta_ti);
            pdf = pdf_m * (1.0 - f);
            eta = eta_it;
            lobe = BsdfFlags::GLOSSY_TRANSMISSION;
            let denom = wo.dot(m) + eta * wi.dot(m);
            dwh_dwi = eta * eta * wi.dot(m) / (denom * denom);
        }
        // eval / pdf: for visible normals D G1(wo) cancels, leaving G1(wi) (Heitz 2014, eq. 19);
        // otherwise Walter et al. 2007, eq. 41, which assumes the sampled D is the evaluated one:
        // with the widened sampling distribution it is not, and the weight is off by the ratio of
        // the two D, a bias Mitsuba has and which is kept here so that images agree.
        let g = if dist.sample_visible {
            dist.smith_g1(wi, m)
        } else {
            dist.g(wo, wi, m) * wo.dot(m) / (cos_theta_o * m.z)
        };
        weight *= g;
        let pdf = pdf * dwh_dwi.abs();
        if weight == Vec3::ZERO || pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            eta,
            lobe,
        })
    }

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::GLOSSY_TRANSMISSION
    }

    /// The same BSDF with its roughness widened by pbrt-v4's rule ([`Microfacet::regularized`]);
    /// unchanged where both roughnesses are 0.3 or more.
    fn regularized(&self) -> AnyBsdf {
        AnyBsdf::RoughDielectric(RoughDielectric {
            distribution: self.distribution.regularized(),
            ..*self
        })
    }
}

/// [`RoughDielectric`] with its roughness and factors textured.
#[derive(Clone, Debug)]
pub struct RoughDielectricMaterial {
    pub roughness: Roughness,
    pub eta: f32,
    pub reflectance: Texture,
    pub transmittance: Texture,
}

impl BsdfMaterial for RoughDielectricMaterial {
    type Desc = RoughDielectricDesc;
    type Bsdf = RoughDielectric;

    fn build(d: &RoughDielectricDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        Ok(RoughDielectricMaterial {
            roughness: Roughness::build(d.distribution.into(), d.alphas(), d.sample_visible, textures)?,
            eta: ior_ratio(&d.int_ior, &d.ext_ior)?,
            reflectance: textures.texture(&d.specular_reflectance)?,
            transmittance: textures.texture(&d.specular_transmittance)?,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> RoughDielectric {
        RoughDielectric::new(
            self.roughness.at(p),
            self.eta,
            self.reflectance.eval_at(p),
            self.transmittance.eval_at(p),
        )
    }
}
