//! Mitsuba 3's `principled` BSDF: Burley's Disney BSDF ("Physically Based Shading at Disney",
//! 2012; "Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering", 2015) as
//! Mitsuba implements it, term for term, so that renders agree with Mitsuba's in expectation:
//!
//! - a diffuse lobe with Burley's retro-reflection, optionally flattened towards the
//!   Hanrahan-Krueger-like "fake subsurface" term (`flatness`), weighted by
//!   `(1 - metallic)(1 - spec_trans)`;
//! - a sheen lobe `sheen (1 - metallic) F_schlick(cos θd)`, tinted towards the base colour's hue;
//! - the main GGX lobe (visible-normal sampled, anisotropic by Burley's aspect ratio), reflecting
//!   with a Fresnel blended from the true dielectric one (the `specular`/`eta` interface), a
//!   Schlick metallic one and a Schlick tinted one, and transmitting by `(1 - metallic) spec_trans`
//!   (Walter et al. 2007 refraction, tinted by `sqrt(base_color)` per crossing);
//! - a clearcoat lobe: GTR1 normals, Schlick Fresnel of `R0 = 0.04`, separable GGX masking of
//!   roughness 0.25; Mitsuba's value `0.25 clearcoat F D G cos θi` lacks the microfacet
//!   `1 / (4 cos θo cos θi)`, and is kept so to match.
//!
//! Mitsuba's lobe probabilities (its `principled.cpp`) are used for sampling; `pdf` is their mixture.

use super::fresnel::{fresnel_dielectric, reflect_about, refract_about};
use super::microfacet::{regularized_alpha, Microfacet, MicrofacetKind};
use super::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use super::{AnyBsdf, Phong, mulsign, Bsdf, BsdfFlags, BsdfSample};
use crate::math::{Vec2, Vec3};
use crate::shading::texture::luminance;
use std::f32::consts::{FRAC_1_PI, PI};
use super::{BsdfMaterial, TextureSource};
use crate::error::Result;
use crate::description::{PrincipledDesc, TextureDesc};
use crate::shading::texture::{TexPoint, Texture};

/// The per-hit values of a principled material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principled {
    pub base_color: Vec3,
    pub roughness: f32,
    pub anisotropic: f32,
    pub metallic: f32,
    pub spec_trans: f32,
    pub spec_tint: f32,
    pub sheen: f32,
    pub sheen_tint: f32,
    pub flatness: f32,
    pub clearcoat: f32,
    pub clearcoat_gloss: f32,
    /// Relative IOR, inside over outside.
    pub eta: f32,
    /// Sampling weights of the diffuse, main specular and clearcoat lobes (Mitsuba's
    /// `*_sampling_rate`).
    pub diffuse_rate: f32,
    pub specular_rate: f32,
    pub clearcoat_rate: f32,
    /// How many times [`Bsdf::regularized`] has widened the microfacet lobes (0, or 1 after a
    /// path's first non-specular bounce): their roughnesses are derived from Burley's
    /// parameters at each use, and widened there.
    pub regularizations: u8,
}

/// Schlick's weight `(1 - cos)^5`, the argument clamped to [0, 1].
#[inline]
pub(crate) fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// Schlick's Fresnel `R0 + (1 - R0) w` with Mitsuba's choice of angle: the incident one when
/// entering the denser side, the transmitted one otherwise (so that it vanishes under total
/// internal reflection's complement correctly).
#[inline]
pub(crate) fn schlick_fresnel(r0: Vec3, cos_theta_i: f32, eta: f32) -> Vec3 {
    let (eta_it, eta_ti) = if cos_theta_i >= 0.0 {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let w = if eta_it > 1.0 {
        schlick_weight(cos_theta_i.abs())
    } else {
        let cos_t2 = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * eta_ti * eta_ti;
        schlick_weight(cos_t2.max(0.0).sqrt())
    };
    r0 + (Vec3::ONE - r0) * w
}

/// Normal-incidence reflectance of a dielectric of relative IOR `eta`.
#[inline]
pub(crate) fn schlick_r0(eta: f32) -> f32 {
    ((eta - 1.0) / (eta + 1.0)).powi(2)
}

/// The base colour divided by its luminance (its hue at unit brightness), white if black.
#[inline]
pub(crate) fn tint(base_color: Vec3) -> Vec3 {
    let lum = luminance(base_color);
    if lum > 0.0 {
        base_color / lum
    } else {
        Vec3::ONE
    }
}

/// Whether `wo` and `wi` both lie on the side of microfacet `m` that faces the macro surface's
/// side of `wo` (reflection), or `wi` on the opposite one (transmission).
#[inline]
pub(crate) fn microfacet_compatible(
    m: Vec3,
    wo: Vec3,
    wi: Vec3,
    cos_o: f32,
    reflection: bool,
) -> bool {
    let m = mulsign(m, cos_o);
    wo.dot(m) > 0.0
        && if reflection {
            wi.dot(m) > 0.0
        } else {
            wi.dot(m) < 0.0
        }
}

/// GGX roughness from Burley's `roughness` and `anisotropic` (2012, Appendix B.2: `alpha =
/// roughness²`, stretched by `aspect = sqrt(1 - 0.9 anisotropic)`), floored at 0.001 as Mitsuba.
#[inline]
pub(crate) fn distribution(roughness: f32, anisotropic: f32) -> Microfacet {
    let r2 = roughness * roughness;
    let aspect = (1.0 - 0.9 * anisotropic).sqrt();
    Microfacet::new(
        MicrofacetKind::Ggx,
        (r2 / aspect).max(0.001),
        (r2 * aspect).max(0.001),
        true,
    )
}

/// `d` widened `times` times by pbrt-v4's regularization ([`Microfacet::regularized`]).
#[inline]
pub(crate) fn regularized_times(d: Microfacet, times: u8) -> Microfacet {
    (0..times).fold(d, |d, _| d.regularized())
}

/// Burley's diffuse with retro-reflection, blended by `flatness` with the fake subsurface term,
/// without the `base_color / π` factor; `cos_i`, `cos_o` are absolute, `cos_d = wi · h`.
#[inline]
pub(crate) fn disney_diffuse(
    roughness: f32,
    flatness: f32,
    cos_o: f32,
    cos_i: f32,
    cos_d: f32,
) -> f32 {
    let (fo, fi) = (schlick_weight(cos_i), schlick_weight(cos_o));
    let f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
    let rr = 2.0 * roughness * cos_d * cos_d;
    let f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
    let lambert_retro = f_diff + f_retro;
    if flatness == 0.0 {
        return lambert_retro;
    }
    let fss90 = 0.5 * rr;
    let fss = (1.0 + (fss90 - 1.0) * fo) * (1.0 + (fss90 - 1.0) * fi);
    let f_ss = 1.25 * (fss * (1.0 / (cos_o + cos_i) - 0.5) + 0.5);
    lambert_retro + (f_ss - lambert_retro) * flatness
}

/// The sheen colour: white blended towards the base colour's hue by `sheen_tint`.
#[inline]
pub(crate) fn sheen_color(base_color: Vec3, sheen_tint: f32) -> Vec3 {
    if sheen_tint == 0.0 {
        Vec3::ONE
    } else {
        Vec3::ONE + (tint(base_color) - Vec3::ONE) * sheen_tint
    }
}

/// Burley's GTR1 ("generalized Trowbridge-Reitz", gamma = 1) normal distribution of the clearcoat.
#[derive(Clone, Copy, Debug)]
struct Gtr1 {
    alpha: f32,
}

impl Gtr1 {
    /// Clearcoat roughness runs from 0.1 (gloss 0) to 0.001 (gloss 1).
    fn from_gloss(gloss: f32) -> Self {
        Gtr1 {
            alpha: 0.1 + (0.001 - 0.1) * gloss,
        }
    }

    /// Burley 2012, eq. 4 normalized: `(α² - 1) / (π ln α² (1 + (α² - 1) cos² θ))`.
    fn d(&self, m: Vec3) -> f32 {
        let a2 = self.alpha * self.alpha;
        let r = (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * m.z * m.z));
        if r * m.z > 1e-20 {
            r
        } else {
            0.0
        }
    }

    fn pdf(&self, m: Vec3) -> f32 {
        if m.z < 0.0 {
            0.0
        } else {
            m.z * self.d(m)
        }
    }

    /// `D(m) cos θm` by inversion (Burley 2012, Appendix B.2).
    fn sample(&self, u: Vec2) -> Vec3 {
        let (sin_phi, cos_phi) = (2.0 * PI * u.x).sin_cos();
        let a2 = self.alpha * self.alpha;
        let cos2 = (1.0 - a2.powf(1.0 - u.y)) / (1.0 - a2);
        let sin = (1.0 - cos2).max(0.0).sqrt();
        Vec3::new(cos_phi * sin, sin_phi * sin, cos2.max(0.0).sqrt())
    }
}

/// Smith's GGX masking of one direction at roughness `alpha`, as the clearcoat uses it.
fn smith_ggx1(v: Vec3, h: Vec3, alpha: f32) -> f32 {
    if v.dot(h) * v.z <= 0.0 {
        return 0.0;
    }
    if v.z == 1.0 {
        return 1.0;
    }
    let cos2 = v.z * v.z;
    let tan2 = (1.0 - cos2) / cos2;
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// Lobe choice probabilities for `wo` given the main lobe's Fresnel `f`.
struct Probabilities {
    diffuse: f32,
    clearcoat: f32,
    spec_trans: f32,
    spec_reflect: f32,
}

impl Principled {
    /// The main lobe's GGX distribution (see [`Self::regularizations`]).
    #[inline]
    pub(crate) fn main_distribution(&self) -> Microfacet {
        regularized_times(
            distribution(self.roughness, self.anisotropic),
            self.regularizations,
        )
    }

    /// The clearcoat's GTR1 roughness, regularized by the same rule as the GGX lobes' (see
    /// [`Self::regularizations`]).
    #[inline]
    pub(crate) fn clearcoat_alpha(&self) -> f32 {
        let alpha = Gtr1::from_gloss(self.clearcoat_gloss).alpha;
        (0..self.regularizations).fold(alpha, |a, _| regularized_alpha(a))
    }

    #[inline]
    fn clearcoat_distribution(&self) -> Gtr1 {
        Gtr1 {
            alpha: self.clearcoat_alpha(),
        }
    }

    /// Weights of the opaque dielectric (diffuse) and transmitting parts.
    #[inline]
    fn weights(&self) -> (f32, f32) {
        let dielectric = 1.0 - self.metallic;
        (
            dielectric * (1.0 - self.spec_trans),
            dielectric * self.spec_trans,
        )
    }

    #[inline]
    fn probabilities(&self, front: bool, f: f32) -> Probabilities {
        let (brdf, bsdf) = self.weights();
        let mut p = if front {
            Probabilities {
                diffuse: brdf * self.diffuse_rate,
                clearcoat: 0.25 * self.clearcoat * self.clearcoat_rate,
                spec_trans: self.specular_rate * bsdf * (1.0 - f),
                spec_reflect: self.specular_rate * (1.0 - bsdf * (1.0 - f)),
            }
        } else {
            // Inside, only the main lobe's reflection and transmission.
            Probabilities {
                diffuse: 0.0,
                clearcoat: 0.0,
                spec_trans: 1.0 - f,
                spec_reflect: f,
            }
        };
        let total = p.diffuse + p.clearcoat + p.spec_trans + p.spec_reflect;
        if total > 0.0 {
            p.diffuse /= total;
            p.clearcoat /= total;
            p.spec_trans /= total;
            p.spec_reflect /= total;
        }
        p
    }

    /// The main lobe's Fresnel: outside, the dielectric one blended with Schlick's metallic and
    /// tinted ones; inside, the plain dielectric one of the transmitting part.
    #[inline]
    fn fresnel(&self, f_dielectric: f32, cos_theta_i: f32, front: bool) -> Vec3 {
        let (_, bsdf) = self.weights();
        if !front {
            return Vec3::splat(bsdf * f_dielectric);
        }
        let eta_it = if cos_theta_i >= 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let mut f = Vec3::splat((1.0 - self.metallic) * (1.0 - self.spec_tint) * f_dielectric);
        if self.metallic > 0.0 {
            f += self.metallic * schlick_fresnel(self.base_color, cos_theta_i, self.eta);
        }
        if self.spec_tint > 0.0 {
            let r0 = tint(self.base_color) * schlick_r0(eta_it);
            f +=
                (1.0 - self.metallic) * self.spec_tint * schlick_fresnel(r0, cos_theta_i, self.eta);
        }
        f
    }

    /// The generalized half vector (Walter et al. 2007, eq. 16), on the outer side.
    #[inline]
    fn half_vector(&self, wo: Vec3, wi: Vec3, reflect: bool, eta_path: f32) -> Vec3 {
        let h = (wo + wi * if reflect { 1.0 } else { eta_path }).normalize();
        mulsign(h, h.z)
    }
}

impl Bsdf for Principled {
    /// The diffuse base, with the glossy lobe as a highlight.
    fn whitted(&self) -> Phong {
        Phong {
            specular: 0.5,
            shininess: 50.0,
            ..Phong::matte(self.base_color)
        }
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let cos_o = wo.z;
        let cos_i = wi.z;
        if cos_o == 0.0 {
            return Vec3::ZERO;
        }
        let (brdf, bsdf) = self.weights();
        let reflect = cos_o * cos_i > 0.0;
        let refract = cos_o * cos_i < 0.0;
        let front = cos_o > 0.0;
        let eta_path = if front { self.eta } else { 1.0 / self.eta };
        let dist = self.main_distribution();
        let h = self.half_vector(wo, wi, reflect, eta_path);
        let (f_d, _, _, _) = fresnel_dielectric(wo.dot(h), self.eta);
        let reflect_ok = reflect && microfacet_compatible(h, wo, wi, cos_o, true);
        let refract_ok = refract && microfacet_compatible(h, wo, wi, cos_o, false);
        let d = dist.d(h);
        let g = dist.g(wo, wi, h);
        let mut value = Vec3::ZERO;
        if reflect_ok && f_d > 0.0 {
            let f = self.fresnel(f_d, wo.dot(h), front);
            value += f * (d * g / (4.0 * cos_o.abs()));
        }
        if refract_ok && bsdf > 0.0 && f_d < 1.0 {
            // Radiance is compressed by (1 / eta_path)² on entering (Veach 1997, 5.2), which
            // cancels the eta_path² of the Jacobian.
            let (o_h, i_h) = (wo.dot(h), wi.dot(h));
            let denom = o_h + eta_path * i_h;
            let t = ((1.0 - f_d) * d * g * o_h * i_h / (cos_o * denom * denom)).abs();
            value += self.base_color.max(Vec3::ZERO).powf(0.5) * (bsdf * t);
        }
        if reflect_ok && front && self.clearcoat > 0.0 {
            let fcc = schlick_fresnel(Vec3::splat(0.04), wo.dot(h), self.eta).x;
            let dcc = self.clearcoat_distribution().d(h);
            let gcc = smith_ggx1(wo, h, 0.25) * smith_ggx1(wi, h, 0.25);
            value += Vec3::splat(0.25 * self.clearcoat * fcc * dcc * gcc * cos_i.abs());
        }
        if reflect && front && brdf > 0.0 {
            let cos_d = h.dot(wi);
            let diffuse = disney_diffuse(
                self.roughness,
                self.flatness,
                cos_o.abs(),
                cos_i.abs(),
                cos_d,
            );
            value += self.base_color * (brdf * cos_i.abs() * FRAC_1_PI * diffuse);
            if self.sheen > 0.0 && self.metallic < 1.0 {
                let fd = schlick_weight(cos_d.abs());
                value += sheen_color(self.base_color, self.sheen_tint)
                    * (self.sheen * (1.0 - self.metallic) * fd * cos_i.abs());
            }
        }
        value
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let cos_o = wo.z;
        let cos_i = wi.z;
        let front = cos_o > 0.0;
        let (_, bsdf) = self.weights();
        // Nothing is sampled from inside when nothing transmits.
        if cos_o == 0.0 || (!front && bsdf <= 0.0) {
            return 0.0;
        }
        let reflect = cos_o * cos_i > 0.0;
        let refract = cos_o * cos_i < 0.0;
        let eta_path = if front { self.eta } else { 1.0 / self.eta };
        let h = self.half_vector(wo, wi, reflect, eta_path);
        let (f_d, _, _, _) = fresnel_dielectric(wo.dot(h), self.eta);
        let p = self.probabilities(front, f_d);
        let (o_h, i_h) = (wo.dot(h), wi.dot(h));
        // |dh / dwi| for reflection (Walter et al. 2007, eq. 14) and refraction (eq. 17).
        let jacobian = if reflect {
            (1.0 / (4.0 * i_h)).abs()
        } else {
            let denom = o_h + eta_path * i_h;
            (eta_path * eta_path * i_h / (denom * denom)).abs()
        };
        let dist = self.main_distribution();
        let wo_up = mulsign(wo, cos_o);
        let mut pdf = 0.0;
        if reflect && microfacet_compatible(h, wo, wi, cos_o, true) {
            pdf += p.spec_reflect * dist.pdf(wo_up, h) * jacobian;
            if p.clearcoat > 0.0 {
                pdf += p.clearcoat * self.clearcoat_distribution().pdf(h) * jacobian;
            }
        }
        if reflect {
            pdf += p.diffuse * square_to_cosine_hemisphere_pdf(wi);
        }
        if refract && microfacet_compatible(h, wo, wi, cos_o, false) {
            pdf += p.spec_trans * dist.pdf(wo_up, h) * jacobian;
        }
        pdf
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        (self.eval(wo, wi), self.pdf(wo, wi))
    }

    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        let cos_o = wo.z;
        let front = cos_o > 0.0;
        let (_, bsdf) = self.weights();
        if cos_o == 0.0 || (!front && bsdf <= 0.0) {
            return None;
        }
        let dist = self.main_distribution();
        let (m, _) = dist.sample(mulsign(wo, cos_o), u2);
        let (f_d, cos_t, eta_it, eta_ti) = fresnel_dielectric(wo.dot(m), self.eta);
        let p = self.probabilities(front, f_d);
        let (wi, lobe, eta) = if u1 < p.diffuse {
            let wi = square_to_cosine_hemisphere(u2);
            (wi, BsdfFlags::DIFFUSE_REFLECTION, 1.0)
        } else if u1 < p.diffuse + p.clearcoat {
            let m = self.clearcoat_distribution().sample(u2);
            let wi = reflect_about(wo, m);
            if cos_o * wi.z <= 0.0 || !microfacet_compatible(m, wo, wi, cos_o, true) {
                return None;
            }
            (wi, BsdfFlags::GLOSSY_REFLECTION, 1.0)
        } else if u1 < p.diffuse + p.clearcoat + p.spec_trans {
            let wi = refract_about(wo, m, cos_t, eta_ti);
            if cos_o * wi.z >= 0.0 || !microfacet_compatible(m, wo, wi, cos_o, false) {
                return None;
            }
            (wi, BsdfFlags::GLOSSY_TRANSMISSION, eta_it)
        } else {
            let wi = reflect_about(wo, m);
            if cos_o * wi.z <= 0.0 || !microfacet_compatible(m, wo, wi, cos_o, true) {
                return None;
            }
            (wi, BsdfFlags::GLOSSY_REFLECTION, 1.0)
        };
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi) / pdf,
            pdf,
            eta,
            lobe,
        })
    }

    fn flags(&self) -> BsdfFlags {
        let mut f = BsdfFlags::DIFFUSE_REFLECTION | BsdfFlags::GLOSSY_REFLECTION;
        if self.spec_trans > 0.0 && self.metallic < 1.0 {
            f = f | BsdfFlags::GLOSSY_TRANSMISSION;
        }
        f
    }

    /// pbrt-v4's rule for every microfacet lobe, in the spirit of its `Regularize` (pbrt has no
    /// principled BSDF): the main GGX lobe's roughnesses and the clearcoat's GTR1 roughness
    /// widened as [`Microfacet::regularized`] widens them; the diffuse, retro-reflection and
    /// sheen terms, which are not near-specular, unchanged (Burley's `roughness` also shapes the
    /// retro-reflection, which is why the widening applies to the lobes' alphas, not to it).
    /// Unchanged where no lobe would widen.
    fn regularized(&self) -> AnyBsdf {
        let main = self.main_distribution();
        let coat = self.clearcoat_alpha();
        let widens =
            main.regularized() != main || (self.clearcoat > 0.0 && regularized_alpha(coat) != coat);
        AnyBsdf::Principled(if widens {
            Principled {
                regularizations: self.regularizations.saturating_add(1),
                ..*self
            }
        } else {
            *self
        })
    }
}

/// `specular` (Burley's reflectance at normal incidence, scaled so 0.5 is 4%) as a relative IOR:
/// `eta = 2 / (1 - sqrt(0.08 specular)) - 1`, Mitsuba's inversion of `R0 = 0.08 specular`.
pub fn specular_to_eta(specular: f32) -> f32 {
    2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
}

/// The textured parameters of [`Principled`]; `eta` is resolved from `specular` at load.
#[derive(Clone, Debug)]
pub struct PrincipledTextures {
    pub base_color: Texture,
    pub roughness: Texture,
    pub anisotropic: Texture,
    pub metallic: Texture,
    pub spec_trans: Texture,
    pub spec_tint: Texture,
    pub sheen: Texture,
    pub sheen_tint: Texture,
    pub flatness: Texture,
    pub clearcoat: Texture,
    pub clearcoat_gloss: Texture,
    pub eta: f32,
    /// Diffuse, main specular and clearcoat sampling rates.
    pub rates: [f32; 3],
}

/// Boxed: the parameters are many, and the other materials should not pay for their size.
pub type PrincipledMaterial = Box<PrincipledTextures>;

impl BsdfMaterial for Box<PrincipledTextures> {
    type Desc = PrincipledDesc;
    type Bsdf = Principled;

    fn build(x: &PrincipledDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        // Mitsuba's constructor: a transmitting material (spec_trans given and not a zero
        // number) never gets eta exactly 1 (no refraction) or specular 0 (the same).
        let transmits = x.spec_trans != TextureDesc::Value(0.0);
        let eta = match (x.eta, x.specular) {
            (Some(eta), _) if transmits && eta == 1.0 => 1.001,
            (Some(eta), _) => eta,
            (None, s) => {
                let s = s.unwrap_or(0.5);
                specular_to_eta(if transmits && s == 0.0 { 1e-3 } else { s })
            }
        };
        let mut tex = |t: &TextureDesc| textures.texture(t);
        Ok(Box::new(PrincipledTextures {
            base_color: tex(&x.base_color)?,
            roughness: tex(&x.roughness)?,
            anisotropic: tex(&x.anisotropic)?,
            metallic: tex(&x.metallic)?,
            spec_trans: tex(&x.spec_trans)?,
            spec_tint: tex(&x.spec_tint)?,
            sheen: tex(&x.sheen)?,
            sheen_tint: tex(&x.sheen_tint)?,
            flatness: tex(&x.flatness)?,
            clearcoat: tex(&x.clearcoat)?,
            clearcoat_gloss: tex(&x.clearcoat_gloss)?,
            eta,
            rates: [
                x.diffuse_reflectance_sampling_rate,
                x.main_specular_sampling_rate,
                x.clearcoat_sampling_rate,
            ],
        }))
    }

    #[inline]
    fn at(&self, tp: &TexPoint) -> Principled {
        let p = self;
        Principled {
            base_color: p.base_color.eval_at(tp),
            roughness: p.roughness.eval_1_at(tp),
            anisotropic: p.anisotropic.eval_1_at(tp),
            metallic: p.metallic.eval_1_at(tp),
            spec_trans: p.spec_trans.eval_1_at(tp),
            spec_tint: p.spec_tint.eval_1_at(tp),
            sheen: p.sheen.eval_1_at(tp),
            sheen_tint: p.sheen_tint.eval_1_at(tp),
            flatness: p.flatness.eval_1_at(tp),
            clearcoat: p.clearcoat.eval_1_at(tp),
            clearcoat_gloss: p.clearcoat_gloss.eval_1_at(tp),
            eta: p.eta,
            diffuse_rate: p.rates[0],
            specular_rate: p.rates[1],
            clearcoat_rate: p.rates[2],
            regularizations: 0,
        }
    }
}
