//! Mitsuba 3's `principledthin` BSDF: Burley's thin-surface variant of the Disney BSDF (2015,
//! section 4: a sheet without interior, light passing straight through, its roughness scaled by
//! the IOR, Figure 15), as Mitsuba implements it. The sheet is symmetric: directions are mirrored
//! to the side of `wo` first. Lobes: specular reflection and "refraction" (the reflection lobe
//! mirrored through the sheet, weighted by `spec_trans`), Burley's diffuse with sheen, and a
//! Lambertian transmission (`diff_trans`, from 0 to 2, halved as in Mitsuba).

use super::fresnel::{fresnel_dielectric, reflect_about};
use super::principled::{
    disney_diffuse, distribution, microfacet_compatible, regularized_times, schlick_fresnel,
    schlick_r0, schlick_weight, sheen_color, tint,
};
use super::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use super::{AnyBsdf, Microfacet, Phong, mulsign, Bsdf, BsdfFlags, BsdfSample};
use crate::math::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;
use super::{BsdfMaterial, TextureSource};
use crate::error::Result;
use crate::description::{PrincipledThinDesc, TextureDesc};
use crate::shading::texture::{TexPoint, Texture};

/// The per-hit values of a thin principled material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipledThin {
    pub base_color: Vec3,
    pub roughness: f32,
    pub anisotropic: f32,
    pub spec_trans: f32,
    pub spec_tint: f32,
    pub sheen: f32,
    pub sheen_tint: f32,
    pub flatness: f32,
    /// Mitsuba's `diff_trans` (0 to 2).
    pub diff_trans: f32,
    /// The sheet's IOR.
    pub eta: f32,
    /// Sampling weights of specular reflection and transmission, diffuse reflection and
    /// transmission (Mitsuba's `*_sampling_rate`).
    pub spec_reflect_rate: f32,
    pub spec_trans_rate: f32,
    pub diffuse_reflect_rate: f32,
    pub diffuse_trans_rate: f32,
    /// How many times [`Bsdf::regularized`] has widened the two microfacet lobes (see
    /// [`super::Principled::regularizations`]).
    pub regularizations: u8,
}

struct Probabilities {
    spec_reflect: f32,
    spec_trans: f32,
    diffuse_reflect: f32,
    diffuse_trans: f32,
}

impl PrincipledThin {
    fn probabilities(&self) -> Probabilities {
        let dt = 0.5 * self.diff_trans;
        let mut p = Probabilities {
            spec_reflect: 0.5 * self.spec_trans * self.spec_reflect_rate,
            spec_trans: 0.5 * self.spec_trans * self.spec_trans_rate,
            diffuse_reflect: self.diffuse_reflect_rate * (1.0 - self.spec_trans) * (1.0 - dt),
            diffuse_trans: self.diffuse_trans_rate * (1.0 - self.spec_trans) * dt,
        };
        let total = p.spec_reflect + p.spec_trans + p.diffuse_reflect + p.diffuse_trans;
        if total > 0.0 {
            p.spec_reflect /= total;
            p.spec_trans /= total;
            p.diffuse_reflect /= total;
            p.diffuse_trans /= total;
        }
        p
    }

    /// Burley's IOR-scaled roughness of the transmission lobe (2015, Figure 15).
    /// Widened as [`Self::regularizations`] says, as is the reflection lobe's.
    pub(crate) fn transmission_distribution(&self) -> Microfacet {
        regularized_times(
            distribution((0.65 * self.eta - 0.35) * self.roughness, self.anisotropic),
            self.regularizations,
        )
    }

    /// The GGX distribution of the specular reflection.
    #[inline]
    pub(crate) fn reflection_distribution(&self) -> Microfacet {
        regularized_times(
            distribution(self.roughness, self.anisotropic),
            self.regularizations,
        )
    }

    /// `wo` and `wi` mirrored to `wo`'s side, and the half vector of `wo` with `wi` reflected
    /// back above the sheet.
    #[inline]
    fn frame(&self, wo: Vec3, wi: Vec3) -> (Vec3, Vec3, Vec3) {
        let o = mulsign(wo, wo.z);
        let i = mulsign(wi, wo.z);
        let h = (o + Vec3::new(i.x, i.y, i.z.abs())).normalize();
        (o, i, h)
    }
}

impl Bsdf for PrincipledThin {
    /// The diffuse base.
    fn whitted(&self) -> Phong {
        Phong::matte(self.base_color)
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z == 0.0 {
            return Vec3::ZERO;
        }
        let dt = 0.5 * self.diff_trans;
        let (o, i, h) = self.frame(wo, wi);
        let (cos_o, cos_i) = (o.z, i.z);
        let reflect = cos_i > 0.0;
        let refract = cos_i < 0.0;
        let mut value = Vec3::ZERO;
        if self.spec_trans > 0.0 {
            let f_d = fresnel_dielectric(o.dot(h), self.eta).0;
            if reflect && microfacet_compatible(h, o, i, o.z, true) {
                let dist = self.reflection_distribution();
                // The dielectric Fresnel blended by `spec_tint` with Schlick's of the tinted R0.
                let schlick = if self.spec_tint > 0.0 {
                    schlick_fresnel(
                        tint(self.base_color) * schlick_r0(self.eta),
                        o.dot(h),
                        self.eta,
                    )
                } else {
                    Vec3::ZERO
                };
                let f = Vec3::splat(f_d) + (schlick - Vec3::splat(f_d)) * self.spec_tint;
                value += f * (self.spec_trans * dist.d(h) * dist.g(o, i, h) / (4.0 * cos_o));
            }
            if refract && microfacet_compatible(h, o, i, o.z, false) {
                let dist = self.transmission_distribution();
                value += self.base_color
                    * (self.spec_trans * (1.0 - f_d) * dist.d(h) * dist.g(o, i, h) / (4.0 * cos_o));
            }
        }
        if reflect && self.spec_trans < 1.0 && dt < 1.0 {
            let cos_d = h.dot(i);
            let diffuse = disney_diffuse(self.roughness, self.flatness, cos_o, cos_i, cos_d);
            let w = (1.0 - self.spec_trans) * (1.0 - dt) * cos_i;
            value += self.base_color * (w * FRAC_1_PI * diffuse);
            if self.sheen > 0.0 {
                let fd = schlick_weight(cos_d.abs());
                value += sheen_color(self.base_color, self.sheen_tint) * (self.sheen * fd * w);
            }
        }
        if refract && self.spec_trans < 1.0 && dt > 0.0 {
            value += self.base_color * ((1.0 - self.spec_trans) * dt * FRAC_1_PI * cos_i.abs());
        }
        value
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z == 0.0 {
            return 0.0;
        }
        let (o, i, h) = self.frame(wo, wi);
        let reflect = i.z > 0.0;
        let refract = i.z < 0.0;
        let p = self.probabilities();
        let mut pdf = 0.0;
        if self.spec_trans > 0.0 {
            // The transmitted direction is a reflection mirrored through the sheet: the
            // reflection's Jacobian 1 / (4 |i_r · h|).
            let jacobian = (1.0 / (4.0 * Vec3::new(i.x, i.y, i.z.abs()).dot(h))).abs();
            if reflect && microfacet_compatible(h, o, i, o.z, true) {
                let dist = self.reflection_distribution();
                pdf += p.spec_reflect * dist.pdf(o, h) * jacobian;
            }
            if refract && microfacet_compatible(h, o, i, o.z, false) {
                pdf += p.spec_trans * self.transmission_distribution().pdf(o, h) * jacobian;
            }
        }
        if reflect {
            pdf += p.diffuse_reflect * square_to_cosine_hemisphere_pdf(i);
        }
        if refract {
            pdf += p.diffuse_trans * square_to_cosine_hemisphere_pdf(-i);
        }
        pdf
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        (self.eval(wo, wi), self.pdf(wo, wi))
    }

    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let o = mulsign(wo, wo.z);
        let p = self.probabilities();
        let (i, lobe) = if u1 < p.spec_reflect {
            let (m, _) = self.reflection_distribution().sample(o, u2);
            let i = reflect_about(o, m);
            if i.z <= 0.0 || !microfacet_compatible(m, o, i, o.z, true) {
                return None;
            }
            (i, BsdfFlags::GLOSSY_REFLECTION)
        } else if u1 < p.spec_reflect + p.spec_trans {
            let (m, _) = self.transmission_distribution().sample(o, u2);
            let r = reflect_about(o, m);
            let i = Vec3::new(r.x, r.y, -r.z);
            if i.z >= 0.0 || !microfacet_compatible(m, o, i, o.z, false) {
                return None;
            }
            (i, BsdfFlags::GLOSSY_TRANSMISSION)
        } else if u1 < p.spec_reflect + p.spec_trans + p.diffuse_reflect {
            (
                square_to_cosine_hemisphere(u2),
                BsdfFlags::DIFFUSE_REFLECTION,
            )
        } else if p.diffuse_trans > 0.0 {
            (
                -square_to_cosine_hemisphere(u2),
                BsdfFlags::DIFFUSE_TRANSMISSION,
            )
        } else {
            return None;
        };
        let wi = mulsign(i, wo.z);
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi) / pdf,
            pdf,
            eta: 1.0,
            lobe,
        })
    }

    fn flags(&self) -> BsdfFlags {
        let mut f = BsdfFlags::DIFFUSE_REFLECTION;
        if self.diff_trans > 0.0 {
            f = f | BsdfFlags::DIFFUSE_TRANSMISSION;
        }
        if self.spec_trans > 0.0 {
            f = f | BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::GLOSSY_TRANSMISSION;
        }
        f
    }

    /// The specular reflection's and transmission's GGX roughnesses widened by pbrt-v4's rule,
    /// the diffuse terms unchanged, as for [`super::Principled`]; unchanged where neither lobe
    /// would widen.
    fn regularized(&self) -> AnyBsdf {
        let widens = [self.reflection_distribution(), self.transmission_distribution()]
            .iter()
            .any(|d| d.regularized() != *d);
        AnyBsdf::PrincipledThin(if widens {
            PrincipledThin {
                regularizations: self.regularizations.saturating_add(1),
                ..*self
            }
        } else {
            *self
        })
    }
}

/// The textured parameters of [`PrincipledThin`].
#[derive(Clone, Debug)]
pub struct PrincipledThinTextures {
    pub base_color: Texture,
    pub roughness: Texture,
    pub anisotropic: Texture,
    pub spec_trans: Texture,
    pub spec_tint: Texture,
    pub sheen: Texture,
    pub sheen_tint: Texture,
    pub flatness: Texture,
    pub diff_trans: Texture,
    pub eta: Texture,
    /// Specular reflection and transmission, diffuse reflection and transmission sampling rates.
    pub rates: [f32; 4],
}

/// Boxed, as [`super::PrincipledMaterial`].
pub type PrincipledThinMaterial = Box<PrincipledThinTextures>;

impl BsdfMaterial for Box<PrincipledThinTextures> {
    type Desc = PrincipledThinDesc;
    type Bsdf = PrincipledThin;

    fn build(x: &PrincipledThinDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        let mut tex = |t: &TextureDesc| textures.texture(t);
        Ok(Box::new(PrincipledThinTextures {
            base_color: tex(&x.base_color)?,
            roughness: tex(&x.roughness)?,
            anisotropic: tex(&x.anisotropic)?,
            spec_trans: tex(&x.spec_trans)?,
            spec_tint: tex(&x.spec_tint)?,
            sheen: tex(&x.sheen)?,
            sheen_tint: tex(&x.sheen_tint)?,
            flatness: tex(&x.flatness)?,
            diff_trans: tex(&x.diff_trans)?,
            eta: tex(&x.eta)?,
            rates: [
                x.specular_reflectance_sampling_rate,
                x.specular_transmittance_sampling_rate,
                x.diffuse_reflectance_sampling_rate,
                x.diffuse_transmittance_sampling_rate,
            ],
        }))
    }

    #[inline]
    fn at(&self, tp: &TexPoint) -> PrincipledThin {
        let p = self;
        PrincipledThin {
            base_color: p.base_color.eval_at(tp),
            roughness: p.roughness.eval_1_at(tp),
            anisotropic: p.anisotropic.eval_1_at(tp),
            spec_trans: p.spec_trans.eval_1_at(tp),
            spec_tint: p.spec_tint.eval_1_at(tp),
            sheen: p.sheen.eval_1_at(tp),
            sheen_tint: p.sheen_tint.eval_1_at(tp),
            flatness: p.flatness.eval_1_at(tp),
            diff_trans: p.diff_trans.eval_1_at(tp),
            eta: p.eta.eval_1_at(tp),
            spec_reflect_rate: p.rates[0],
            spec_trans_rate: p.rates[1],
            diffuse_reflect_rate: p.rates[2],
            diffuse_trans_rate: p.rates[3],
            regularizations: 0,
        }
    }
}
