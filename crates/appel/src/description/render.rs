//! `[render]` and the camera's closed sets of names: every name here is a serde enum, so an
//! unknown one is a parse error at its line.

use super::IntegratorName;
use crate::accel::{AccelOptions, BadOption, Structure};
use serde::{Deserialize, Serialize};

/// `[render]`, with one optional `[render.NAME]` table of build options per registered
/// acceleration structure (`accel/registry.rs`).
/// `[render]` also has one optional `[render.NAME]` table of parameters per registered
/// integrator (`integrator_registry.rs`).
macro_rules! render_desc {
    (
        structures: [$($Variant:ident($module:ident::$Type:ident)),* $(,)?];
        $($IVariant:ident { name: $iname:ident, runtime: $imodule:ident::$IType:ident, params: $IParams:ident, sampler: $isampler:ident, monte_carlo: $imc:literal, media: $imedia:literal }),* $(,)?
    ) => {
        #[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
        #[serde(deny_unknown_fields)]
        pub struct RenderDesc {
            #[serde(default)]
            pub integrator: IntegratorName,
            /// Whitted: the deepest recursion. Path and direct: Mitsuba's meaning, the most vertices of a
            /// path (1: emitters seen directly; 2: direct light; -1: unlimited).
            #[serde(default = "default_max_depth")]
            pub max_depth: i32,
            /// Path: the depth from which Russian roulette may end paths (Mitsuba's `rr_depth`).
            #[serde(default = "default_rr_depth")]
            pub rr_depth: u32,
            /// Path and direct: emitters seen directly by the camera are black.
            #[serde(default)]
            pub hide_emitters: bool,
            #[serde(default = "default_accel")]
            pub accel: String,
            /// Samples per pixel. Raycast and Whitted: 1 means exactly the pixel centre.
            #[serde(default = "default_spp")]
            pub spp: u32,
            /// How samples are drawn; unset, the integrator's own choice ([`IntegratorName::sampler`]).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub sampler: Option<SamplerName>,
            /// Another seed gives another (equally valid) noise pattern.
            #[serde(default)]
            pub seed: u64,
            /// The reconstruction filter through which samples reach pixels.
            #[serde(default)]
            pub filter: FilterDesc,
            /// Ray-triangle test: "watertight" or "moller".
            #[serde(default = "default_triangle")]
            pub triangle: String,
            $(
                #[doc = concat!("`[render.", stringify!($module), "]`: how the structure `",
                    stringify!($module), "` is built (when `accel` names it).")]
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $module: Option<<crate::accel::$Type as Structure>::Options>,
            )*
            $(
                #[doc = concat!("`[render.", stringify!($iname), "]`: the parameters of the integrator `",
                    stringify!($iname), "` (when `integrator` names it).")]
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $iname: Option<super::$IParams>,
            )*
        }

        impl Default for RenderDesc {
            fn default() -> Self {
                Self {
                    integrator: IntegratorName::default(),
                    max_depth: default_max_depth(),
                    rr_depth: default_rr_depth(),
                    hide_emitters: false,
                    accel: default_accel(),
                    spp: default_spp(),
                    sampler: None,
                    seed: 0,
                    filter: FilterDesc::default(),
                    triangle: default_triangle(),
                    $($module: None,)*
                    $($iname: None,)*
                }
            }
        }

        impl RenderDesc {
            /// The structures' build options: `[render.NAME]` where the file gives it, the
            /// defaults elsewhere.
            pub fn accel_options(&self) -> AccelOptions {
                AccelOptions {
                    $($module: self.$module.unwrap_or_default(),)*
                }
            }

            /// The first option of a `[render.NAME]` table that makes no sense: the table's name and
            /// the problem.
            pub fn check_accel_options(&self) -> Result<(), (&'static str, BadOption)> {
                $(if let Some(o) = &self.$module {
                    <crate::accel::$Type as Structure>::check_options(o)
                        .map_err(|e| (stringify!($module), e))?;
                })*
                Ok(())
            }

            /// The integrators' parameters: `[render.NAME]` where the file gives it, the defaults
            /// elsewhere.
            pub fn integrator_params(&self) -> super::IntegratorParams {
                super::IntegratorParams {
                    $($iname: self.$iname.clone().unwrap_or_default(),)*
                }
            }

            /// The integrator whose image the film holds: the one nested in `integrator` (as in
            /// `aov`) if its table names one, else `integrator`.
            pub fn image_integrator(&self) -> IntegratorName {
                let nested = match self.integrator {
                    $(IntegratorName::$IVariant => self.$iname.as_ref().and_then(super::IntegratorTable::nested),)*
                };
                nested.unwrap_or(self.integrator)
            }

            /// The first parameter of a `[render.NAME]` integrator table that makes no sense: the
            /// table's name, the key and the problem.
            pub fn check_integrator_params(&self) -> Result<(), (&'static str, &'static str, String)> {
                $(if let Some(p) = &self.$iname {
                    super::IntegratorTable::check(p).map_err(|(k, e)| (stringify!($iname), k, e))?;
                })*
                Ok(())
            }
        }
    };
}

/// Hands the structures to the integrator list, which calls [`render_desc`] with both.
macro_rules! render_desc_of_structures {
    ($($Variant:ident($module:ident::$Type:ident)),* $(,)?) => {
        super::for_each_integrator!(render_desc(structures: [$($Variant($module::$Type)),*];));
    };
}
crate::accel::for_each_structure!(render_desc_of_structures);

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SamplerName {
    /// Independent uniform numbers (PCG32).
    #[default]
    Independent,
    /// Owen-scrambled Sobol points (low discrepancy).
    Sobol,
    /// The same film positions in every pixel, the centre first then the R2 sequence; the other
    /// dimensions independent.
    PixelPattern,
}

impl SamplerName {
    pub const NAMES: &'static [&'static str] = &["independent", "sobol", "pixel_pattern"];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "independent" => Some(Self::Independent),
            "sobol" => Some(Self::Sobol),
            "pixel_pattern" => Some(Self::PixelPattern),
            _ => None,
        }
    }
}

/// A pixel reconstruction filter, with Mitsuba's parameters and defaults.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum FilterDesc {
    /// Each sample counts only in its own pixel.
    Box {
        #[serde(default = "half")]
        radius: f32,
    },
    /// A triangle of radius `radius` pixels.
    Tent {
        #[serde(default = "one")]
        radius: f32,
    },
    /// A Gaussian of standard deviation `stddev` pixels, cut at 4 standard deviations.
    Gaussian {
        #[serde(default = "half")]
        stddev: f32,
    },
}

impl Default for FilterDesc {
    fn default() -> Self {
        FilterDesc::Box { radius: 0.5 }
    }
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum CameraKind {
    #[default]
    Perspective,
    Orthographic,
}

/// The image axis a perspective camera's field of view spans (Mitsuba's `fov_axis`).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FovAxis {
    X,
    #[default]
    Y,
    Diagonal,
    Smaller,
    Larger,
}

fn half() -> f32 {
    0.5
}
fn one() -> f32 {
    1.0
}
fn default_max_depth() -> i32 {
    5
}
fn default_rr_depth() -> u32 {
    5
}
fn default_accel() -> String {
    crate::accel::AccelKind::default().name().into()
}
fn default_spp() -> u32 {
    1
}
fn default_triangle() -> String {
    "watertight".into()
}
