//! The scene ready to render: geometry, acceleration structure, materials, lights and camera, and
//! the queries rays make of them. Building one from a description is `crate::scene_build`'s work.

pub mod builtin;
mod camera;
mod file_extras;
mod geometry;
mod instance;
mod queries;
mod scene_emitters;
mod scene_media;

use crate::description;
pub use camera::{Camera, CameraConnection};
pub use file_extras::FileExtras;
pub use geometry::{
    Geometry, PrimRef, PrimRefs, SceneHit, Shape, ShapeKind, ShapeSource, NO_INSTANCE,
};
pub use instance::{Instance, Prototype};
pub use scene_emitters::{SceneEmitters, NO_EMITTER};
pub use scene_media::{MediumInterface, SceneMedia, NO_MEDIUM};

use crate::accel::{Accel, AccelKind, AccelOptions, AccelStats};
use crate::math::Vec3;
use std::time::Duration;

/// Which integrator renders the scene.
pub use crate::description::IntegratorName as IntegratorKind;

#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub integrator: IntegratorKind,
    pub max_depth: i32,
    pub rr_depth: u32,
    pub hide_emitters: bool,
    pub spp: u32,
    pub sampler: description::SamplerName,
    pub seed: u64,
    pub filter: description::FilterDesc,
    pub accel: AccelKind,
    /// `[render.NAME]` of each structure.
    pub accel_options: AccelOptions,
    /// `[render.NAME]` of each integrator.
    pub integrator_params: description::IntegratorParams,
}

/// How long building the scene took, phase by phase.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneTimings {
    /// Reading files and creating the geometry.
    pub load: Duration,
    /// Building the acceleration structure.
    pub build: Duration,
}

/// A scene ready to render.
#[derive(Clone, Debug)]
pub struct Scene {
    pub camera: Camera,
    pub settings: RenderSettings,
    pub geometry: Geometry,
    pub accel: Accel,
    /// The materials of every integrator, by the index each surface carries (see
    /// [`crate::shading::material::Material`]).
    pub shading_materials: Vec<crate::shading::material::Material>,
    /// Whether any material is a mask (cut-outs), which rays must then step through.
    pub has_masks: bool,
    /// The lights of every integrator: every `[[light]]` and emitting surface.
    pub emitters: SceneEmitters,
    /// The participating media, the media each surface separates and the camera's.
    pub media: SceneMedia,
    /// What `whitted` and `raycast` show where a ray leaves the scene.
    pub background: Vec3,
    /// The ambient light of `whitted` and `raycast`, weighted by each material's `ambient`.
    pub ambient: Vec3,
    pub timings: SceneTimings,
    /// What the scene's mesh files brought besides triangles (materials, emitting surfaces, lights,
    /// cameras, warnings).
    pub from_files: FileExtras,
}

impl Scene {
    pub fn accel_stats(&self) -> AccelStats {
        let mut s = self.accel.stats();
        s.build_time = self.timings.build;
        s
    }
}
