//! The parameters of each BSDF as the scene file gives them, one file per BSDF (listed in
//! [`super::bsdf_registry`]): its struct, Mitsuba's (or pbrt's) keys and defaults, the checks
//! beyond "each texture and index of refraction makes sense".

use super::bsdf_registry::{for_each_bsdf, same_name_ignoring_case};
pub(crate) use super::param_error::non_negative;
pub use super::param_error::ParamError;
use super::{IorDesc, TextureDesc};
use serde::{Deserialize, Serialize};

/// A BSDF's parameters in the description.
pub trait BsdfParams {
    /// The `type` of `[materials.NAME]`, Mitsuba's (or pbrt's) plugin name; also its module's.
    const NAME: &'static str;

    /// Every texture the BSDF reads, with its key (each is validated as a texture).
    fn textures(&self) -> Vec<(&'static str, &TextureDesc)>;

    /// The indices of refraction of its interfaces, with their keys (each is validated).
    fn iors(&self) -> Vec<(&'static str, &IorDesc)> {
        Vec::new()
    }

    /// What validation checks beyond [`Self::textures`] and [`Self::iors`].
    fn check(&self) -> Result<(), ParamError> {
        Ok(())
    }
}

macro_rules! define_bsdf_descs {
    ($($(#[$attr:meta])* $Variant:ident($module:ident: $Desc:ident => $Bsdf:ident, $Material:ident)),* $(,)?) => {
        $(pub mod $module;)*
        $(pub use $module::$Desc;)*

        $(const _: () = assert!(
            same_name_ignoring_case(<$Desc as BsdfParams>::NAME, stringify!($module))
                && same_name_ignoring_case(stringify!($Variant), stringify!($module)),
            concat!("`", stringify!($Desc), "::NAME` and the variant must be the module's name")
        );)*
    };
}
for_each_bsdf!(define_bsdf_descs);
pub use coateddiffuse::{LayerDesc, MAX_LAYER_DEPTH, MAX_LAYER_SAMPLES};

/// The microfacet normal distribution.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum DistributionDesc {
    #[default]
    Beckmann,
    Ggx,
}

/// Mitsuba's default roughness.
pub const DEFAULT_ALPHA: f32 = 0.1;

/// Roughness: `alpha` (isotropic) or `alpha_u` and `alpha_v` (anisotropic); 0.1 by default. The
/// rough materials repeat these keys rather than flattening a shared struct, because serde cannot
/// reject unknown keys through `flatten`.
macro_rules! rough_fields {
    ($(#[$m:meta])* pub struct $name:ident { $($body:tt)* }) => {
        $(#[$m])*
        #[derive(Clone, Debug, serde::Deserialize, serde::Serialize, PartialEq)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            $($body)*
            #[serde(default)]
            pub distribution: super::DistributionDesc,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub alpha: Option<TextureDesc>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub alpha_u: Option<TextureDesc>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub alpha_v: Option<TextureDesc>,
            /// Sample only the visible normals (Heitz and d'Eon 2014).
            #[serde(default = "super::yes")]
            pub sample_visible: bool,
        }

        impl $name {
            /// The roughness along u and along v: `alpha_u` and `alpha_v`, else `alpha`, else
            /// [`super::DEFAULT_ALPHA`].
            pub fn alphas(&self) -> (TextureDesc, TextureDesc) {
                let or = |t: &Option<TextureDesc>| {
                    t.as_ref()
                        .or(self.alpha.as_ref())
                        .cloned()
                        .unwrap_or(TextureDesc::Value(super::DEFAULT_ALPHA))
                };
                (or(&self.alpha_u), or(&self.alpha_v))
            }

            fn rough_textures(&self) -> [Option<(&'static str, &TextureDesc)>; 3] {
                [
                    self.alpha.as_ref().map(|t| ("alpha", t)),
                    self.alpha_u.as_ref().map(|t| ("alpha_u", t)),
                    self.alpha_v.as_ref().map(|t| ("alpha_v", t)),
                ]
            }
        }
    };
}
pub(crate) use rough_fields;

pub(crate) fn half() -> TextureDesc {
    TextureDesc::Value(0.5)
}
pub(crate) fn one() -> TextureDesc {
    TextureDesc::Value(1.0)
}
pub(crate) fn zero() -> TextureDesc {
    TextureDesc::Value(0.0)
}
pub(crate) fn one_and_a_half() -> TextureDesc {
    TextureDesc::Value(1.5)
}
pub(crate) fn one_f() -> f32 {
    1.0
}
pub(crate) fn yes() -> bool {
    true
}
pub(crate) fn bk7() -> IorDesc {
    IorDesc::Named("bk7".into())
}
pub(crate) fn air() -> IorDesc {
    IorDesc::Named("air".into())
}
pub(crate) fn polypropylene() -> IorDesc {
    IorDesc::Named("polypropylene".into())
}
