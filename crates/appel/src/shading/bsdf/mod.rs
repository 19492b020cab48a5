//! The BSDFs of the path tracer, matching Mitsuba 3's plugins of the same names (RGB mode,
//! radiance transport): `diffuse`, `conductor`, `roughconductor`, `dielectric`, `thindielectric`,
//! `roughdielectric`, `plastic`, `roughplastic`, `principled`, `principledthin`; and `phong`,
//! Whitted's model, which the `whitted` and `raycast` integrators read through
//! [`Bsdf::whitted`], the Whitted response every BSDF has.
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

mod conductor;
mod dielectric;
mod diffuse;
pub mod fresnel;
pub mod microfacet;
mod phong;
mod plastic;
pub mod principled;
mod principledthin;
mod roughconductor;
mod roughdielectric;
mod roughplastic;
mod thindielectric;
pub mod warp;

#[cfg(test)]
mod tests;

pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
pub use microfacet::{Microfacet, MicrofacetKind};
pub use phong::{Checker, Phong, PhongParams};
pub use plastic::{Plastic, PlasticParams};
pub use principled::Principled;
pub use principledthin::PrincipledThin;
pub use roughconductor::RoughConductor;
pub use roughdielectric::RoughDielectric;
pub use roughplastic::{RoughPlastic, RoughPlasticParams, TRANSMITTANCE_RES};
pub use thindielectric::ThinDielectric;

use crate::math::{Vec2, Vec3};
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
    /// A delta transmission; also the straight-through lobe of [`ThinDielectric`] (Mitsuba's
    /// "null" lobe: the direction is `-wo`, the eta of the sample 1).
    pub const DELTA_TRANSMISSION: BsdfFlags = BsdfFlags(1 << 5);
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

    /// Whether there is a lobe that is not a delta (one that light sampling can reach).
    #[inline]
    pub fn has_smooth(self) -> bool {
        self.0 & !Self::DELTA != 0
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

/// One of the BSDFs, matched once per call.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf {
    Diffuse(Diffuse),
    Conductor(Conductor),
    RoughConductor(RoughConductor),
    Dielectric(Dielectric),
    ThinDielectric(ThinDielectric),
    RoughDielectric(RoughDielectric),
    Plastic(Plastic),
    RoughPlastic(RoughPlastic),
    Principled(Principled),
    PrincipledThin(PrincipledThin),
    Phong(Phong),
}

macro_rules! dispatch {
    ($self:ident, $b:ident => $e:expr) => {
        match $self {
            Bsdf::Diffuse($b) => $e,
            Bsdf::Conductor($b) => $e,
            Bsdf::RoughConductor($b) => $e,
            Bsdf::Dielectric($b) => $e,
            Bsdf::ThinDielectric($b) => $e,
            Bsdf::RoughDielectric($b) => $e,
            Bsdf::Plastic($b) => $e,
            Bsdf::RoughPlastic($b) => $e,
            Bsdf::Principled($b) => $e,
            Bsdf::PrincipledThin($b) => $e,
            Bsdf::Phong($b) => $e,
        }
    };
}

impl Bsdf {
    /// `f(wo, wi) |cos θi|` (Mitsuba's `BSDF::eval` convention); zero for delta lobes.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        dispatch!(self, b => b.eval(wo, wi))
    }

    /// Solid-angle density of [`Bsdf::sample`] returning `wi`; zero for delta lobes.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        dispatch!(self, b => b.pdf(wo, wi))
    }

    /// [`Bsdf::eval`] and [`Bsdf::pdf`] together, sharing their common work.
    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        dispatch!(self, b => b.eval_pdf(wo, wi))
    }

    /// A direction `wi` for `wo`: `u1` chooses the lobe, `u2` the direction in it. `None` when
    /// nothing can be sampled (the wrong side of a one-sided BSDF, a direction below the horizon,
    /// a sample carrying no energy).
    #[inline]
    pub fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        dispatch!(self, b => b.sample(wo, u1, u2))
    }

    /// The lobes this BSDF has.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        dispatch!(self, b => b.flags())
    }
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
