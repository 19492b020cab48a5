//! `[media.NAME]`: participating media, after Mitsuba 3's `homogeneous` and `heterogeneous`
//! plugins, each with its phase function and the volumes its coefficients come from. Shapes name
//! the media on their two sides (`interior`, `exterior`) and the camera the one it sits in
//! (`[camera] medium`). The lists are in [`super::medium_registry`].

use super::medium_registry::{for_each_medium, for_each_phase};
use super::param_error::ParamError;
use super::{TransformDesc, Vec3f};
use serde::{Deserialize, Serialize};

/// A constant colour: one number for every channel, or `[r, g, b]`.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum ColorDesc {
    Value(f32),
    Rgb(Vec3f),
}

impl ColorDesc {
    pub fn rgb(self) -> Vec3f {
        match self {
            ColorDesc::Value(v) => [v; 3],
            ColorDesc::Rgb(c) => c,
        }
    }
}

/// A medium's coefficient over space: a constant, or a volume object.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum VolumeDesc {
    Value(f32),
    Rgb(Vec3f),
    Volume(VolumeNode),
}

/// Mitsuba's volumes: a value over the unit cube `[0, 1]^3`, placed by `transform`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum VolumeNode {
    /// The same value everywhere (its box only bounds a heterogeneous medium).
    ConstVolume {
        value: ColorDesc,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        transform: Option<TransformDesc>,
    },
    /// A Mitsuba `.vol` grid of one or three channels, its samples at the centres of the cells
    /// that divide the unit cube, interpolated trilinearly (or `filter = "nearest"`) and clamped
    /// at the border.
    /// A grid written out in the scene (pbrt's `uniformgrid`): `channels` (1 or 3) values per
    /// cell, x fastest, looked up as a `gridvolume`'s.
    Values {
        resolution: [usize; 3],
        channels: usize,
        values: Vec<f32>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        transform: Option<TransformDesc>,
    },
    GridVolume {
        /// Relative to the scene file's folder.
        file: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        transform: Option<TransformDesc>,
        #[serde(default, skip_serializing_if = "is_default")]
        filter: VolumeFilter,
    },
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum VolumeFilter {
    #[default]
    Trilinear,
    Nearest,
}

impl VolumeDesc {
    /// The constant colour, if the volume is one.
    pub fn constant(&self) -> Option<Vec3f> {
        match self {
            VolumeDesc::Value(v) => Some([*v; 3]),
            VolumeDesc::Rgb(c) => Some(*c),
            VolumeDesc::Volume(VolumeNode::ConstVolume { value, .. }) => Some(value.rgb()),
            VolumeDesc::Volume(VolumeNode::GridVolume { .. } | VolumeNode::Values { .. }) => None,
        }
    }

    fn check(&self, key: &'static str, max: Option<f32>) -> Result<(), ParamError> {
        if let Some(c) = self.constant() {
            super::param_error::non_negative(key, &c)?;
            if let Some(m) = max.filter(|m| c.iter().any(|x| x > m)) {
                return Err(ParamError::new(
                    key,
                    format!("`{key}` must lie in [0, {m}], got {c:?}"),
                ));
            }
        }
        if let VolumeDesc::Volume(VolumeNode::GridVolume { file, .. }) = self {
            if file.is_empty() {
                return Err(ParamError::new(key, "a gridvolume needs a `file`"));
            }
        }
        if let VolumeDesc::Volume(VolumeNode::Values {
            resolution,
            channels,
            values,
            ..
        }) = self
        {
            let cells = resolution.iter().product::<usize>();
            if !matches!(channels, 1 | 3) || cells == 0 || values.len() != cells * channels {
                return Err(ParamError::new(
                    key,
                    format!(
                        "a grid of {resolution:?} cells and {channels} channel(s) (1 or 3) needs \
                         {} values, got {}",
                        cells * channels,
                        values.len()
                    ),
                ));
            }
            super::param_error::non_negative(key, values)?;
        }
        Ok(())
    }

    /// The volume's transform, if it has one.
    pub fn transform(&self) -> Option<&TransformDesc> {
        match self {
            VolumeDesc::Volume(
                VolumeNode::ConstVolume { transform, .. }
                | VolumeNode::GridVolume { transform, .. }
                | VolumeNode::Values { transform, .. },
            ) => transform.as_ref(),
            _ => None,
        }
    }
}

/// A medium's parameters in the description.
pub trait MediumParams {
    /// Its name in the registry (`type`, Mitsuba's plugin name).
    const NAME: &'static str;
    fn check(&self) -> Result<(), ParamError>;
    fn phase(&self) -> &PhaseDesc;
}

/// A phase function's parameters in the description.
pub trait PhaseParams {
    const NAME: &'static str;
    fn check(&self) -> Result<(), ParamError> {
        Ok(())
    }
}

/// Mitsuba's `homogeneous`: the same extinction everywhere (the albedo may vary), given as
/// `sigma_t` and `albedo` (Mitsuba 3) or as `sigma_a` and `sigma_s` (pbrt, Mitsuba 0.6); `scale`
/// multiplies the extinction. The medium fills all of space on its side of the surfaces that name
/// it.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HomogeneousDesc {
    /// Extinction per scene unit (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_t: Option<ColorDesc>,
    /// Single-scattering albedo, in [0, 1] (default 0.75).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub albedo: Option<VolumeDesc>,
    /// Absorption per scene unit, with `sigma_s` instead of `sigma_t` and `albedo`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_a: Option<ColorDesc>,
    /// Scattering per scene unit, with `sigma_a`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_s: Option<ColorDesc>,
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub scale: f32,
    #[serde(default, skip_serializing_if = "is_default")]
    pub phase: PhaseDesc,
}

/// Mitsuba's `heterogeneous`: extinction and albedo from volumes (`sigma_t`, default 1, and
/// `albedo`, default 0.75), or absorption and scattering from volumes (`sigma_a` and `sigma_s`,
/// pbrt-v4's `rgbgrid`); `scale` multiplies the coefficients. The medium is the box of its
/// extinction's volume (nothing scatters or absorbs outside it): `sigma_t`'s, or the box that
/// `sigma_a` and `sigma_s` share (a plain number takes the other's box; two volumes must have
/// the same transform, and two grids the same resolution and filter, so that their sum, the
/// extinction, is itself a grid interpolated as theirs are).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HeterogeneousDesc {
    // Boxed: four volumes, each with its transform, would make every `MediumDesc` large.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_t: Option<Box<VolumeDesc>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub albedo: Option<Box<VolumeDesc>>,
    /// Absorption per scene unit, with `sigma_s` instead of `sigma_t` and `albedo`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_a: Option<Box<VolumeDesc>>,
    /// Scattering per scene unit, with `sigma_a`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_s: Option<Box<VolumeDesc>>,
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub scale: f32,
    #[serde(default, skip_serializing_if = "is_default")]
    pub phase: PhaseDesc,
}

impl Default for HeterogeneousDesc {
    fn default() -> Self {
        HeterogeneousDesc {
            sigma_t: None,
            albedo: None,
            sigma_a: None,
            sigma_s: None,
            scale: 1.0,
            phase: PhaseDesc::default(),
        }
    }
}

/// A heterogeneous medium's coefficients, in the form they were given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HeterogeneousCoefficients<'a> {
    /// Extinction and single-scattering albedo.
    ExtinctionAlbedo {
        sigma_t: &'a VolumeDesc,
        albedo: &'a VolumeDesc,
    },
    /// Absorption and scattering.
    AbsorptionScattering {
        sigma_a: &'a VolumeDesc,
        sigma_s: &'a VolumeDesc,
    },
}

impl HeterogeneousDesc {
    /// The coefficients with their defaults (`sigma_t` 1, `albedo` 0.75).
    pub fn coefficients(&self) -> HeterogeneousCoefficients<'_> {
        const SIGMA_T: VolumeDesc = VolumeDesc::Value(1.0);
        const ALBEDO: VolumeDesc = VolumeDesc::Value(0.75);
        match (self.sigma_a.as_deref(), self.sigma_s.as_deref()) {
            (Some(sigma_a), Some(sigma_s)) => {
                HeterogeneousCoefficients::AbsorptionScattering { sigma_a, sigma_s }
            }
            _ => HeterogeneousCoefficients::ExtinctionAlbedo {
                sigma_t: self.sigma_t.as_deref().unwrap_or(&SIGMA_T),
                albedo: self.albedo.as_deref().unwrap_or(&ALBEDO),
            },
        }
    }

    /// The volumes given, with their keys.
    pub fn volumes(&self) -> impl Iterator<Item = (&'static str, &VolumeDesc)> {
        [
            ("sigma_t", &self.sigma_t),
            ("albedo", &self.albedo),
            ("sigma_a", &self.sigma_a),
            ("sigma_s", &self.sigma_s),
        ]
        .into_iter()
        .filter_map(|(k, v)| v.as_deref().map(|v| (k, v)))
    }
}

/// The extinction and the albedo of a homogeneous medium's two forms, as `sigma_t` and `albedo`
/// (the albedo where `sigma_t` is 0 is 0).
impl HomogeneousDesc {
    pub fn sigma_t_albedo(&self) -> (Vec3f, VolumeDesc) {
        match (self.sigma_a, self.sigma_s) {
            (Some(a), Some(s)) => {
                let (a, s) = (a.rgb(), s.rgb());
                let t = [a[0] + s[0], a[1] + s[1], a[2] + s[2]];
                let albedo = [0, 1, 2].map(|k| if t[k] > 0.0 { s[k] / t[k] } else { 0.0 });
                (t, VolumeDesc::Rgb(albedo))
            }
            _ => (
                self.sigma_t.map_or([1.0; 3], ColorDesc::rgb),
                self.albedo.clone().unwrap_or_else(default_albedo),
            ),
        }
    }
}

impl MediumParams for HomogeneousDesc {
    const NAME: &'static str = "homogeneous";

    fn check(&self) -> Result<(), ParamError> {
        let pair = (self.sigma_a.is_some(), self.sigma_s.is_some());
        pair_check(pair, (self.sigma_t.is_some(), self.albedo.is_some()))?;
        if pair.0 {
            super::param_error::non_negative("sigma_a", &self.sigma_a.expect("given").rgb())?;
            super::param_error::non_negative("sigma_s", &self.sigma_s.expect("given").rgb())?;
        }
        if let Some(t) = self.sigma_t {
            super::param_error::non_negative("sigma_t", &t.rgb())?;
        }
        if let Some(a) = &self.albedo {
            a.check("albedo", Some(1.0))?;
        }
        scale_check(self.scale)
    }

    fn phase(&self) -> &PhaseDesc {
        &self.phase
    }
}

impl MediumParams for HeterogeneousDesc {
    const NAME: &'static str = "heterogeneous";

    fn check(&self) -> Result<(), ParamError> {
        pair_check(
            (self.sigma_a.is_some(), self.sigma_s.is_some()),
            (self.sigma_t.is_some(), self.albedo.is_some()),
        )?;
        for (key, v) in self.volumes() {
            v.check(key, (key == "albedo").then_some(1.0))?;
        }
        if let (Some(a), Some(s)) = (&self.sigma_a, &self.sigma_s) {
            if let (Some(ta), Some(ts)) = (a.transform(), s.transform()) {
                if ta != ts {
                    return Err(ParamError::new(
                        "sigma_s",
                        "`sigma_a` and `sigma_s` must share one transform (the medium's box)",
                    ));
                }
            }
        }
        scale_check(self.scale)
    }

    fn phase(&self) -> &PhaseDesc {
        &self.phase
    }
}

/// The two forms of a medium's coefficients: `sigma_a` and `sigma_s` together, and then
/// neither `sigma_t` nor `albedo`.
fn pair_check(
    (sigma_a, sigma_s): (bool, bool),
    (sigma_t, albedo): (bool, bool),
) -> Result<(), ParamError> {
    if sigma_a != sigma_s {
        let key = if sigma_a { "sigma_s" } else { "sigma_a" };
        return Err(ParamError::new(
            key,
            "give `sigma_a` and `sigma_s` together",
        ));
    }
    if sigma_a {
        for (key, given) in [("sigma_t", sigma_t), ("albedo", albedo)] {
            if given {
                return Err(ParamError::new(
                    key,
                    format!(
                        "give `sigma_t` and `albedo`, or `sigma_a` and `sigma_s`, not `{key}` \
                         with `sigma_a`"
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn scale_check(scale: f32) -> Result<(), ParamError> {
    super::param_error::non_negative("scale", &[scale])
}

/// The uniform phase function, `1 / 4 pi`.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct IsotropicDesc {}

/// Henyey and Greenstein's phase function (1941): `g` is the mean cosine of the scattering angle,
/// positive forward, negative backward.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HgDesc {
    /// In (-1, 1); Mitsuba's default 0.8.
    #[serde(default = "default_g")]
    pub g: f32,
}

/// Rayleigh scattering by particles much smaller than the wavelength: `3 (1 + cos^2) / 16 pi`.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RayleighDesc {}

/// Mitsuba's `blendphase`: `(1 - weight) phases[0] + weight phases[1]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BlendPhaseDesc {
    /// In [0, 1]; Mitsuba's default 0.5.
    #[serde(default = "half")]
    pub weight: f32,
    pub phases: Box<[PhaseDesc; 2]>,
}

impl PhaseParams for IsotropicDesc {
    const NAME: &'static str = "isotropic";
}

impl PhaseParams for HgDesc {
    const NAME: &'static str = "hg";

    fn check(&self) -> Result<(), ParamError> {
        if !(self.g > -1.0 && self.g < 1.0) {
            return Err(ParamError::new(
                "g",
                format!("`g` must lie strictly between -1 and 1, got {}", self.g),
            ));
        }
        Ok(())
    }
}

impl PhaseParams for RayleighDesc {
    const NAME: &'static str = "rayleigh";
}

impl PhaseParams for BlendPhaseDesc {
    const NAME: &'static str = "blendphase";

    fn check(&self) -> Result<(), ParamError> {
        if !(0.0..=1.0).contains(&self.weight) {
            return Err(ParamError::new(
                "weight",
                format!("`weight` must lie in [0, 1], got {}", self.weight),
            ));
        }
        for p in self.phases.iter() {
            p.check()
                .map_err(|e| ParamError::new("phases", e.message))?;
        }
        Ok(())
    }
}

macro_rules! define_medium_desc {
    ($($Variant:ident { name: $name:ident, desc: $Desc:ident, runtime: $module:ident::$Type:ident }),* $(,)?) => {
        /// `[media.NAME]`: one variant per medium of the registry.
        #[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
        #[serde(tag = "type", rename_all = "lowercase")]
        pub enum MediumDesc {
            $($Variant($Desc),)*
        }

        $(const _: () = assert!(
            super::bsdf_registry::same_name_ignoring_case(<$Desc as MediumParams>::NAME, stringify!($name)),
            concat!("`", stringify!($Desc), "::NAME` must be the medium's name")
        );)*

        /// Every medium's name, in the registry's order.
        pub const MEDIUM_NAMES: &[&str] = &[$(stringify!($name),)*];

        impl MediumDesc {
            /// See [`MediumParams::check`]; the phase function's problems too.
            pub fn check(&self) -> Result<(), ParamError> {
                match self {
                    $(MediumDesc::$Variant(d) => {
                        <$Desc as MediumParams>::check(d)?;
                        d.phase().check().map_err(|e| ParamError::new("phase", e.message))
                    })*
                }
            }
        }
    };
}
for_each_medium!(define_medium_desc);

macro_rules! define_phase_desc {
    ($($Variant:ident { name: $name:ident, desc: $Desc:ident, runtime: $module:ident::$Type:ident }),* $(,)?) => {
        /// A medium's `phase`: one variant per phase function of the registry.
        #[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
        #[serde(tag = "type", rename_all = "lowercase")]
        pub enum PhaseDesc {
            $($Variant($Desc),)*
        }

        $(const _: () = assert!(
            super::bsdf_registry::same_name_ignoring_case(<$Desc as PhaseParams>::NAME, stringify!($name)),
            concat!("`", stringify!($Desc), "::NAME` must be the phase function's name")
        );)*

        /// Every phase function's name, in the registry's order.
        pub const PHASE_NAMES: &[&str] = &[$(stringify!($name),)*];

        impl PhaseDesc {
            /// See [`PhaseParams::check`].
            pub fn check(&self) -> Result<(), ParamError> {
                match self {
                    $(PhaseDesc::$Variant(d) => <$Desc as PhaseParams>::check(d),)*
                }
            }
        }
    };
}
for_each_phase!(define_phase_desc);

impl Default for PhaseDesc {
    fn default() -> Self {
        PhaseDesc::Isotropic(IsotropicDesc {})
    }
}

fn default_albedo() -> VolumeDesc {
    VolumeDesc::Value(0.75)
}
fn default_g() -> f32 {
    0.8
}
fn one() -> f32 {
    1.0
}
fn half() -> f32 {
    0.5
}
fn is_one(v: &f32) -> bool {
    *v == 1.0
}
fn is_default<T: Default + PartialEq>(v: &T) -> bool {
    *v == T::default()
}

impl super::Description {
    /// Whether a medium is in use: the camera's, or one inside or outside a shape.
    pub fn uses_media(&self) -> bool {
        self.camera.medium.is_some()
            || self.shapes.iter().any(|s| {
                let (interior, exterior) = s.media();
                interior.is_some() || exterior.is_some()
            })
    }

    /// A warning when the scene's media will not show: its integrator traces none (it passes
    /// through `null` surfaces as if the media were vacuum, as Mitsuba 3's `path` does). The
    /// integrator is the one whose image the film holds (`aov`'s nested one).
    pub fn media_ignored_warning(&self) -> Option<String> {
        let integrator = self.render.image_integrator();
        (self.uses_media() && !integrator.traces_media()).then(|| {
            let tracers: Vec<&str> = super::IntegratorName::ALL
                .iter()
                .filter(|i| i.traces_media())
                .map(|i| i.name())
                .collect();
            format!(
                "the scene has participating media, which `{}` does not trace (it renders them \
                 as vacuum); render with {} to see them",
                integrator.name(),
                tracers
                    .iter()
                    .map(|t| format!("`{t}`"))
                    .collect::<Vec<_>>()
                    .join(" or ")
            )
        })
    }
}
