//! A built scene with what its queries build lazily.

use super::multi_hit::MultiHit;
use super::surface::Surface;
use crate::description::CameraDesc;
use crate::scene::Scene;
use std::sync::{OnceLock, RwLock};

/// A scene ready for rendering and queries. Queries share it; a render that changes the settings
/// or the camera for its duration holds it alone.
pub struct SceneHandle {
    pub(super) scene: RwLock<Scene>,
    /// The camera as described (after framing and overrides), to which camera overrides apply.
    pub(super) camera: CameraDesc,
    /// Structures for queries that must see every hit along a ray, built on first use.
    pub(super) multi: OnceLock<MultiHit>,
    /// The scene's triangles in world space with a closest-point hierarchy and an inside test,
    /// built on first use.
    pub(super) surface: OnceLock<Surface>,
}

impl SceneHandle {
    pub(super) fn new(scene: Scene, camera: CameraDesc) -> Self {
        Self {
            scene: RwLock::new(scene),
            camera,
            multi: OnceLock::new(),
            surface: OnceLock::new(),
        }
    }

    pub(super) fn read(&self) -> std::sync::RwLockReadGuard<'_, Scene> {
        self.scene.read().unwrap_or_else(|e| e.into_inner())
    }

    /// The image size, `(width, height)`.
    pub fn size(&self) -> (u32, u32) {
        let s = self.read();
        (s.camera.width, s.camera.height)
    }

    /// The camera as a JSON object with the scene schema's keys.
    pub fn camera_json(&self) -> String {
        serde_json::to_string(&self.camera).unwrap_or_default()
    }

    /// Bounds of everything bounded, `(min, max)`.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let b = self.read().geometry.bounds();
        (b.min.into(), b.max.into())
    }

    /// Triangles of the scene as stored (instanced ones once).
    pub fn triangle_count(&self) -> usize {
        self.read().geometry.triangle_count()
    }
}
