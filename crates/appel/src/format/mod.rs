//! Scene formats: each reads one kind of scene file into a [`Description`], implementing
//! [`SceneFormat`]; [`registry`] lists them once, and [`load`] picks the one that recognises a
//! path. TOML and JSON ([`toml`]), Mitsuba 3 XML ([`mitsuba`]), pbrt-v4 ([`pbrt`]) and glTF 2.0
//! ([`gltf`]). A format
//! builds on the description and on `io`'s leaf readers only, and nothing beneath it names it.

pub mod gltf;
pub mod mitsuba;
pub mod pbrt;
pub mod registry;
pub mod toml;

use crate::description::loaded_mesh::FileCamera;
use crate::description::origins::Origins;
use crate::description::validate::Invalid;
use crate::description::{path_string, Description};
use crate::error::{Error, Location, Result};
use std::path::{Path, PathBuf};

pub use crate::description::description_from_str;
pub use registry::{find, formats};

/// What a scene file is read with besides its path.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FormatOptions {
    /// `name=value` parameters (Mitsuba's `-D`): they replace `$name` in the scene and override its
    /// defaults. Only formats whose [`SceneFormat::takes_params`] says so accept any.
    pub params: Vec<(String, String)>,
}

/// A scene description read from a file, and the folder its relative paths are relative to.
#[derive(Clone, Debug)]
pub struct LoadedDescription {
    pub description: Description,
    pub base_dir: PathBuf,
    /// Where each entry of a converted description was written (empty for TOML and JSON, whose
    /// problems are placed by the text's own spans).
    pub origins: Origins,
    /// What the reader noticed but could render (pbrt's unused parameters).
    pub warnings: Vec<String>,
    /// The cameras a file defines among its content, in the order a choice of camera numbers
    /// them (glTF's camera nodes); `description.camera` views through the first. Empty for
    /// formats whose scene has one camera.
    pub cameras: Vec<FileCamera>,
}

/// One kind of scene file.
pub trait SceneFormat: Sync {
    /// Short name, for messages (`toml`, `mitsuba`, `pbrt`).
    fn name(&self) -> &'static str;

    /// The file name endings it reads, lowercase with their dot (`.toml`), for messages and the
    /// default [`Self::recognises`].
    fn extensions(&self) -> &'static [&'static str];

    /// Whether `path` is a file of this format; by default, by its name's ending.
    fn recognises(&self, path: &Path) -> bool {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        self.extensions().iter().any(|e| name.ends_with(e))
    }

    /// Whether the format reads [`FormatOptions::params`].
    fn takes_params(&self) -> bool {
        false
    }

    /// Reads and validates the scene file `path`. Errors name the file and, where the format
    /// knows it, the line and column.
    fn load(&self, path: &Path, options: &FormatOptions) -> Result<LoadedDescription>;
}

/// Reads and validates a scene file with the registered format that recognises it.
pub fn load(path: &Path, options: &FormatOptions) -> Result<LoadedDescription> {
    let format = find(path).ok_or_else(|| {
        Error::input(
            Location::file(path),
            format!(
                "unknown scene file extension: expected {}",
                registry::extension_list()
            ),
        )
    })?;
    if !options.params.is_empty() && !format.takes_params() {
        return Err(Error::input(
            Location::file(path),
            format!(
                "a {} scene takes no parameters (given: {})",
                format.name(),
                options
                    .params
                    .iter()
                    .map(|(n, _)| n.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    format.load(path, options)
}

/// The folder a scene file's relative paths are relative to: for an entry of a zip archive
/// (`x.zip:inner/scene.gltf`), the archive's folder.
fn base_dir(path: &Path) -> PathBuf {
    let archive = crate::description::archive_path::archive_path(path);
    let path = archive.as_ref().map_or(path, |a| a.archive.as_path());
    path.parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."))
}

/// Validates a description converted from `path` (its values, then its files), placing each
/// problem where `origins` recorded the entry.
fn validate_converted(
    description: Description,
    origins: Origins,
    warnings: Vec<String>,
    path: &Path,
) -> Result<LoadedDescription> {
    let base_dir = base_dir(path);
    let placed = |invalid: Invalid| converted_error(&invalid, &origins, path);
    crate::description::validate::validate(&description).map_err(placed)?;
    crate::description::validate::files(&description, &base_dir).map_err(placed)?;
    Ok(LoadedDescription {
        description,
        base_dir,
        origins,
        warnings,
        cameras: Vec::new(),
    })
}

/// A problem in a description converted from `path`: at the place `origins` recorded for it, or
/// at the file where none was.
fn converted_error(invalid: &Invalid, origins: &Origins, path: &Path) -> Error {
    let location = origins
        .locate(&invalid.path)
        .cloned()
        .unwrap_or_else(|| Location::file(path));
    let message = format!(
        "in the converted scene, {}: {}",
        path_string(&invalid.path),
        invalid.message
    );
    Error::input(location, message)
}
