//! glTF 2.0 files (`.gltf`, `.glb`, and `x.zip:inner.gltf`) as scenes: the default scene's node
//! hierarchy with its meshes, cameras and `KHR_lights_punctual` lights.
//!
//! The geometry and materials are the mesh reader's ([`crate::io::gltf`]): the description holds
//! the file as one mesh shape, which the scene builder reads with every node's transform composed
//! down the tree, a mesh placed by several nodes as instances of one copy, and the
//! metallic-roughness materials mapped onto Appel's (`scene_build::file_materials`). This format
//! reads what makes the file a scene: its first camera in traversal order as the view (the
//! others listed for a choice of camera), its lights, and, for a file without a camera or without
//! lights, the framing and lighting a bare mesh file gets ([`crate::description::framing`]).

mod bounds;
mod cameras;
mod lights;
mod nodes;
#[cfg(test)]
mod tests;

use super::{FormatOptions, LoadedDescription, SceneFormat};
use crate::description::archive_path::archive_path;
use crate::description::framing::{view_file, FileView};
use crate::description::origins::{key_path, Origin, Origins};
use crate::description::{CameraDesc, Description, MeshShapeDesc, ShapeDesc};
use crate::error::{Error, Location, Result};
use std::path::Path;

/// glTF 2.0 scene files.
pub struct GltfFormat;

impl SceneFormat for GltfFormat {
    fn name(&self) -> &'static str {
        "gltf"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".gltf", ".glb"]
    }

    fn load(&self, path: &Path, _options: &FormatOptions) -> Result<LoadedDescription> {
        let bytes = read_bytes(path)?;
        let gltf = crate::io::gltf::read_document(&bytes, path)?;
        let text = (!bytes.starts_with(b"glTF"))
            .then(|| std::str::from_utf8(&bytes).ok())
            .flatten();
        let placed = nodes::placed_nodes(&gltf.document, path, text)?;
        let mut warnings = vec![];
        let file_cameras = cameras::cameras(&placed, path, &mut warnings);
        let file_lights = lights::lights(&placed, path, &mut warnings);
        let extent = bounds::mesh_extent(&placed);
        let bounds = match extent.bounds {
            Some(b) => b,
            None => crate::io::mesh_file::load_mesh(path)?.bounds(),
        };
        if file_lights.is_empty() {
            warnings.push(format!(
                "{}: the file has no lights (KHR_lights_punctual); it is lit as a bare model is{}",
                path.display(),
                if extent.physically_based {
                    ", by a light beside the camera, one from above and a grey sky"
                } else {
                    ", by a light beside the camera and one from above"
                }
            ));
        }
        let file = FileView {
            lights: &file_lights,
            cameras: &file_cameras,
            physically_based: extent.physically_based,
        };
        let description = view_file(&scene_of(shape_file(path)?), bounds, &file, None)
            .map_err(|m| Error::input(Location::file(path), m))?;
        let mut origins = Origins::default();
        let at = || Origin::at(Location::file(path));
        origins.record(key_path(&[&"camera"]), at());
        origins.record(key_path(&[&"shape"]), at());
        origins.record(key_path(&[&"light"]), at());
        let mut loaded = super::validate_converted(description, origins, warnings, path)?;
        loaded.cameras = file_cameras;
        Ok(loaded)
    }
}

/// The file's bytes: on disk, or an entry of a zip archive (`x.zip:inner/scene.gltf`).
fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    match archive_path(path) {
        Some(archive) => {
            let is_gltf = |n: &str| GltfFormat.recognises(Path::new(n));
            let (_, bytes, _) = crate::io::assets::open_archive(&archive, is_gltf)?;
            Ok(bytes)
        }
        None => std::fs::read(path).map_err(|e| Error::io(path, e)),
    }
}

/// How the description's mesh shape names the file: relative to the folder of the file (or of
/// its archive), where the description's base folder is.
fn shape_file(path: &Path) -> Result<String> {
    let archive = archive_path(path);
    let on_disk = archive.as_ref().map_or(path, |a| a.archive.as_path());
    let name = on_disk
        .file_name()
        .and_then(|f| f.to_str())
        .ok_or_else(|| Error::input(Location::file(path), "the file name is not valid UTF-8"))?;
    Ok(match archive.as_ref().and_then(|a| a.inner.as_deref()) {
        Some(inner) => format!("{name}:{inner}"),
        None => name.to_string(),
    })
}

/// The scene before it is viewed: the file as one mesh shape, and the image size and field of
/// view a bare model's framing starts from.
fn scene_of(file: String) -> Description {
    Description {
        camera: CameraDesc {
            fov: 45.0,
            width: 640,
            height: 480,
            ..CameraDesc::default()
        },
        render: Default::default(),
        environment: Default::default(),
        materials: Default::default(),
        meshes: Default::default(),
        instances: vec![],
        shapes: vec![ShapeDesc::Mesh(MeshShapeDesc {
            file,
            ..Default::default()
        })],
        lights: vec![],
        media: Default::default(),
        animation: None,
    }
}
