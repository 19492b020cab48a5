//! Materials of the Monte Carlo integrators: a BSDF's textured parameters, resolved at a surface
//! point into a [`Bsdf`] of plain values (pbrt-v4's Material -> BSDF split). What depends only on
//! constants (the plastics' precomputed albedos) is computed once, at scene load.

use super::bsdf::{
    Bsdf, Conductor, Dielectric, Diffuse, Microfacet, MicrofacetKind, Plastic, PlasticParams,
    Principled, PrincipledThin, RoughConductor, RoughDielectric, RoughPlastic, RoughPlasticParams,
    ThinDielectric,
};
use super::texture::Texture;
use crate::math::{Vec2, Vec3};

#[derive(Clone, Debug)]
pub enum Material {
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
    fn at(&self, uv: Vec2) -> Microfacet {
        Microfacet::new(
            self.kind,
            self.alpha_u.eval_1(uv),
            self.alpha_v.eval_1(uv),
            self.sample_visible,
        )
    }
}

/// The BSDF at a surface point, and whether it is seen from behind a two-sided material (the
/// integrator then mirrors directions through the surface before evaluating it).
#[derive(Clone, Copy, Debug)]
pub struct SurfaceBsdf {
    pub bsdf: Bsdf,
    pub flipped: bool,
}

/// How deep two-sided and mask materials may nest (validation rejects cycles; this bounds the
/// walk regardless).
const MAX_NESTING: u32 = 16;

impl Material {
    /// The BSDF of material `index` of `materials` at texture coordinates `uv`, for a direction
    /// `wo` whose local z is `cos_wo` (its sign picks the side of a two-sided material). Masks are
    /// not resolved here: see [`Self::opacity`].
    pub fn bsdf(materials: &[Material], index: u32, uv: Vec2, cos_wo: f32) -> SurfaceBsdf {
        let mut m = &materials[index as usize];
        let mut flipped = false;
        for _ in 0..MAX_NESTING {
            match m {
                Material::TwoSided { front, back } => {
                    // Mitsuba's twosided: below the surface, the back material with directions
                    // mirrored.
                    if cos_wo < 0.0 {
                        flipped = !flipped;
                        m = &materials[*back as usize];
                    } else {
                        m = &materials[*front as usize];
                    }
                }
                Material::Mask { inner, .. } => m = &materials[*inner as usize],
                _ => break,
            }
        }
        SurfaceBsdf {
            bsdf: m.leaf_bsdf(uv),
            flipped,
        }
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

    fn leaf_bsdf(&self, uv: Vec2) -> Bsdf {
        match self {
            Material::Diffuse { reflectance } => Bsdf::Diffuse(Diffuse::new(
                reflectance.eval(uv).clamp(Vec3::ZERO, Vec3::ONE),
            )),
            Material::Conductor { eta, k, specular } => {
                Bsdf::Conductor(Conductor::new(*eta, *k, specular.eval(uv)))
            }
            Material::RoughConductor {
                roughness,
                eta,
                k,
                specular,
            } => Bsdf::RoughConductor(RoughConductor::new(
                roughness.at(uv),
                *eta,
                *k,
                specular.eval(uv),
            )),
            Material::Dielectric {
                eta,
                reflectance,
                transmittance,
            } => Bsdf::Dielectric(Dielectric::new(
                *eta,
                reflectance.eval(uv),
                transmittance.eval(uv),
            )),
            Material::ThinDielectric {
                eta,
                reflectance,
                transmittance,
            } => Bsdf::ThinDielectric(ThinDielectric::new(
                *eta,
                reflectance.eval(uv),
                transmittance.eval(uv),
            )),
            Material::RoughDielectric {
                roughness,
                eta,
                reflectance,
                transmittance,
            } => Bsdf::RoughDielectric(RoughDielectric::new(
                roughness.at(uv),
                *eta,
                reflectance.eval(uv),
                transmittance.eval(uv),
            )),
            Material::Plastic {
                params,
                diffuse,
                specular,
            } => Bsdf::Plastic(Plastic::new(params, diffuse.eval(uv), specular.eval(uv))),
            Material::RoughPlastic {
                params,
                diffuse,
                specular,
            } => Bsdf::RoughPlastic(RoughPlastic::new(
                params,
                diffuse.eval(uv),
                specular.eval(uv),
            )),
            Material::Principled(p) => Bsdf::Principled(Principled {
                base_color: p.base_color.eval(uv),
                roughness: p.roughness.eval_1(uv),
                anisotropic: p.anisotropic.eval_1(uv),
                metallic: p.metallic.eval_1(uv),
                spec_trans: p.spec_trans.eval_1(uv),
                spec_tint: p.spec_tint.eval_1(uv),
                sheen: p.sheen.eval_1(uv),
                sheen_tint: p.sheen_tint.eval_1(uv),
                flatness: p.flatness.eval_1(uv),
                clearcoat: p.clearcoat.eval_1(uv),
                clearcoat_gloss: p.clearcoat_gloss.eval_1(uv),
                eta: p.eta,
                diffuse_rate: p.rates[0],
                specular_rate: p.rates[1],
                clearcoat_rate: p.rates[2],
            }),
            Material::PrincipledThin(p) => Bsdf::PrincipledThin(PrincipledThin {
                base_color: p.base_color.eval(uv),
                roughness: p.roughness.eval_1(uv),
                anisotropic: p.anisotropic.eval_1(uv),
                spec_trans: p.spec_trans.eval_1(uv),
                spec_tint: p.spec_tint.eval_1(uv),
                sheen: p.sheen.eval_1(uv),
                sheen_tint: p.sheen_tint.eval_1(uv),
                flatness: p.flatness.eval_1(uv),
                diff_trans: p.diff_trans.eval_1(uv),
                eta: p.eta.eval_1(uv),
                spec_reflect_rate: p.rates[0],
                spec_trans_rate: p.rates[1],
                diffuse_reflect_rate: p.rates[2],
                diffuse_trans_rate: p.rates[3],
            }),
            // Resolved by `bsdf`; reached only past the nesting bound, as black.
            Material::TwoSided { .. } | Material::Mask { .. } => {
                Bsdf::Diffuse(Diffuse::new(Vec3::ZERO))
            }
        }
    }
}
