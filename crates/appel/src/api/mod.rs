//! The library as other languages see it: a scene loaded or built from arrays, rendered whole or
//! by windows, and asked ray and point queries over flat arrays. Front ends (the Python package)
//! call only this module, never `Scene`'s fields, so the scene's insides can change freely.
//!
//! Every call runs on the current rayon pool: a front end picks the thread count with
//! `ThreadPool::install`.

mod handle;
mod image;
mod load;
mod meshes;
mod multi_hit;
mod rays;
mod render;
mod resolve;
mod surface;

pub use handle::SceneHandle;
pub use image::ImageArrays;
pub use load::{is_override_key, render_keys, Override, CAMERA_KEYS};
pub use meshes::{MeshArrays, Placement};
pub use multi_hit::HitList;
pub use rays::{Coords, GeometricHits, RayHits};
pub use render::RenderRequest;
pub use resolve::{
    build_resolved, builtin_names, is_model, resolve_description, resolve_scene, RequestNames,
    ResolvedScene, SceneRequest,
};
pub use surface::ClosestHits;

/// The id of a miss (and of the instance of a surface that is not instanced).
pub const MISS: u32 = u32::MAX;
