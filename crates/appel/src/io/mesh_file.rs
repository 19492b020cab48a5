//! Triangle meshes from files: the entry point that picks a reader by the file's extension
//! (`.ply`, `.obj`, `.gltf`, `.glb`, `.serialized`, and `.ply.gz` / `.obj.gz`). What the readers
//! return, [`LoadedMesh`], is a description type (`description::loaded_mesh`).

use super::assets::{archive_path, open_archive, Assets};
pub use crate::description::archive_path::mesh_source_exists;
use crate::description::loaded_mesh::LoadedMesh;
use crate::error::{Error, Location, Result};
use std::io::Read;
use std::path::{Path, PathBuf};

/// Mesh formats by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    Ply,
    Obj,
    Gltf,
    /// Mitsuba's zlib-compressed `.serialized` meshes.
    Serialized,
}

impl MeshFormat {
    /// The format of a file name and whether it is gzip-compressed, or `None` if it is no mesh file.
    pub fn from_path(path: &Path) -> Option<(MeshFormat, bool)> {
        let name = path.file_name()?.to_str()?.to_ascii_lowercase();
        let (stem, gz) = match name.strip_suffix(".gz") {
            Some(s) => (s.to_string(), true),
            None => (name, false),
        };
        let ext = stem.rsplit_once('.')?.1;
        let format = match ext {
            "ply" => MeshFormat::Ply,
            "obj" => MeshFormat::Obj,
            "gltf" | "glb" if !gz => MeshFormat::Gltf,
            "serialized" if !gz => MeshFormat::Serialized,
            _ => return None,
        };
        Some((format, gz))
    }
}

/// Whether `path` names a mesh file Appel can read (by its extension), or a zip archive to find
/// one in.
pub fn is_mesh_file(path: &Path) -> bool {
    MeshFormat::from_path(path).is_some() || archive_path(path).is_some()
}

/// Reads a mesh file, or the mesh file in a zip archive (`x.zip`, `x.zip:inner/path`; see
/// [`super::assets`]). Errors name the file and the line (text formats) or byte offset (binary; for
/// `.gz` files the offset is into the decompressed data). A file without triangles is an error.
pub fn load_mesh(path: &Path) -> Result<LoadedMesh> {
    if let Some(archive) = archive_path(path) {
        let (inner, bytes, assets) = open_archive(&archive, |n| is_mesh_file(Path::new(n)))?;
        let name = PathBuf::from(format!("{}:{inner}", archive.archive.display()));
        let (format, gz) = MeshFormat::from_path(Path::new(&inner)).ok_or_else(|| {
            Error::input(
                Location::file(&name),
                "not a mesh file Appel reads: expected .ply, .obj, .gltf, .glb, .serialized, .ply.gz or .obj.gz",
            )
        })?;
        let bytes = if gz { gunzip(&bytes, &name)? } else { bytes };
        let loaded = parse_mesh_bytes(format, &bytes, &name, &assets)?;
        return check_not_empty(loaded, &name);
    }
    let (format, gz) = MeshFormat::from_path(path).ok_or_else(|| {
        Error::input(
            Location::file(path),
            "unknown mesh file extension: expected .ply, .obj, .gltf, .glb, .serialized, .ply.gz or .obj.gz (or a .zip holding one)",
        )
    })?;
    let assets = Assets::beside(path);
    let loaded = match (format, gz) {
        (MeshFormat::Ply, false) => {
            let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
            let len = file.metadata().map_err(|e| Error::io(path, e))?.len();
            if len == 0 {
                super::ply::parse_ply(&[], path)?
            } else {
                // SAFETY: the map is read-only and private to this call. Another process truncating
                // the file while we read it would fault (SIGBUS); that is the documented price of
                // mapping, paid for load speed on large scans.
                let map = unsafe { memmap2::Mmap::map(&file) }.map_err(|e| Error::io(path, e))?;
                super::ply::parse_ply(&map, path)?
            }
        }
        (format, gz) => {
            let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
            let bytes = if gz { gunzip(&bytes, path)? } else { bytes };
            parse_mesh_bytes(format, &bytes, path, &assets)?
        }
    };
    check_not_empty(loaded, path)
}

fn parse_mesh_bytes(
    format: MeshFormat,
    bytes: &[u8],
    name: &Path,
    assets: &Assets,
) -> Result<LoadedMesh> {
    match format {
        MeshFormat::Ply => super::ply::parse_ply(bytes, name),
        MeshFormat::Obj => super::obj::parse_obj(bytes, name, assets),
        MeshFormat::Gltf => super::gltf::parse_gltf_from(bytes, name, assets),
        MeshFormat::Serialized => super::serialized::parse_serialized(bytes, name),
    }
}

pub(crate) fn check_not_empty(loaded: LoadedMesh, path: &Path) -> Result<LoadedMesh> {
    if loaded.triangle_count() == 0 {
        return Err(Error::input(
            Location::file(path),
            "the mesh has no triangles: nothing to render",
        ));
    }
    Ok(loaded)
}

fn gunzip(bytes: &[u8], path: &Path) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(bytes)
        .read_to_end(&mut out)
        .map_err(|e| {
            Error::input(
                Location::file(path),
                format!("cannot decompress gzip data: {e}"),
            )
        })?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_pick_the_format() {
        let f = |s: &str| MeshFormat::from_path(Path::new(s));
        assert_eq!(f("a/b.PLY"), Some((MeshFormat::Ply, false)));
        assert_eq!(f("bunny.obj.gz"), Some((MeshFormat::Obj, true)));
        assert_eq!(f("x.glb"), Some((MeshFormat::Gltf, false)));
        assert_eq!(f("x.gltf.gz"), None);
        assert_eq!(f("scene.toml"), None);
        assert_eq!(f("noext"), None);
    }
}
