//! How a description names a mesh inside a zip archive: `archive.zip` (the archive then holds
//! exactly one mesh file) or `archive.zip:path/inside.obj`. Reading the archive is `io::assets`'
//! work; the name alone is what validation and the memory estimate need.

use std::path::{Path, PathBuf};

/// A mesh file named inside a zip archive.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArchivePath {
    pub archive: PathBuf,
    /// The entry, if one was named after `:`.
    pub inner: Option<String>,
}

/// `x.zip` or `x.zip:inner/path` (the extension in any case), else `None`.
pub fn archive_path(path: &Path) -> Option<ArchivePath> {
    let s = path.to_str()?;
    let lower = s.to_ascii_lowercase();
    if lower.ends_with(".zip") {
        return Some(ArchivePath {
            archive: PathBuf::from(s),
            inner: None,
        });
    }
    let at = lower.find(".zip:")?;
    let inner = &s[at + 5..];
    Some(ArchivePath {
        archive: PathBuf::from(&s[..at + 4]),
        inner: (!inner.is_empty()).then(|| inner.to_string()),
    })
}

/// Whether `path` names a mesh file that exists, or an archive that exists (its entry is checked
/// when it is read).
pub fn mesh_source_exists(path: &Path) -> bool {
    match archive_path(path) {
        Some(a) => a.archive.is_file(),
        None => path.is_file(),
    }
}
