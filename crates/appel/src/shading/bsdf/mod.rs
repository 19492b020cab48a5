//! The BSDFs of the path tracer, matching Mitsuba 3's plugins of the same names (RGB mode,
//! radiance transport): `diffuse`, `conductor`, `roughconductor`, `dielectric`, `thindielectric`,
//! `roughdielectric`, `plastic`, `roughplastic`, `principled`, `principledthin`; pbrt-v4's
//! stochastic layered `coateddiffuse` and `coatedconductor` ([`layered`]); and `phong`, Whitted's
//! model, which the `whitted` and `raycast` integrators read through [`Bsdf::whitted`], the
//! Whitted response every BSDF has.
//!
//! Directions are in the local shading frame (`z` = shading normal, see
//! [`crate::shading::frame::ShadingFrame`]), unit length, both pointing away from the surface: `wo`
//! toward the viewer or previous path vertex, `wi` toward the light or next vertex (pbrt's names;
//! Mitsuba's `si.wi` is `wo` here and its `wo` is `wi`). One-sided BSDFs are black unless both
//! directions are above the surface (`twosided` is the material layer's flip of `z`); dielectrics
//! see both sides, the inside being `wo.z < 0`.
//!
//! A [`Bsdf`] is a plain value built per hit from texture values; what costs more than a few
//! arithmetic operations and depends only on constants is computed once per material at scene
//! load ([`PlasticParams::precompute`], [`RoughPlasticParams::precompute`]).
//!
//! Each BSDF is one line of the registry (`description::bsdf_registry`) and two files:
//! its parameters in the description (`description::bsdf::NAME`) and, here in
//! `bsdf/NAME.rs`, its [`Bsdf`] (sampling and evaluation) and its [`BsdfMaterial`] (textures
//! resolved at a hit).

pub mod fresnel;
pub mod layered;
pub mod microfacet;
pub mod warp;

#[cfg(test)]
mod tests;

pub use microfacet::{Microfacet, MicrofacetKind};
pub use phong::Checker;
pub use plastic::PlasticParams;
pub use principled::PrincipledTextures;
pub use principledthin::PrincipledThinTextures;
pub use roughplastic::{RoughPlasticParams, TRANSMITTANCE_RES};

use crate::description::{for_each_bsdf, DistributionDesc, IorDesc, TextureDesc};
use crate::error::{Error, Result};
use crate::math::{Vec2, Vec3};
use crate::shading::spectra;
use crate::shading::texture::{TexPoint, Texture};
use std::ops::BitOr;

/// The kinds of lobes a BSDF has, or the one a sample came from.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct BsdfFlags(u8);

impl BsdfFlags {
    pub const NONE: BsdfFlags = BsdfFlags(0);
    pub const DIFFUSE_REFLECTION: BsdfFlags = BsdfFlags(1);
    pub const GLOSSY_REFLECTION: BsdfFlags = BsdfFlags(1 << 1);
    pub const DELTA_REFLECTION: BsdfFlags = BsdfFlags(1 << 2);
    pub const DIFFUSE_TRANSMISSION: BsdfFlags = BsdfFlags(1 << 3);
    pub const GLOSSY_TRANSMISSION: BsdfFlags = BsdfFlags(1 << 4);
    /// A delta transmission.
    pub const DELTA_TRANSMISSION: BsdfFlags = BsdfFlags(1 << 5);
    /// Straight through, undeviated (Mitsuba's null lobe: the `null` BSDF and the transmission of
    /// [`ThinDielectric`]; the direction is `-wo`, the eta of the sample 1): a delta
    /// transmission that the volumetric path tracer counts as no bounce at all and that its
    /// shadow rays cross with [`Bsdf::null_transmission`].
    pub const NULL: BsdfFlags = BsdfFlags(1 << 6 | 1 << 5);
    const DELTA: u8 = Self::DELTA_REFLECTION.0 | Self::DELTA_TRANSMISSION.0;

    /// Whether every lobe of `other` is in `self`.
    #[inline]
    pub fn contains(self, other: BsdfFlags) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether there is a delta lobe (one `eval` and `pdf` cannot see).
    #[inline]
    pub fn is_delta(self) -> bool {
        self.0 & Self::DELTA != 0
    }

    /// Whether there is a lobe that is not a delta (one that light sampling can reach); the null
    /// lobe is a delta transmission.
    #[inline]
    pub fn has_smooth(self) -> bool {
        self.0 & !(Self::DELTA | Self::NULL.0) != 0
    }
}

impl BitOr for BsdfFlags {
    type Output = BsdfFlags;
    #[inline]
    fn bitor(self, rhs: BsdfFlags) -> BsdfFlags {
        BsdfFlags(self.0 | rhs.0)
    }
}

/// A sampled direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// The sampled direction, local.
    pub wi: Vec3,
    /// `eval(wo, wi) / pdf` (the cosine included); for a delta lobe the throughput factor itself,
    /// as Mitsuba's `BSDF::sample` returns it.
    pub weight: Vec3,
    /// Solid-angle density of `wi`, times the probability of the lobe; for a delta lobe the
    /// probability of having chosen it.
    pub pdf: f32,
    /// Relative IOR of the crossing (Mitsuba's `bs.eta`): the inside's over the outside's when
    /// entering, its inverse when leaving, 1 for reflection.
    pub eta: f32,
    /// The one lobe that was sampled.
    pub lobe: BsdfFlags,
}

/// A BSDF of plain values at one surface point. Written for one direction pair at a time; the
/// methods are generic only in the sense of taking plain vectors, so that a BSDF can later be
/// written over a lane type as well (see docs/architecture.md).
pub trait Bsdf: Copy {
    /// `f(wo, wi) |cos θi|` (Mitsuba's `BSDF::eval` convention); zero for delta lobes, and zero
    /// by default: a BSDF of delta lobes only need not define it.
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let _ = (wo, wi);
        Vec3::ZERO
    }

    /// Solid-angle density of [`Bsdf::sample`] returning `wi`; zero for delta lobes (the
    /// default, as for [`Bsdf::eval`]).
    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let _ = (wo, wi);
        0.0
    }

    /// [`Bsdf::eval`] and [`Bsdf::pdf`] together; BSDFs whose two share work override it.
    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        (self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// A direction `wi` for `wo`: `u1` chooses the lobe, `u2` the direction in it. `None` when
    /// nothing can be sampled (the wrong side of a one-sided BSDF, a direction below the horizon,
    /// a sample carrying no energy).
    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample>;

    /// The lobes this BSDF has.
    fn flags(&self) -> BsdfFlags;

    /// The BSDF as the `whitted` and `raycast` integrators see it, its lobes as Phong's
    /// ([`phong`]): a diffuse lobe as the Lambertian one, delta reflection as the mirror, delta
    /// refraction as the refraction (with the Fresnel weights of the dielectric), a glossy coating
    /// as a Blinn highlight. Those integrators follow delta directions only, so rough metals are
    /// mirrors and rough glass is smooth glass.
    fn whitted(&self) -> Phong;

    /// The weight of light passing straight through the surface unchanged, without a bounce
    /// (Mitsuba's `eval_null_transmission`), which shadow rays of the volumetric path tracer
    /// cross: zero but for BSDFs with a [`BsdfFlags::NULL`] lobe.
    #[inline]
    fn null_transmission(&self, wo: Vec3) -> Vec3 {
        let _ = wo;
        Vec3::ZERO
    }

    /// The BSDF as pbrt-v4's `regularize` option sees it after a path's first non-specular
    /// bounce (pbrt-v4's `BxDF::Regularize`): every microfacet roughness below 0.3 widened by
    /// [`Microfacet::regularized`], a smooth (delta) lobe replaced by its rough twin of roughness
    /// 0.1, so that paths through near-specular surfaces (caustics seen in a mirror) become
    /// findable by light sampling and connections, at the price of bias. May be another BSDF
    /// (a smooth `dielectric` becomes a `roughdielectric`). The default, for BSDFs with nothing
    /// near-specular to widen (diffuse lobes, the null lobe), is the BSDF unchanged.
    fn regularized(&self) -> AnyBsdf
    where
        Self: Into<AnyBsdf>,
    {
        (*self).into()
    }
}

/// Where a material's textures come from: the scene's cache of decoded images.
pub trait TextureSource {
    fn texture(&mut self, d: &TextureDesc) -> Result<Texture>;
}

/// A BSDF's textured parameters, built once from its description and resolved at each hit into
/// its [`Bsdf`] of plain values (pbrt-v4's Material -> BSDF split).
pub trait BsdfMaterial: Sized {
    /// Its parameters in the description.
    type Desc;
    /// What it resolves to at a surface point.
    type Bsdf: Bsdf;

    /// Resolves the description's textures and precomputes what depends only on constants. The
    /// description has been validated: what validation rejects may be an error here too, with a
    /// message, never a panic.
    fn build(desc: &Self::Desc, textures: &mut dyn TextureSource) -> Result<Self>;

    /// The BSDF at a surface point.
    fn at(&self, p: &TexPoint) -> Self::Bsdf;
}

macro_rules! define_bsdfs {
    ($($(#[$attr:meta])* $Variant:ident($module:ident: $Desc:ident => $Bsdf:ident, $Material:ident)),* $(,)?) => {
        $(pub mod $module;)*
        $(pub use $module::{$Bsdf, $Material};)*

        /// One of the BSDFs, matched once per call, then the BSDF's own code, inlined (no
        /// dynamic dispatch).
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum AnyBsdf {
            $($Variant($Bsdf),)*
        }

        impl AnyBsdf {
            /// See [`Bsdf::eval`].
            #[inline]
            pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
                match self {
                    $(AnyBsdf::$Variant(b) => b.eval(wo, wi),)*
                }
            }

            /// See [`Bsdf::pdf`].
            #[inline]
            pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
                match self {
                    $(AnyBsdf::$Variant(b) => b.pdf(wo, wi),)*
                }
            }

            /// See [`Bsdf::eval_pdf`].
            #[inline]
            pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
                match self {
                    $(AnyBsdf::$Variant(b) => b.eval_pdf(wo, wi),)*
                }
            }

            /// See [`Bsdf::sample`].
            #[inline]
            pub fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
                match self {
                    $(AnyBsdf::$Variant(b) => b.sample(wo, u1, u2),)*
                }
            }

            /// See [`Bsdf::flags`].
            #[inline]
            pub fn flags(&self) -> BsdfFlags {
                match self {
                    $(AnyBsdf::$Variant(b) => b.flags(),)*
                }
            }

            /// See [`Bsdf::null_transmission`].
            #[inline]
            pub fn null_transmission(&self, wo: Vec3) -> Vec3 {
                match self {
                    $(AnyBsdf::$Variant(b) => b.null_transmission(wo),)*
                }
            }

            /// See [`Bsdf::whitted`].
            #[inline]
            pub fn whitted(&self) -> Phong {
                match self {
                    $(AnyBsdf::$Variant(b) => b.whitted(),)*
                }
            }

            /// See [`Bsdf::regularized`].
            #[inline]
            pub fn regularized(&self) -> AnyBsdf {
                match self {
                    $(AnyBsdf::$Variant(b) => b.regularized(),)*
                }
            }
        }

        $(impl From<$Bsdf> for AnyBsdf {
            #[inline]
            fn from(b: $Bsdf) -> AnyBsdf {
                AnyBsdf::$Variant(b)
            }
        })*
    };
}
for_each_bsdf!(define_bsdfs);

/// A microfacet distribution whose roughness may vary over the surface.
#[derive(Clone, Debug)]
pub struct Roughness {
    pub kind: MicrofacetKind,
    pub alpha_u: Texture,
    pub alpha_v: Texture,
    pub sample_visible: bool,
}

impl Roughness {
    /// The textures of a description's `(alpha_u, alpha_v)`.
    pub fn build(
        kind: MicrofacetKind,
        (alpha_u, alpha_v): (TextureDesc, TextureDesc),
        sample_visible: bool,
        textures: &mut dyn TextureSource,
    ) -> Result<Self> {
        Ok(Roughness {
            kind,
            alpha_u: textures.texture(&alpha_u)?,
            alpha_v: textures.texture(&alpha_v)?,
            sample_visible,
        })
    }

    #[inline]
    pub fn at(&self, p: &TexPoint) -> Microfacet {
        Microfacet::new(
            self.kind,
            self.alpha_u.eval_1_at(p),
            self.alpha_v.eval_1_at(p),
            self.sample_visible,
        )
    }
}

impl From<DistributionDesc> for MicrofacetKind {
    fn from(d: DistributionDesc) -> Self {
        match d {
            DistributionDesc::Beckmann => MicrofacetKind::Beckmann,
            DistributionDesc::Ggx => MicrofacetKind::Ggx,
        }
    }
}

/// An index of refraction: a positive number or one of Mitsuba's names.
pub(crate) fn ior(i: &IorDesc) -> Result<f32> {
    match i {
        IorDesc::Value(v) if v.is_finite() && *v > 0.0 => Ok(*v),
        IorDesc::Value(v) => Err(Error::Invalid(format!(
            "an index of refraction must be positive, got {v}"
        ))),
        IorDesc::Named(n) => spectra::ior(n).ok_or_else(|| {
            Error::Invalid(format!(
                "unknown index of refraction `{n}`, expected a number or one of: {}",
                spectra::IOR_NAMES.join(", ")
            ))
        }),
    }
}

/// The relative index of an interface: inside over outside.
pub(crate) fn ior_ratio(int: &IorDesc, ext: &IorDesc) -> Result<f32> {
    Ok(ior(int)? / ior(ext)?)
}

/// The channel mean of a texture's mean, as Mitsuba's `Texture::mean` for lobe weights.
pub(crate) fn texture_mean(t: &Texture) -> f32 {
    let m = t.mean();
    (m.x + m.y + m.z) / 3.0
}

/// `v` with its sign flipped where `s` is negative (Mitsuba's `mulsign`).
#[inline]
pub(crate) fn mulsign(v: Vec3, s: f32) -> Vec3 {
    if s.is_sign_negative() {
        -v
    } else {
        v
    }
}
