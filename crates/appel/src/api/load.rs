//! Scenes from files, built-in names and JSON text, with camera and render keys overridden.

use super::resolve::{builtin_names, resolve_scene, RequestNames, SceneRequest};
use super::SceneHandle;
use crate::accel::AccelKind;
use crate::description::parse::Syntax;
use crate::description::{description_from_str, validate, Description};
use crate::error::{Error, Location, Result};
use crate::format::FormatOptions;
use crate::scene::builtin::builtin_scene;
use crate::scene::Scene;
use crate::scene_build::SceneOptions;
use std::path::{Path, PathBuf};

/// One overridden key: a `[camera]` or `[render]` key of the scene schema (or `size`, `[width,
/// height]`), with its value as JSON.
pub type Override = (String, serde_json::Value);

/// The `[camera]` keys an override may set.
pub const CAMERA_KEYS: &[&str] = &[
    "type",
    "eye",
    "look_at",
    "up",
    "fov",
    "fov_axis",
    "half_width",
    "near_clip",
    "aperture_radius",
    "focus_distance",
    "width",
    "height",
];

/// The `[render]` keys an override may set other than the structures' tables.
const RENDER_SETTINGS: &[&str] = &[
    "integrator",
    "max_depth",
    "rr_depth",
    "hide_emitters",
    "accel",
    "spp",
    "sampler",
    "seed",
    "filter",
    "triangle",
];

/// The `[render]` keys an override may set: the settings, and the `[render.NAME]` table of every
/// registered acceleration structure ([`AccelKind::NAMES`]).
pub fn render_keys() -> Vec<&'static str> {
    RENDER_SETTINGS
        .iter()
        .chain(AccelKind::NAMES)
        .copied()
        .collect()
}

/// Whether `key` is one an override may set: `size`, a camera key or a render key.
pub fn is_override_key(key: &str) -> bool {
    key == "size" || CAMERA_KEYS.contains(&key) || render_keys().contains(&key)
}

/// Sets `value` at `key` of the serialized `table`, and reads the table back: serde then checks
/// the value as the file parser would.
fn set_key<T: serde::Serialize + serde::de::DeserializeOwned>(
    table: &mut T,
    key: &str,
    value: &serde_json::Value,
) -> Result<()> {
    let mut v = serde_json::to_value(&*table).map_err(|e| Error::Invalid(e.to_string()))?;
    v[key] = value.clone();
    *table = serde_json::from_value(v)
        .map_err(|e| Error::Invalid(format!("override `{key}` = {value}: {e}")))?;
    Ok(())
}

/// Applies overrides to the camera and render tables, then validates the whole description.
pub fn apply_overrides(d: &mut Description, overrides: &[Override]) -> Result<()> {
    apply_keys(d, overrides)?;
    validate::validate(d).map_err(|e| Error::Invalid(format!("after the overrides: {}", e.message)))
}

/// Sets one overridden key.
fn set_override(d: &mut Description, key: &str, value: &serde_json::Value) -> Result<()> {
    if key == "size" {
        let size: [u32; 2] = serde_json::from_value(value.clone()).map_err(|_| {
            Error::Invalid(format!(
                "override `size`: expected [width, height], got {value}"
            ))
        })?;
        (d.camera.width, d.camera.height) = (size[0], size[1]);
        Ok(())
    } else if CAMERA_KEYS.contains(&key) {
        set_key(&mut d.camera, key, value)
    } else if render_keys().contains(&key) {
        set_key(&mut d.render, key, value)
    } else {
        Err(Error::Invalid(format!(
            "unknown override `{key}`: expected size, a camera key ({}) or a render key ({})",
            CAMERA_KEYS.join(", "),
            render_keys().join(", ")
        )))
    }
}

impl SceneHandle {
    /// Any scene Appel reads ([`super::resolve_scene`]): a scene file of any registered format
    /// with its `params` (Mitsuba's `-D`), a mesh file (`x.zip:inner.obj` too), which is framed by
    /// a camera looking at its bounds or viewed through its own camera, as `appel render` does, or
    /// a built-in scene's name.
    pub fn load(
        path: &Path,
        params: &FormatOptions,
        overrides: &[Override],
    ) -> Result<SceneHandle> {
        let name = path.to_str().ok_or_else(|| {
            Error::Invalid(format!("{}: the file name is not UTF-8", path.display()))
        })?;
        let apply = |d: &mut Description| apply_keys(d, overrides);
        let request = SceneRequest {
            name,
            params: params.clone(),
            camera: None,
            overrides: &apply,
            names: RequestNames::default(),
        };
        let (resolved, scene) = resolve_scene(&request, SceneOptions::default())?;
        Ok(SceneHandle::new(scene, resolved.description.camera))
    }

    /// A built-in scene by name.
    pub fn builtin(name: &str, overrides: &[Override]) -> Result<SceneHandle> {
        if builtin_scene(name).is_none() {
            return Err(Error::Invalid(format!(
                "`{name}` is not a built-in scene (built-in: {})",
                builtin_names().join(", ")
            )));
        }
        Self::load(Path::new(name), &FormatOptions::default(), overrides)
    }

    /// A scene from JSON text with the scene schema; relative file names are relative to
    /// `base_dir`. Errors name `origin`.
    pub fn from_json(text: &str, base_dir: &Path, origin: &str) -> Result<SceneHandle> {
        let origin = PathBuf::from(origin);
        let d = description_from_str(text, Syntax::Json, &origin)?;
        validate::files(&d, base_dir).map_err(|invalid| {
            Error::input(Location::file(&origin), invalid.message.to_string())
        })?;
        let scene = Scene::new(&d, base_dir)?;
        Ok(SceneHandle::new(scene, d.camera))
    }
}

/// The overrides set on the description, without validating it (the resolution does).
fn apply_keys(d: &mut Description, overrides: &[Override]) -> Result<()> {
    for (key, value) in overrides {
        set_override(d, key, value)?;
    }
    Ok(())
}
