//! The scene description: the scene file's schema, plain serde data, exactly what the user wrote
//! (with defaults filled in; `docs/scene-format.md` documents every key, unknown keys are
//! rejected), its parsing with spans, its validation, where converted entries came from, and the
//! values that mesh readers and shading share (loaded meshes, file materials, texture lookup).
//! This layer names nothing above it: the formats, `io`'s readers, shading and the scene build on
//! it.

pub mod animation;
pub mod archive_path;
pub mod bsdf;
pub(crate) mod bsdf_registry;
pub mod emitter;
mod emitter_registry;
pub mod framing;
mod from_text;
pub mod integrator;
mod integrator_registry;
pub mod loaded_mesh;
mod material;
pub mod medium;
mod medium_registry;
pub mod origins;
mod param_error;
pub mod parse;
mod render;
mod shape;
pub mod spectra;
pub mod texture_lookup;
pub mod validate;

pub(crate) use bsdf_registry::for_each_bsdf;
pub use emitter::{
    AreaEmitterDesc, ConstantDesc, DirectionalDesc, EmitterParams, EnvMapDesc, EqualAreaEnvMapDesc,
    LightDesc, PointDesc, ProjectorDesc, SpotDesc, SunPlaceDesc, SunSkyDesc, SunTime,
};
pub(crate) use emitter_registry::for_each_emitter;
pub use emitter_registry::{is_light, light_names, EMITTER_NAMES};
pub use from_text::{description_from_str, located, path_string};
pub use integrator::{
    AovChannel, AovParams, AovType, BdptParams, PtracerParams, SppmParams, StrategyImages,
};
pub(crate) use integrator_registry::for_each_integrator;
pub use integrator_registry::{IntegratorName, IntegratorParams, IntegratorTable, NoParams};
pub use material::*;
pub use medium::{
    BlendPhaseDesc, ColorDesc, HeterogeneousCoefficients, HeterogeneousDesc, HgDesc,
    HomogeneousDesc, IsotropicDesc, MediumDesc, PhaseDesc, RayleighDesc, VolumeDesc, VolumeFilter,
    VolumeNode, MEDIUM_NAMES, PHASE_NAMES,
};
pub(crate) use medium_registry::{for_each_medium, for_each_phase};

macro_rules! export_bsdf_descs {
    ($($(#[$attr:meta])* $Variant:ident($module:ident: $Desc:ident => $Bsdf:ident, $Material:ident)),* $(,)?) => {
        pub use bsdf::{$($Desc,)*};
    };
}
bsdf_registry::for_each_bsdf!(export_bsdf_descs);
pub use bsdf::phong::CheckerDesc;
pub use bsdf::{BsdfParams, DistributionDesc, LayerDesc, ParamError, DEFAULT_ALPHA};
pub use render::*;
pub use shape::*;

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

pub type Vec3f = [f32; 3];

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Description {
    pub camera: CameraDesc,
    #[serde(default)]
    pub render: RenderDesc,
    #[serde(default)]
    pub environment: EnvironmentDesc,
    #[serde(default, deserialize_with = "material::deserialize_materials")]
    pub materials: BTreeMap<String, MaterialDesc>,
    #[serde(default, rename = "shape", skip_serializing_if = "Vec::is_empty")]
    pub shapes: Vec<ShapeDesc>,
    #[serde(default, rename = "light", skip_serializing_if = "Vec::is_empty")]
    pub lights: Vec<LightDesc>,
    /// `[media.NAME]`: participating media, named by shapes' `interior` and `exterior` and by
    /// the camera's `medium`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub media: BTreeMap<String, MediumDesc>,
    /// Meshes declared once and placed by `[[instance]]` entries; not rendered by themselves.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub meshes: BTreeMap<String, MeshDesc>,
    #[serde(default, rename = "instance", skip_serializing_if = "Vec::is_empty")]
    pub instances: Vec<InstanceDesc>,
    /// `[animation]`: the scene is a sequence of frames (see `animation`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animation: Option<AnimationDesc>,
}

/// `[animation]`: frame `k` shows the scene at time `k / fps` seconds.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AnimationDesc {
    /// Frames in the sequence, numbered from 0.
    pub frames: u32,
    /// Frames per second: the time keyframes are placed in.
    #[serde(default = "default_fps")]
    pub fps: f32,
}

fn default_fps() -> f32 {
    24.0
}

/// One key of a keyframed transform: where the object is at `time` seconds. Between two keys the
/// transforms are decomposed into translation, rotation and scale and interpolated (linearly,
/// and spherically for the rotation); before the first key and after the last the object rests.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct KeyframeDesc {
    pub time: f32,
    pub transform: TransformDesc,
}

/// `[meshes.NAME]`: a mesh file loaded once, with its own acceleration structure.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MeshDesc {
    /// A mesh file, relative to the scene file's folder (or empty, with `triangles`).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub file: String,
    /// Overrides the file's own materials.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// As for a mesh shape: the file's parts without vertex normals get smooth ones.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub smooth_normals: bool,
    /// Triangle meshes written out instead of a file (pbrt's object definitions), each with its
    /// own `material` (or the entry's); they cannot emit.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub triangles: Vec<TriangleMeshDesc>,
}

/// `[[instance]]`: placements of a declared mesh, by one `transform` or a file of `placements`
/// (neither: the mesh where it is).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InstanceDesc {
    /// The name of a `[meshes.NAME]` entry.
    pub mesh: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
    /// A placement list (see `io::placements`), relative to the scene file's folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub placements: Option<String>,
    /// A moving placement, instead of `transform`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub keyframes: Vec<KeyframeDesc>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// "perspective" (default) or "orthographic".
    #[serde(default, rename = "type", skip_serializing_if = "is_default")]
    pub kind: CameraKind,
    pub eye: Vec3f,
    pub look_at: Vec3f,
    #[serde(default = "default_up")]
    pub up: Vec3f,
    /// Field of view in degrees, along `fov_axis`.
    #[serde(default = "default_fov")]
    pub fov: f32,
    /// The image axis `fov` spans: "y" (vertical, the default), "x", "diagonal", "smaller" or
    /// "larger", as Mitsuba's `fov_axis`.
    #[serde(default, skip_serializing_if = "is_default")]
    pub fov_axis: FovAxis,
    /// Orthographic cameras: half the width of the view in scene units (the height follows the
    /// aspect ratio).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub half_width: Option<f32>,
    /// Nothing nearer than this distance along the view axis is seen.
    #[serde(default, skip_serializing_if = "is_default")]
    pub near_clip: f32,
    /// The radius of a thin lens's aperture in scene units (Mitsuba's `thinlens`
    /// `aperture_radius`, pbrt's `lensradius`); 0, the default, is a pinhole.
    #[serde(default, skip_serializing_if = "is_default")]
    pub aperture_radius: f32,
    /// The distance along the view axis from the lens to the plane in focus; by default the
    /// distance from `eye` to `look_at`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focus_distance: Option<f32>,
    /// The `[media.NAME]` the camera sits in; none is vacuum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub medium: Option<String>,
    #[serde(default = "default_width")]
    pub width: u32,
    #[serde(default = "default_height")]
    pub height: u32,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDesc {
    /// Radiance of rays that leave the scene.
    #[serde(default = "default_background")]
    pub background: Vec3f,
    /// Ambient light, scaled by each material's `ambient` coefficient.
    #[serde(default = "default_ambient_light")]
    pub ambient: Vec3f,
}

impl Default for EnvironmentDesc {
    fn default() -> Self {
        Self {
            background: default_background(),
            ambient: default_ambient_light(),
        }
    }
}

/// Places a shape: scale first, then rotate, then translate (`M = T * R * S`); or a whole
/// `matrix`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TransformDesc {
    /// A 4x4 matrix, row by row (the last row `[0, 0, 0, 1]`), instead of the other keys.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<[[f32; 4]; 4]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translate: Option<Vec3f>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotate: Option<RotateDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<ScaleDesc>,
}

/// A rotation by `degrees` about `axis` (right-handed: counter-clockwise looking down the axis).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RotateDesc {
    pub axis: Vec3f,
    pub degrees: f32,
}

/// `scale = 2.0` or `scale = [1.0, 2.0, 1.0]`.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum ScaleDesc {
    Uniform(f32),
    Axes(Vec3f),
}

impl ScaleDesc {
    pub fn axes(self) -> Vec3f {
        match self {
            ScaleDesc::Uniform(s) => [s; 3],
            ScaleDesc::Axes(a) => a,
        }
    }
}

impl Default for CameraDesc {
    fn default() -> Self {
        Self {
            kind: CameraKind::default(),
            eye: [0.0, 0.0, 5.0],
            look_at: [0.0; 3],
            up: default_up(),
            fov: default_fov(),
            fov_axis: FovAxis::default(),
            half_width: None,
            near_clip: 0.0,
            aperture_radius: 0.0,
            focus_distance: None,
            medium: None,
            width: default_width(),
            height: default_height(),
        }
    }
}

impl CameraDesc {
    /// The distance to the plane in focus: `focus_distance`, or the distance from `eye` to
    /// `look_at`.
    pub fn focus_distance(&self) -> f32 {
        self.focus_distance.unwrap_or_else(|| {
            (glam::Vec3::from(self.look_at) - glam::Vec3::from(self.eye)).length()
        })
    }
}

impl TransformDesc {
    /// Follows the transform with a uniform scale by `s` about the origin:
    /// `s * (T R S) = T(s t) R S(s S)`.
    pub fn scale_about_origin(&mut self, s: f32) {
        if let Some(m) = &mut self.matrix {
            for row in m.iter_mut().take(3) {
                for x in row.iter_mut() {
                    *x *= s;
                }
            }
            return;
        }
        self.translate = self.translate.map(|t| t.map(|x| x * s));
        let axes = self.scale.map_or([1.0; 3], ScaleDesc::axes);
        self.scale = Some(ScaleDesc::Axes(axes.map(|x| x * s)));
    }

    /// `T * R * S`: applied to a point, scale acts first, then rotation, then translation.
    pub fn matrix(&self) -> glam::Mat4 {
        use glam::{Mat4, Quat, Vec3};
        if let Some(m) = self.matrix {
            return Mat4::from_cols_array_2d(&m).transpose();
        }
        let s = Vec3::from(self.scale.map_or([1.0; 3], ScaleDesc::axes));
        let r = self.rotate.as_ref().map_or(Quat::IDENTITY, |r| {
            Quat::from_axis_angle(Vec3::from(r.axis).normalize(), r.degrees.to_radians())
        });
        let t = Vec3::from(self.translate.unwrap_or([0.0; 3]));
        Mat4::from_scale_rotation_translation(s, r, t)
    }
}

fn default_up() -> Vec3f {
    [0.0, 1.0, 0.0]
}
fn default_fov() -> f32 {
    45.0
}
fn default_width() -> u32 {
    640
}
fn default_height() -> u32 {
    480
}
fn is_default<T: Default + PartialEq>(v: &T) -> bool {
    *v == T::default()
}
fn default_background() -> Vec3f {
    [0.0, 0.0, 0.0]
}
fn default_ambient_light() -> Vec3f {
    [1.0, 1.0, 1.0]
}

impl Description {
    /// The same scene uniformly scaled by `s` about the origin, camera included. Point-light
    /// intensities scale by `s^2` so that inverse-square falloff leaves the image unchanged.
    pub fn scaled(&self, s: f32) -> Description {
        let sc = |v: Vec3f| v.map(|x| x * s);
        let mut d = self.clone();
        d.camera.eye = sc(d.camera.eye);
        d.camera.look_at = sc(d.camera.look_at);
        for m in d.materials.values_mut() {
            if let MaterialDesc::Phong(PhongDesc {
                checker: Some(c), ..
            }) = m
            {
                c.size *= s;
            }
        }
        for sh in &mut d.shapes {
            sh.scale(s);
        }
        // Placement files are not rewritten: only inline transforms scale.
        for t in d.instances.iter_mut().filter(|i| i.placements.is_none()) {
            t.transform
                .get_or_insert_with(Default::default)
                .scale_about_origin(s);
        }
        for l in &mut d.lights {
            l.scale(s);
        }
        d
    }
}
