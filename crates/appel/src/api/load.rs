//! Scenes from files, built-in names and JSON text, with camera and render keys overridden.

use super::SceneHandle;
use crate::description::parse::Syntax;
use crate::description::{description_from_str, validate, Description};
use crate::error::{Error, Location, Result};
use crate::format::FormatOptions;
use crate::io::is_mesh_file;
use crate::scene::builtin::{builtin_scene, BUILTIN_SCENES};
use crate::scene::{frame_model, model_description, Scene};
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
    "width",
    "height",
];

/// The `[render]` keys an override may set.
pub const RENDER_KEYS: &[&str] = &[
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
    "bvh",
    "grid",
    "kdtree",
];

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
    for (key, value) in overrides {
        if key == "size" {
            let size: [u32; 2] = serde_json::from_value(value.clone()).map_err(|_| {
                Error::Invalid(format!(
                    "override `size`: expected [width, height], got {value}"
                ))
            })?;
            (d.camera.width, d.camera.height) = (size[0], size[1]);
        } else if CAMERA_KEYS.contains(&key.as_str()) {
            set_key(&mut d.camera, key, value)?;
        } else if RENDER_KEYS.contains(&key.as_str()) {
            set_key(&mut d.render, key, value)?;
        } else {
            return Err(Error::Invalid(format!(
                "unknown override `{key}`: expected size, a camera key ({}) or a render key ({})",
                CAMERA_KEYS.join(", "),
                RENDER_KEYS.join(", ")
            )));
        }
    }
    validate::validate(d).map_err(|e| Error::Invalid(format!("after the overrides: {}", e.message)))
}

impl SceneHandle {
    /// Any scene Appel reads: a scene file (TOML, JSON, Mitsuba 3 XML) or a mesh file, which is
    /// framed by a camera looking at its bounds, as `appel render` does.
    pub fn load(path: &Path, overrides: &[Override]) -> Result<SceneHandle> {
        if is_mesh_file(path) {
            if !path.is_file() {
                return Err(Error::io(
                    path,
                    std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
                ));
            }
            let file = path.file_name().and_then(|f| f.to_str()).ok_or_else(|| {
                Error::Invalid(format!("{}: the file name is not UTF-8", path.display()))
            })?;
            let base_dir = match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => PathBuf::from("."),
            };
            let mut d = model_description(file);
            apply_overrides(&mut d, overrides)?;
            let mut scene = Scene::new(&d, &base_dir)?;
            let mut framed = frame_model(&d, scene.geometry.bounds());
            apply_overrides(&mut framed, overrides)?;
            scene.set_view(&framed)?;
            return Ok(SceneHandle::new(scene, framed.camera));
        }
        if !path.exists() {
            return Err(Error::io(
                path,
                std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
            ));
        }
        let loaded = crate::format::load(path, &FormatOptions::default())?;
        Self::build(loaded.description, &loaded.base_dir, overrides)
    }

    /// A built-in scene by name.
    pub fn builtin(name: &str, overrides: &[Override]) -> Result<SceneHandle> {
        let text = builtin_scene(name).ok_or_else(|| {
            Error::Invalid(format!(
                "`{name}` is not a built-in scene (built-in: {})",
                BUILTIN_SCENES
                    .iter()
                    .map(|s| s.0)
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
        let origin = PathBuf::from(format!("<built-in scene {name}>"));
        let d = description_from_str(text, Syntax::Toml, &origin)?;
        Self::build(d, Path::new("."), overrides)
    }

    /// A scene from JSON text with the scene schema; relative file names are relative to
    /// `base_dir`. Errors name `origin`.
    pub fn from_json(text: &str, base_dir: &Path, origin: &str) -> Result<SceneHandle> {
        let origin = PathBuf::from(origin);
        let d = description_from_str(text, Syntax::Json, &origin)?;
        validate::files(&d, base_dir).map_err(|invalid| {
            Error::input(Location::file(&origin), invalid.message.to_string())
        })?;
        Self::build(d, base_dir, &[])
    }

    fn build(mut d: Description, base_dir: &Path, overrides: &[Override]) -> Result<SceneHandle> {
        apply_overrides(&mut d, overrides)?;
        let scene = Scene::new(&d, base_dir)?;
        Ok(SceneHandle::new(scene, d.camera))
    }
}
