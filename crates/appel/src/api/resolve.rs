//! From a scene's name to a built scene, the one way every front end takes: the command line
//! (`appel render`, `bench`, `view`, animations), the Python package and the viewer.
//!
//! A name is a built-in scene (`appel scenes`), a file of any registered scene format
//! ([`crate::format::registry`]) read with its parameters (Mitsuba's `-D`), glTF files
//! (`scene.glb`, `x.zip:inner.gltf`) among them, or another mesh file (`bunny.ply`, `x.zip`,
//! `x.zip:inner.obj`) that is framed once its bounds are known. Overrides of the
//! camera and `[render]` keys apply after the file is read, and again after a mesh file's framing,
//! so that they win over both.

use crate::description::archive_path::archive_path;
use crate::description::framing::{pick_camera, view_through};
use crate::description::loaded_mesh::FileCamera;
use crate::description::parse::Syntax;
use crate::description::{description_from_str, validate, Description};
use crate::error::{Error, Result};
use crate::format::FormatOptions;
use crate::io::is_mesh_file;
use crate::scene::builtin::{builtin_scene, BUILTIN_SCENES};
use crate::scene::Scene;
use crate::scene_build::{model_description, view_model, SceneOptions};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The scene to resolve, and what the caller changes in it. `E` is the caller's error type, so
/// that its overrides can fail with its own messages.
pub struct SceneRequest<'a, E> {
    /// A built-in scene's name, a mesh file or a scene file.
    pub name: &'a str,
    /// Parameters of the scene file (Mitsuba's `-D`); an error for names whose format takes none.
    pub params: FormatOptions,
    /// A glTF file's camera to view it through (0-based, in traversal order); by default its
    /// first, or automatic framing when it has none. An error for any other scene.
    pub camera: Option<usize>,
    /// Changes to the description (camera and `[render]` keys), applied after it is read and again
    /// after a mesh file's framing.
    pub overrides: &'a dyn Fn(&mut Description) -> std::result::Result<(), E>,
    /// How messages name the overrides and the camera choice (`command-line overrides`,
    /// `--camera`).
    pub names: RequestNames,
}

/// How messages call the parts of a [`SceneRequest`], in the caller's terms.
#[derive(Clone, Copy, Debug)]
pub struct RequestNames {
    pub overrides: &'static str,
    pub camera: &'static str,
    pub params: &'static str,
}

impl Default for RequestNames {
    fn default() -> Self {
        Self {
            overrides: "the overrides",
            camera: "camera",
            params: "parameters",
        }
    }
}

/// A scene's description as read and overridden, before it is built.
#[derive(Clone, Debug)]
pub struct ResolvedScene {
    pub description: Description,
    /// The folder its relative file names are relative to.
    pub base_dir: PathBuf,
    /// What the format's reader noticed but could render (pbrt's unused parameters).
    pub warnings: Vec<String>,
    /// The cameras the file defines, to choose from (glTF's camera nodes); empty for scenes
    /// with one camera.
    pub cameras: Vec<FileCamera>,
    /// A mesh file, framed by [`build_resolved`] once its bounds are known.
    pub framed_model: bool,
    /// The time spent reading and checking the file.
    pub parse_time: Duration,
}

/// Reads the scene `request` names and applies its overrides, then validates the result.
pub fn resolve_description<E: From<Error>>(
    request: &SceneRequest<'_, E>,
) -> std::result::Result<ResolvedScene, E> {
    let start = Instant::now();
    let mut resolved = read_scene_or_model(request.name, &request.params, request.names)?;
    if let (Some(n), false) = (request.camera, resolved.framed_model) {
        if resolved.cameras.is_empty() {
            return Err(Error::Invalid(format!(
                "{} picks a camera of a glTF file; `{}` defines none to choose from",
                request.names.camera, request.name
            ))
            .into());
        }
        let chosen = pick_camera(&resolved.cameras, Some(n))
            .map_err(|e| Error::Invalid(format!("{}: {e}", request.names.camera)))?;
        if let Some(c) = chosen {
            view_through(&mut resolved.description, c);
        }
    }
    (request.overrides)(&mut resolved.description)?;
    check(&resolved.description, request.names)?;
    resolved
        .warnings
        .extend(resolved.description.media_ignored_warning());
    resolved.parse_time = start.elapsed();
    Ok(resolved)
}

/// Builds a resolved scene on the current thread pool; a mesh file is then viewed as
/// [`view_model`] says (through its own camera, or framed), the overrides are applied again, and
/// `resolved.description` becomes that view.
pub fn build_resolved<E: From<Error>>(
    request: &SceneRequest<'_, E>,
    resolved: &mut ResolvedScene,
    options: SceneOptions,
) -> std::result::Result<Scene, E> {
    let description = &resolved.description;
    let mut scene = Scene::new_with(description, &resolved.base_dir, options)?;
    if resolved.framed_model {
        let mut framed = view_model(&scene, description, request.camera)
            .map_err(|e| Error::Invalid(format!("{}: {e}", request.names.camera)))?;
        (request.overrides)(&mut framed)?;
        check(&framed, request.names)?;
        scene.set_view(&framed)?;
        scene.settings.integrator = framed.render.integrator;
        scene.settings.spp = framed.render.spp;
        scene.settings.max_depth = framed.render.max_depth;
        resolved.description = framed;
    }
    Ok(scene)
}

/// [`resolve_description`] then [`build_resolved`]: the description returned is the one the
/// scene is viewed by (a mesh file's framing included).
pub fn resolve_scene<E: From<Error>>(
    request: &SceneRequest<'_, E>,
    options: SceneOptions,
) -> std::result::Result<(ResolvedScene, Scene), E> {
    let mut resolved = resolve_description(request)?;
    let scene = build_resolved(request, &mut resolved, options)?;
    Ok((resolved, scene))
}

fn check(d: &Description, names: RequestNames) -> Result<()> {
    validate::validate(d)
        .map_err(|e| Error::Invalid(format!("after {}: {}", names.overrides, e.message)))
}

/// Whether `name` is a mesh file Appel reads (or an archive holding one), to be framed: not one
/// a scene format reads (a glTF file is a scene).
pub fn is_model(name: &str) -> bool {
    let path = Path::new(name);
    is_mesh_file(path) && crate::format::find(path).is_none()
}

/// A scene file, a mesh file (framed later, once its bounds are known), or a built-in scene.
/// `params` go to a scene format that takes them, and only to one.
fn read_scene_or_model(
    name: &str,
    params: &FormatOptions,
    names: RequestNames,
) -> Result<ResolvedScene> {
    let path = Path::new(name);
    if !params.params.is_empty() && !crate::format::find(path).is_some_and(|f| f.takes_params()) {
        let takers: Vec<String> = crate::format::formats()
            .iter()
            .filter(|f| f.takes_params())
            .map(|f| format!("{} ({})", f.name(), f.extensions().join(", ")))
            .collect();
        return Err(Error::Invalid(format!(
            "{} ({}) are read by a scene file of {}; `{name}` is not one",
            names.params,
            params
                .params
                .iter()
                .map(|(n, _)| n.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            takers.join(" or ")
        )));
    }
    let resolved = |description, base_dir, warnings, framed_model| ResolvedScene {
        description,
        base_dir,
        warnings,
        cameras: Vec::new(),
        framed_model,
        parse_time: Duration::ZERO,
    };
    let format = crate::format::find(path);
    if is_model(name) {
        let (file, base_dir) = model_file(name)?;
        return Ok(resolved(
            model_description(&file),
            base_dir,
            Vec::new(),
            true,
        ));
    }
    // An entry of a zip archive exists if its archive does (the entry is looked up when read).
    let on_disk = archive_path(path).map_or_else(|| path.to_path_buf(), |a| a.archive);
    if Syntax::from_path(path).is_none() && format.is_none() && !on_disk.exists() {
        if let Some(text) = builtin_scene(name) {
            let origin = PathBuf::from(format!("<built-in scene {name}>"));
            let d = description_from_str(text, Syntax::Toml, &origin)?;
            return Ok(resolved(d, PathBuf::from("."), Vec::new(), false));
        }
        return Err(Error::Invalid(format!(
            "`{name}` is neither a scene file nor a built-in scene (built-in: {})",
            builtin_names().join(", ")
        )));
    }
    if !on_disk.exists() {
        return Err(Error::io(
            on_disk,
            std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
        ));
    }
    let loaded = crate::format::load(path, params)?;
    Ok(ResolvedScene {
        cameras: loaded.cameras,
        ..resolved(loaded.description, loaded.base_dir, loaded.warnings, false)
    })
}

/// A mesh file's name as the framing scene's shape names it (relative to its folder; an archive's
/// entry as `x.zip:dir/m.obj`), and that folder.
fn model_file(name: &str) -> Result<(String, PathBuf)> {
    let path = Path::new(name);
    let archive = archive_path(path);
    let file_path = archive.as_ref().map_or(path, |a| a.archive.as_path());
    let file = file_path
        .file_name()
        .and_then(|f| f.to_str())
        .ok_or_else(|| Error::Invalid(format!("`{name}`: the file name is not valid UTF-8")))?;
    let file = match archive.as_ref().and_then(|a| a.inner.as_deref()) {
        Some(inner) => format!("{file}:{inner}"),
        None => file.to_string(),
    };
    if !file_path.is_file() {
        return Err(Error::io(
            file_path,
            std::io::Error::new(std::io::ErrorKind::NotFound, "no such mesh file"),
        ));
    }
    let base_dir = match file_path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Ok((file, base_dir))
}

/// The built-in scenes' names.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN_SCENES.iter().map(|s| s.0).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request<'a>(
        name: &'a str,
        params: &[(&str, &str)],
        overrides: &'a dyn Fn(&mut Description) -> Result<()>,
    ) -> SceneRequest<'a, Error> {
        SceneRequest {
            name,
            params: FormatOptions {
                params: params
                    .iter()
                    .map(|(n, v)| (n.to_string(), v.to_string()))
                    .collect(),
            },
            camera: None,
            overrides,
            names: RequestNames::default(),
        }
    }

    #[test]
    fn a_builtin_name_is_a_builtin_scene() {
        let none = |_: &mut Description| Ok(());
        let r = resolve_description(&request("whitted", &[], &none)).unwrap();
        assert!(!r.framed_model);
        assert_eq!(r.base_dir, PathBuf::from("."));
    }

    #[test]
    fn an_unknown_name_lists_the_builtins() {
        let none = |_: &mut Description| Ok(());
        let e = resolve_description(&request("nosuchscene", &[], &none))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("neither a scene file nor a built-in scene"),
            "{e}"
        );
        assert!(e.contains("whitted"), "{e}");
    }

    #[test]
    fn parameters_need_a_format_that_takes_them() {
        let none = |_: &mut Description| Ok(());
        let e = resolve_description(&request("whitted", &[("spp", "4")], &none))
            .unwrap_err()
            .to_string();
        assert!(e.contains("parameters (spp)"), "{e}");
        assert!(e.contains("mitsuba (.xml)"), "{e}");
    }

    #[test]
    fn a_missing_mesh_file_is_named() {
        let none = |_: &mut Description| Ok(());
        let e = resolve_description(&request("/no/such/dir/m.ply", &[], &none))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/no/such/dir/m.ply: no such mesh file"), "{e}");
        let e = resolve_description(&request("/no/such/dir/a.zip:m.obj", &[], &none))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/no/such/dir/a.zip: no such mesh file"), "{e}");
    }

    #[test]
    fn overrides_are_validated_under_their_name() {
        let zero = |d: &mut Description| {
            d.camera.width = 0;
            Ok(())
        };
        let e = resolve_description(&request("whitted", &[], &zero))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("after the overrides: "), "{e}");
    }

    #[test]
    fn a_camera_choice_is_only_for_mesh_files() {
        let none = |_: &mut Description| Ok(());
        let mut r = request("whitted", &[], &none);
        r.camera = Some(0);
        let e = resolve_description(&r).unwrap_err().to_string();
        assert!(e.contains("picks a camera of a glTF file"), "{e}");
    }

    #[test]
    fn a_mesh_inside_an_archive_is_built_and_framed() {
        use std::io::Write;
        let dir = tempfile::tempdir().unwrap();
        let archive = dir.path().join("assets.zip");
        let mut zip = zip::ZipWriter::new(std::fs::File::create(&archive).unwrap());
        let options = zip::write::SimpleFileOptions::default();
        zip.start_file("other.obj", options).unwrap();
        zip.write_all(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
            .unwrap();
        zip.start_file("dir/inner.obj", options).unwrap();
        zip.write_all(b"v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
            .unwrap();
        zip.finish().unwrap();
        let name = format!("{}:dir/inner.obj", archive.display());
        let small = |d: &mut Description| {
            (d.camera.width, d.camera.height) = (20, 10);
            Ok(())
        };
        let (resolved, scene) =
            resolve_scene(&request(&name, &[], &small), SceneOptions::default()).unwrap();
        assert!(resolved.framed_model);
        assert_eq!(resolved.base_dir, dir.path());
        assert_eq!(scene.geometry.triangle_count(), 4);
        assert_eq!(scene.geometry.bounds().max, crate::math::Vec3::splat(2.0));
        // Framed at the box's centre, at the overridden size.
        assert_eq!(resolved.description.camera.look_at, [1.0; 3]);
        assert_eq!((scene.camera.width, scene.camera.height), (20, 10));
    }
}
