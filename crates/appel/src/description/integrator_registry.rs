//! The one list of integrators. Everything that enumerates integrators is generated from it: the
//! description's [`IntegratorName`] with its names, parsing and error list, the `[render.NAME]`
//! table of an integrator's own parameters ([`IntegratorParams`]), the sampler an integrator
//! takes when `[render]` names none, and the render dispatch (`render/mod.rs`, which checks at
//! compile time that each runtime type's `Integrator::NAME` is its name here).

/// Calls macro `$then!` with every integrator as
/// `Variant { name, runtime, params, sampler, monte_carlo, media }`:
/// - `name`: what `render.integrator`, `--integrator` and the formats' mappings call it;
/// - `runtime`: the type in `render/` (`module::Type`) that implements `render::Integrator`;
/// - `params`: the description type of its `[render.NAME]` table ([`NoParams`] when it has
///   none; `max_depth`, `rr_depth` and `hide_emitters` are shared keys of `[render]`);
/// - `sampler`: the [`super::SamplerName`] used when `[render]` names none;
/// - `monte_carlo`: whether it estimates light transport by sampling (then `max_depth = -1`
///   means unlimited, and its images have a variance);
/// - `media`: whether it traces participating media (the others pass through `null` surfaces
///   and see no medium, as Mitsuba 3's `path` does).
///
/// Adding an integrator is its runtime file, its parameters' file if it has parameters, one line
/// here, and the format mappings that name it. The order is the order of
/// [`IntegratorName::NAMES`]; `$then` may be given leading tokens to carry (`$then!(tokens)`).
macro_rules! for_each_integrator {
    ($then:ident $(($($carry:tt)*))?) => {
        $then! {
            $($($carry)*)?
            Raycast { name: raycast, runtime: whitted::Raycast, params: NoParams, sampler: PixelPattern, monte_carlo: false, media: false },
            Whitted { name: whitted, runtime: whitted::Whitted, params: NoParams, sampler: PixelPattern, monte_carlo: false, media: false },
            Path { name: path, runtime: path::PathTracer, params: NoParams, sampler: Independent, monte_carlo: true, media: false },
            Direct { name: direct, runtime: direct::Direct, params: NoParams, sampler: Independent, monte_carlo: true, media: false },
            VolPath { name: volpath, runtime: volpath::VolPath, params: NoParams, sampler: Independent, monte_carlo: true, media: true },
            Aov { name: aov, runtime: aov::Aov, params: AovParams, sampler: Independent, monte_carlo: true, media: false },
            Bdpt { name: bdpt, runtime: bdpt::Bdpt, params: BdptParams, sampler: Independent, monte_carlo: true, media: false },
            Ptracer { name: ptracer, runtime: ptracer::ParticleTracer, params: PtracerParams, sampler: Independent, monte_carlo: true, media: false },
            Sppm { name: sppm, runtime: sppm::Sppm, params: SppmParams, sampler: Independent, monte_carlo: true, media: false },
        }
    };
}
pub(crate) use for_each_integrator;

use super::integrator::{AovParams, BdptParams, PtracerParams, SppmParams};
use super::SamplerName;
use serde::{Deserialize, Deserializer, Serialize};

/// The parameters of an integrator that has no `[render.NAME]` table: such a table is an error
/// (its settings are the shared keys of `[render]`).
#[derive(Clone, Copy, Debug, Default, Serialize, PartialEq, Eq)]
pub struct NoParams {}

impl<'de> Deserialize<'de> for NoParams {
    fn deserialize<D: Deserializer<'de>>(_: D) -> Result<Self, D::Error> {
        Err(serde::de::Error::custom(
            "this integrator has no table of its own: its settings (max_depth, rr_depth, \
             hide_emitters) are keys of [render]",
        ))
    }
}

/// A `[render.NAME]` table of an integrator's parameters.
pub trait IntegratorTable {
    /// The first problem of the table: the key and what is wrong.
    fn check(&self) -> Result<(), (&'static str, String)> {
        Ok(())
    }

    /// The integrator nested in this one, whose image the film holds (`aov`'s).
    fn nested(&self) -> Option<IntegratorName> {
        None
    }
}

impl IntegratorTable for NoParams {}

macro_rules! define_integrator_names {
    ($($Variant:ident { name: $name:ident, runtime: $module:ident::$Type:ident, params: $Params:ident, sampler: $sampler:ident, monte_carlo: $mc:literal, media: $media:literal }),* $(,)?) => {
        /// Which integrator renders the scene (`render.integrator`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
        #[serde(try_from = "String", into = "&'static str")]
        pub enum IntegratorName {
            $($Variant,)*
        }

        impl IntegratorName {
            /// Every integrator, in the registry's order.
            pub const ALL: &'static [IntegratorName] = &[$(IntegratorName::$Variant,)*];
            pub const NAMES: &'static [&'static str] = &[$(stringify!($name),)*];

            pub fn from_name(name: &str) -> Option<Self> {
                match name {
                    $(stringify!($name) => Some(Self::$Variant),)*
                    _ => None,
                }
            }

            pub fn name(self) -> &'static str {
                match self {
                    $(Self::$Variant => stringify!($name),)*
                }
            }

            /// Whether the integrator samples light transport.
            pub fn is_monte_carlo(self) -> bool {
                match self {
                    $(Self::$Variant => $mc,)*
                }
            }

            /// Whether the integrator traces participating media.
            pub fn traces_media(self) -> bool {
                match self {
                    $(Self::$Variant => $media,)*
                }
            }

            /// The sampler used when `[render]` names none: raycast and Whitted look through the
            /// pixel centre first (their images at one sample per pixel are the convention's),
            /// the Monte Carlo integrators draw independent numbers as Mitsuba's default
            /// sampler does.
            pub fn sampler(self, named: Option<SamplerName>) -> SamplerName {
                named.unwrap_or(match self {
                    $(Self::$Variant => SamplerName::$sampler,)*
                })
            }
        }

        /// The `[render.NAME]` tables of the integrators, each under its name (the defaults
        /// where the file gives none); the integrator that renders reads its own.
        #[derive(Clone, Debug, Default, PartialEq)]
        pub struct IntegratorParams {
            $(pub $name: $Params,)*
        }
    };
}
for_each_integrator!(define_integrator_names);

// The enum is generated from the registry's list, where no variant can carry `#[default]`.
#[allow(clippy::derivable_impls)]
impl Default for IntegratorName {
    fn default() -> Self {
        IntegratorName::Whitted
    }
}

impl TryFrom<String> for IntegratorName {
    type Error = String;

    fn try_from(name: String) -> Result<Self, String> {
        Self::from_name(&name).ok_or_else(|| {
            format!(
                "unknown integrator `{name}`, expected one of: {}",
                Self::NAMES.join(", ")
            )
        })
    }
}

impl From<IntegratorName> for &'static str {
    fn from(i: IntegratorName) -> Self {
        i.name()
    }
}

impl std::fmt::Display for IntegratorName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
