//! Materials of the Monte Carlo integrators: a BSDF's textured parameters, resolved at a surface
//! point into a [`Bsdf`] of plain values (pbrt-v4's Material -> BSDF split). What depends only on
//! constants (the plastics' precomputed albedos) is computed once, at scene load.

use super::bsdf::{
    Bsdf, BsdfFlags, BsdfSample, Conductor, Dielectric, Diffuse, Microfacet, MicrofacetKind, Phong,
    PhongParams, Plastic, PlasticParams, Principled, PrincipledThin, RoughConductor,
    RoughDielectric, RoughPlastic, RoughPlasticParams, ThinDielectric,
};
use super::frame::ShadingFrame;
use super::perturb::{normal_from_bump, normal_from_map, Perturbation};
use super::texture::{AttributePoint, TexPoint, Texture};
use crate::math::{Vec2, Vec3};

#[derive(Clone, Debug)]
pub enum Material {
    /// Whitted's model (`phong`), its colour a plain colour or Whitted's checkerboard.
    Phong(PhongParams),
    Diffuse {
        reflectance: Texture,
    },
    Conductor {
        eta: Vec3,
        k: Vec3,
        specular: Texture,
    },
    RoughConductor {
        roughness: Roughness,
        eta: Vec3,
        k: Vec3,
        specular: Texture,
    },
    Dielectric {
        eta: f32,
        reflectance: Texture,
        transmittance: Texture,
    },
    ThinDielectric {
        eta: f32,
        reflectance: Texture,
        transmittance: Texture,
    },
    RoughDielectric {
        roughness: Roughness,
        eta: f32,
        reflectance: Texture,
        transmittance: Texture,
    },
    Plastic {
        params: PlasticParams,
        diffuse: Texture,
        specular: Texture,
    },
    RoughPlastic {
        params: RoughPlasticParams,
        diffuse: Texture,
        specular: Texture,
    },
    /// Mitsuba's `principled` (Burley's Disney BSDF); `eta` is resolved from `specular` at load.
    Principled(Box<PrincipledTextures>),
    /// Mitsuba's `principledthin`.
    PrincipledThin(Box<PrincipledThinTextures>),
    /// One-sided materials seen from both sides: `front` from the front, `back` from behind (both
    /// indices into the scene's materials).
    TwoSided {
        front: u32,
        back: u32,
    },
    /// The surface is present with probability `opacity` (Mitsuba's `mask`), as `inner`.
    Mask {
        opacity: Texture,
        inner: u32,
    },
    /// `inner` around the normal a tangent-space normal map gives (Mitsuba's `normalmap`).
    NormalMap {
        normals: Texture,
        inner: u32,
        flip_invalid: bool,
        shadowing: bool,
    },
    /// `first` and `second` mixed as `(1 - weight) first + weight second` (Mitsuba's
    /// `blendbsdf`); both are plain BSDFs, not wrappers.
    Blend {
        weight: Texture,
        first: u32,
        second: u32,
    },
    /// `inner` around the normal of a height field scaled by `scale` (Mitsuba's `bumpmap`).
    BumpMap {
        height: Texture,
        scale: f32,
        inner: u32,
        flip_invalid: bool,
        shadowing: bool,
    },
}

/// The textured parameters of [`Material::Principled`] (boxed: they are many, and the other
/// materials should not pay for their size).
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

/// The textured parameters of [`Material::PrincipledThin`].
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

/// A microfacet distribution whose roughness may vary over the surface.
#[derive(Clone, Debug)]
pub struct Roughness {
    pub kind: MicrofacetKind,
    pub alpha_u: Texture,
    pub alpha_v: Texture,
    pub sample_visible: bool,
}

impl Roughness {
    #[inline]
    fn at(&self, p: &TexPoint) -> Microfacet {
        Microfacet::new(
            self.kind,
            self.alpha_u.eval_1_at(p),
            self.alpha_v.eval_1_at(p),
            self.sample_visible,
        )
    }
}

/// What a material needs to know of the surface point, in the coordinates of its shading frame
/// (`z` = shading normal, `x` along dp/du).
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint<'a> {
    pub uv: Vec2,
    /// The mesh attributes at the point, where the surface has them.
    pub attributes: Option<AttributePoint<'a>>,
    /// Toward the viewer (or the previous path vertex).
    pub wo: Vec3,
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    /// The geometric normal.
    pub n: Vec3,
    /// +1 or -1: a normal map's y runs along this times `z × x` (see
    /// [`SurfaceInteraction::bitangent_sign`](crate::geometry::SurfaceInteraction::bitangent_sign)).
    pub bitangent_sign: f32,
}

impl<'a> SurfacePoint<'a> {
    /// The point `si` with its directions in `frame`, seen from world direction `wo`.
    pub fn new(
        si: &crate::geometry::SurfaceInteraction,
        frame: &ShadingFrame,
        wo: Vec3,
        attributes: Option<AttributePoint<'a>>,
    ) -> Self {
        SurfacePoint {
            uv: si.uv,
            attributes,
            wo: frame.to_local(wo),
            dpdu: frame.to_local(si.dpdu),
            dpdv: frame.to_local(si.dpdv),
            n: frame.to_local(si.n),
            bitangent_sign: si.bitangent_sign(),
        }
    }
}

/// The BSDF at a surface point with the wrappers around it resolved: a two-sided material seen
/// from behind mirrors directions through the surface (`flip_outer`, or `flip_inner` inside a
/// normal or bump map), a normal or bump map turns them into its perturbed frame. Directions in
/// and out are in the surface's shading frame.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceBsdf {
    pub bsdf: Bsdf,
    /// A blend: the second BSDF and its weight (`bsdf` is the first).
    blend: Option<(Bsdf, f32)>,
    flip_outer: bool,
    perturbation: Option<Perturbation>,
    flip_inner: bool,
}

/// The largest f32 below 1: a rescaled random number stays in [0, 1).
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[inline]
fn flip_if(flip: bool, mut w: Vec3) -> Vec3 {
    if flip {
        w.z = -w.z;
    }
    w
}

impl SurfaceBsdf {
    /// A BSDF with no wrapper.
    pub fn plain(bsdf: Bsdf) -> Self {
        SurfaceBsdf {
            bsdf,
            blend: None,
            flip_outer: false,
            perturbation: None,
            flip_inner: false,
        }
    }

    pub fn flags(&self) -> BsdfFlags {
        match &self.blend {
            Some((second, _)) => self.bsdf.flags() | second.flags(),
            None => self.bsdf.flags(),
        }
    }

    /// The BSDF, or the blend of two, in its own frame.
    fn leaf_eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let (f, pdf) = self.bsdf.eval_pdf(wo, wi);
        match &self.blend {
            None => (f, pdf),
            Some((second, w)) => {
                let (f2, pdf2) = second.eval_pdf(wo, wi);
                (f * (1.0 - w) + f2 * *w, pdf * (1.0 - w) + pdf2 * w)
            }
        }
    }

    /// A blend samples one of its BSDFs, the second with probability `weight`, and keeps that
    /// one's weight (`f_i / pdf_i`: its expectation over the choice is the blend's value), as
    /// Mitsuba's `blendbsdf` does. Unlike Mitsuba, a smooth sample reports the blend's density,
    /// so that the MIS weight of an emitter it hits matches the density emitter sampling uses.
    fn leaf_sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        let Some((second, w)) = &self.blend else {
            return self.bsdf.sample(wo, u1, u2);
        };
        let (chosen, other, u1, p_other) = if u1 > *w {
            (&self.bsdf, second, (u1 - w) / (1.0 - w), *w)
        } else {
            (second, &self.bsdf, u1 / w, 1.0 - w)
        };
        let mut s = chosen.sample(wo, u1.min(ONE_MINUS_EPSILON), u2)?;
        if !s.lobe.is_delta() {
            s.pdf = (1.0 - p_other) * s.pdf + p_other * other.pdf(wo, s.wi);
        }
        Some(s)
    }

    /// [`Bsdf::eval_pdf`] through the wrappers. A perturbed frame gives nothing where `wi` lies on
    /// different sides of the two frames' surfaces, and its value (not its pdf) carries the
    /// terminator shadowing.
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let (wo, wi) = (flip_if(self.flip_outer, wo), flip_if(self.flip_outer, wi));
        let Some(p) = &self.perturbation else {
            return self.leaf_eval_pdf(wo, wi);
        };
        let (pwo, pwi) = (p.frame.to_local(wo), p.frame.to_local(wi));
        if wi.z * pwi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let (pwo, pwi) = (flip_if(self.flip_inner, pwo), flip_if(self.flip_inner, pwi));
        let (f, pdf) = self.leaf_eval_pdf(pwo, pwi);
        (f * p.attenuation(wi), pdf)
    }

    /// [`Bsdf::sample`] through the wrappers; `None` also where a perturbed frame rejects the
    /// direction.
    pub fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        let wo = flip_if(self.flip_outer, wo);
        let Some(p) = &self.perturbation else {
            let mut s = self.leaf_sample(wo, u1, u2)?;
            s.wi = flip_if(self.flip_outer, s.wi);
            return Some(s);
        };
        let pwo = flip_if(self.flip_inner, p.frame.to_local(wo));
        let mut s = self.leaf_sample(pwo, u1, u2)?;
        let pwi = flip_if(self.flip_inner, s.wi);
        let wi = p.frame.to_world(pwi);
        if wi.z * pwi.z <= 0.0 {
            return None;
        }
        s.weight *= p.attenuation(wi);
        s.wi = flip_if(self.flip_outer, wi);
        Some(s)
    }
}

/// How deep two-sided and mask materials may nest (validation rejects cycles; this bounds the
/// walk regardless).
const MAX_NESTING: u32 = 16;

impl Material {
    /// The BSDF of material `index` of `materials` at surface point `at`. Masks are not resolved
    /// here: see [`Self::opacity`].
    pub fn bsdf(materials: &[Material], index: u32, at: &SurfacePoint) -> SurfaceBsdf {
        let tp = TexPoint {
            uv: at.uv,
            attributes: at.attributes,
        };
        let mut m = &materials[index as usize];
        let mut out = SurfaceBsdf::plain(Bsdf::Diffuse(Diffuse::new(Vec3::ZERO)));
        // `wo` as the wrapper being resolved sees it.
        let mut wo = at.wo;
        for _ in 0..MAX_NESTING {
            match m {
                Material::TwoSided { front, back } => {
                    // Mitsuba's twosided: below the surface, the back material with directions
                    // mirrored.
                    if wo.z < 0.0 {
                        if out.perturbation.is_some() {
                            out.flip_inner = !out.flip_inner;
                        } else {
                            out.flip_outer = !out.flip_outer;
                        }
                        wo.z = -wo.z;
                        m = &materials[*back as usize];
                    } else {
                        m = &materials[*front as usize];
                    }
                }
                Material::Mask { inner, .. } => m = &materials[*inner as usize],
                // Validation allows one map in a chain; a second would be passed through.
                Material::NormalMap { inner, .. } | Material::BumpMap { inner, .. }
                    if out.perturbation.is_some() =>
                {
                    m = &materials[*inner as usize]
                }
                Material::NormalMap {
                    normals,
                    inner,
                    flip_invalid,
                    shadowing,
                } => {
                    // The map's normal is relative to the unmirrored shading frame, as Mitsuba's
                    // adapter reads it from the surface interaction a two-sided BSDF leaves as it
                    // is (only the directions are mirrored).
                    let mut n = normal_from_map(normals.eval_at(&tp));
                    n.y *= at.bitangent_sign;
                    let p = Perturbation::new(n, wo, *flip_invalid, *shadowing);
                    wo = p.frame.to_local(wo);
                    out.perturbation = Some(p);
                    m = &materials[*inner as usize];
                }
                Material::BumpMap {
                    height,
                    scale,
                    inner,
                    flip_invalid,
                    shadowing,
                } => {
                    let grad = *scale * height.eval_1_grad(at.uv);
                    let n = normal_from_bump(grad, at.dpdu, at.dpdv, at.n);
                    let p = Perturbation::new(n, wo, *flip_invalid, *shadowing);
                    wo = p.frame.to_local(wo);
                    out.perturbation = Some(p);
                    m = &materials[*inner as usize];
                }
                Material::Blend {
                    weight,
                    first,
                    second,
                } => {
                    // Validation keeps blends' components plain BSDFs.
                    let w = weight.eval_1_at(&tp).clamp(0.0, 1.0);
                    out.bsdf = materials[*first as usize].leaf_bsdf(&tp);
                    out.blend = Some((materials[*second as usize].leaf_bsdf(&tp), w));
                    return out;
                }
                _ => break,
            }
        }
        out.bsdf = m.leaf_bsdf(&tp);
        out
    }

    /// The probability that the surface is there at `uv` (1 unless a mask wraps the material).
    pub fn opacity(materials: &[Material], index: u32, uv: Vec2) -> f32 {
        match &materials[index as usize] {
            Material::Mask { opacity, .. } => opacity.eval_1(uv).clamp(0.0, 1.0),
            _ => 1.0,
        }
    }

    pub fn has_mask(&self) -> bool {
        matches!(self, Material::Mask { .. })
    }

    /// Whether the material reads texture coordinates: surfaces may skip computing them
    /// otherwise (a `phong` material without a checkerboard, as most of Whitted's are).
    #[inline(always)]
    pub fn needs_uv(&self) -> bool {
        match self {
            Material::Phong(p) => p.needs_uv(),
            _ => true,
        }
    }

    /// What the `whitted` and `raycast` integrators read of material `index` at `uv`: a `phong`
    /// material's own lobes, any other BSDF's [`Bsdf::whitted`] response. `attributes` (asked
    /// only for the latter) are the mesh attributes of the point.
    #[inline(always)]
    pub fn whitted<'a>(
        materials: &'a [Material],
        index: u32,
        uv: Vec2,
        attributes: impl FnOnce() -> Option<AttributePoint<'a>>,
    ) -> Phong {
        match &materials[index as usize] {
            Material::Phong(p) => p.at(uv),
            _ => Self::whitted_of_bsdf(
                materials,
                index,
                &TexPoint {
                    uv,
                    attributes: attributes(),
                },
            ),
        }
    }

    /// [`Self::whitted`] of a material other than `phong`, out of line. Whitted's surfaces are
    /// two-sided and are not cut out, and its rays follow the geometric surface: a two-sided
    /// material is seen as its front, a mask or a normal or bump map as the material inside it, a
    /// blend as its first BSDF.
    #[inline(never)]
    fn whitted_of_bsdf(materials: &[Material], index: u32, tp: &TexPoint) -> Phong {
        let mut m = &materials[index as usize];
        for _ in 0..MAX_NESTING {
            m = match m {
                Material::TwoSided { front, .. } => &materials[*front as usize],
                Material::Mask { inner, .. }
                | Material::NormalMap { inner, .. }
                | Material::BumpMap { inner, .. } => &materials[*inner as usize],
                Material::Blend { first, .. } => &materials[*first as usize],
                _ => break,
            };
        }
        m.leaf_bsdf(tp).whitted()
    }

    fn leaf_bsdf(&self, tp: &TexPoint) -> Bsdf {
        match self {
            Material::Phong(p) => Bsdf::Phong(p.at(tp.uv)),
            Material::Diffuse { reflectance } => Bsdf::Diffuse(Diffuse::new(
                reflectance.eval_at(tp).clamp(Vec3::ZERO, Vec3::ONE),
            )),
            Material::Conductor { eta, k, specular } => {
                Bsdf::Conductor(Conductor::new(*eta, *k, specular.eval_at(tp)))
            }
            Material::RoughConductor {
                roughness,
                eta,
                k,
                specular,
            } => Bsdf::RoughConductor(RoughConductor::new(
                roughness.at(tp),
                *eta,
                *k,
                specular.eval_at(tp),
            )),
            Material::Dielectric {
                eta,
                reflectance,
                transmittance,
            } => Bsdf::Dielectric(Dielectric::new(
                *eta,
                reflectance.eval_at(tp),
                transmittance.eval_at(tp),
            )),
            Material::ThinDielectric {
                eta,
                reflectance,
                transmittance,
            } => Bsdf::ThinDielectric(ThinDielectric::new(
                *eta,
                reflectance.eval_at(tp),
                transmittance.eval_at(tp),
            )),
            Material::RoughDielectric {
                roughness,
                eta,
                reflectance,
                transmittance,
            } => Bsdf::RoughDielectric(RoughDielectric::new(
                roughness.at(tp),
                *eta,
                reflectance.eval_at(tp),
                transmittance.eval_at(tp),
            )),
            Material::Plastic {
                params,
                diffuse,
                specular,
            } => Bsdf::Plastic(Plastic::new(
                params,
                diffuse.eval_at(tp),
                specular.eval_at(tp),
            )),
            Material::RoughPlastic {
                params,
                diffuse,
                specular,
            } => Bsdf::RoughPlastic(RoughPlastic::new(
                params,
                diffuse.eval_at(tp),
                specular.eval_at(tp),
            )),
            Material::Principled(p) => Bsdf::Principled(Principled {
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
            }),
            Material::PrincipledThin(p) => Bsdf::PrincipledThin(PrincipledThin {
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
            }),
            // Resolved by `bsdf`; reached only past the nesting bound, as black.
            Material::TwoSided { .. }
            | Material::Mask { .. }
            | Material::NormalMap { .. }
            | Material::BumpMap { .. }
            | Material::Blend { .. } => Bsdf::Diffuse(Diffuse::new(Vec3::ZERO)),
        }
    }
}

#[cfg(test)]
#[path = "material_tests.rs"]
mod tests;
