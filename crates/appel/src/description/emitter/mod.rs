//! The parameters of each emitter as the scene file gives them, one file per emitter (listed in
//! [`super::emitter_registry`]): its struct, Mitsuba's keys and defaults, and its checks. The
//! `[[light]]` table, [`LightDesc`], is generated from the same list.

use super::emitter_registry::for_each_emitter;
use super::param_error::ParamError;
use super::{TransformDesc, Vec3f};
use serde::{Deserialize, Serialize};

pub mod area;
pub mod constant;
pub mod directional;
pub mod envmap;
pub mod equal_area_envmap;
pub mod point;
pub mod projector;
pub mod spot;
pub mod sunsky;

pub use area::AreaEmitterDesc;
pub use constant::ConstantDesc;
pub use directional::DirectionalDesc;
pub use envmap::EnvMapDesc;
pub use equal_area_envmap::EqualAreaEnvMapDesc;
pub use point::PointDesc;
pub use projector::ProjectorDesc;
pub use spot::SpotDesc;
pub use sunsky::{SunPlaceDesc, SunSkyDesc, SunTime};

/// An emitter's parameters in the description.
pub trait EmitterParams {
    /// Its name in the registry (`[[light]] type`, Mitsuba's plugin name).
    const NAME: &'static str;

    /// What makes no sense in the values as given (ranges, zero vectors, contradictions).
    fn check(&self) -> Result<(), ParamError>;

    /// Its transform, validated as every transform is.
    fn transform(&self) -> Option<&TransformDesc> {
        None
    }

    /// Scales the scene around the light by `s` ([`super::Description::scaled`]): positions by
    /// `s`, and the power of lights that fall off with the inverse square of the distance by
    /// `s^2`, so that the image stays the same. The default, nothing, is that of lights at
    /// infinity.
    fn scale(&mut self, _s: f32) {}
}

macro_rules! define_light_desc {
    ($($Variant:ident { name: $name:ident, runtime: $module:ident::$Type:ident, light: [$($Desc:ident)?] }),* $(,)?) => {
        /// `[[light]]`: an emitter that is not a surface (surfaces emit through a shape's
        /// `emitter` key), one variant per light of the registry, each documented by its
        /// parameters' struct.
        #[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
        #[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
        pub enum LightDesc {
            $($($Variant($Desc),)?)*
        }

        $($(const _: () = assert!(
            super::bsdf_registry::same_name_ignoring_case(<$Desc as EmitterParams>::NAME, stringify!($name))
                && super::bsdf_registry::same_name_ignoring_case(stringify!($Variant), stringify!($name)),
            concat!("`", stringify!($Desc), "::NAME` and the variant must be the emitter's name")
        );)?)*

        impl LightDesc {
            /// See [`EmitterParams::check`].
            pub fn check(&self) -> Result<(), ParamError> {
                match self {
                    $($(LightDesc::$Variant(d) => <$Desc as EmitterParams>::check(d),)?)*
                }
            }

            /// See [`EmitterParams::transform`].
            pub fn transform(&self) -> Option<&TransformDesc> {
                match self {
                    $($(LightDesc::$Variant(d) => <$Desc as EmitterParams>::transform(d),)?)*
                }
            }

            /// See [`EmitterParams::scale`].
            pub fn scale(&mut self, s: f32) {
                match self {
                    $($(LightDesc::$Variant(d) => <$Desc as EmitterParams>::scale(d, s),)?)*
                }
            }
        }
    };
}
for_each_emitter!(define_light_desc);

pub(crate) fn white() -> Vec3f {
    [1.0; 3]
}
pub(crate) fn unit() -> f32 {
    1.0
}

/// Scales a position by `s`.
pub(crate) fn scale_point(v: &mut Vec3f, s: f32) {
    *v = v.map(|x| x * s);
}

/// Checks a light looking from `position` at `look_at`.
pub(crate) fn check_aim(position: &Vec3f, look_at: &Vec3f) -> Result<(), ParamError> {
    super::param_error::finite("position", position)?;
    super::param_error::finite("look_at", look_at)?;
    if position == look_at {
        return Err(ParamError::new(
            "look_at",
            "`look_at` must differ from `position`",
        ));
    }
    Ok(())
}
