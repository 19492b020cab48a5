//! Rendering a loaded scene, with the integrator, samples and camera of the call.

use super::load::{apply_overrides, Override, CAMERA_KEYS};
use super::SceneHandle;
use crate::error::{Error, Result};
use crate::render::{render, Film, RenderOptions, RenderStats, Window};
use crate::scene::{Camera, IntegratorKind};
use std::sync::atomic::AtomicBool;

/// What one render asks beyond the scene.
#[derive(Default)]
pub struct RenderRequest<'a> {
    /// Samples per pixel (the scene's when `None`).
    pub spp: Option<u32>,
    /// An integrator name (the scene's when `None`).
    pub integrator: Option<&'a str>,
    /// Camera keys to change for this render.
    pub camera: &'a [Override],
    /// Only these pixels of the image.
    pub window: Option<Window>,
    /// Called with the number of pixels done.
    pub progress: Option<&'a (dyn Fn(u64) + Sync)>,
    pub cancel: Option<&'a AtomicBool>,
}

impl SceneHandle {
    /// Renders on the current thread pool. A render that changes nothing of the scene shares it
    /// with queries; one that changes the integrator, samples or camera holds it alone while it
    /// runs and restores it after.
    pub fn render(&self, r: &RenderRequest) -> Result<(Film, RenderStats)> {
        let integrator = match r.integrator {
            Some(name) => Some(IntegratorKind::from_name(name).ok_or_else(|| {
                Error::Invalid(format!(
                    "integrator: unknown integrator `{name}`, expected one of: {}",
                    IntegratorKind::NAMES.join(", ")
                ))
            })?),
            None => None,
        };
        if r.spp == Some(0) {
            return Err(Error::Invalid("spp: expected at least 1 sample".into()));
        }
        let camera = if r.camera.is_empty() {
            None
        } else {
            for (key, _) in r.camera {
                if key != "size" && !CAMERA_KEYS.contains(&key.as_str()) {
                    return Err(Error::Invalid(format!(
                        "camera: unknown key `{key}`, expected size or one of: {}",
                        CAMERA_KEYS.join(", ")
                    )));
                }
            }
            let mut d = crate::scene::model_description("mesh.ply");
            d.camera = self.camera.clone();
            apply_overrides(&mut d, r.camera)?;
            Some(Camera::new(&d.camera))
        };
        let options = RenderOptions {
            progress: r.progress,
            cancel: r.cancel,
            window: r.window,
            ..Default::default()
        };
        let unchanged = {
            let s = self.read();
            integrator.is_none_or(|i| i == s.settings.integrator)
                && r.spp.is_none_or(|n| n == s.settings.spp)
                && camera.is_none_or(|c| c == s.camera)
        };
        if unchanged {
            return render(&self.read(), &options);
        }
        let mut scene = self.scene.write().unwrap_or_else(|e| e.into_inner());
        let (settings, view) = (scene.settings.clone(), scene.camera);
        if let Some(i) = integrator {
            scene.settings.integrator = i;
        }
        if let Some(n) = r.spp {
            scene.settings.spp = n;
        }
        if let Some(c) = camera {
            scene.camera = c;
        }
        let result = render(&scene, &options);
        scene.settings = settings;
        scene.camera = view;
        result
    }
}
