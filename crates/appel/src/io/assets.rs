//! Where a mesh file and the files it refers to (MTL libraries, glTF buffers, textures) come from:
//! the folder of the mesh file, or the folder of an entry inside a zip archive.
//!
//! A zip archive is named as `archive.zip` (the archive must then hold exactly one mesh file) or
//! `archive.zip:path/inside.obj`. References are resolved relative to the mesh file's folder in
//! either case; inside an archive, `..` and `.` are resolved by hand and `\` (written by Windows
//! exporters into MTL files) is read as `/`. A name not found as written is looked up again ignoring
//! case, since OBJ/MTL files copied between systems often disagree with their textures' case.

use crate::error::{Error, Location, Result};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

pub use crate::description::archive_path::{archive_path, ArchivePath};

/// The files a mesh refers to.
pub enum Assets {
    /// Relative to this folder.
    Dir(PathBuf),
    /// Relative to `dir` (with a trailing `/`, or empty) inside the archive.
    Zip {
        archive: PathBuf,
        zip: Mutex<zip::ZipArchive<std::fs::File>>,
        dir: String,
    },
    /// Nothing can be read (tests, fuzzing).
    None,
}

impl Assets {
    /// The files beside `path` on disk.
    pub fn beside(path: &Path) -> Self {
        Assets::Dir(path.parent().unwrap_or(Path::new(".")).to_path_buf())
    }

    /// How `relative` is named in messages.
    pub fn name(&self, relative: &str) -> PathBuf {
        match self {
            Assets::Dir(dir) => dir.join(relative),
            Assets::Zip { archive, dir, .. } => PathBuf::from(format!(
                "{}:{}",
                archive.display(),
                normalise(dir, relative)
            )),
            Assets::None => PathBuf::from(relative),
        }
    }

    /// The bytes of `relative`, or a message saying why not (naming the file).
    pub fn read(&self, relative: &str) -> std::result::Result<Vec<u8>, String> {
        match self {
            Assets::Dir(dir) => {
                let file = dir.join(relative.replace('\\', "/"));
                std::fs::read(&file).map_err(|e| {
                    if e.kind() == std::io::ErrorKind::NotFound {
                        format!("`{}` does not exist", file.display())
                    } else {
                        format!("cannot read `{}`: {e}", file.display())
                    }
                })
            }
            Assets::Zip { archive, zip, dir } => {
                let name = normalise(dir, relative);
                let mut zip = zip.lock().unwrap_or_else(|p| p.into_inner());
                let found = zip.index_for_name(&name).or_else(|| {
                    let lower = name.to_lowercase();
                    (0..zip.len()).find(|&i| {
                        zip.name_for_index(i)
                            .is_some_and(|n| n.is_ok_and(|n| n.to_lowercase() == lower))
                    })
                });
                let Some(index) = found else {
                    return Err(format!(
                        "`{name}` is not in the archive `{}`",
                        archive.display()
                    ));
                };
                read_entry(&mut zip, index)
                    .map_err(|e| format!("cannot read `{name}` from `{}`: {e}", archive.display()))
            }
            Assets::None => Err(format!("`{relative}` cannot be read here")),
        }
    }
}

/// Refuses entries that would need more than this much memory: a zip's declared size is what a
/// hostile archive lies about first.
const MAX_ENTRY_BYTES: u64 = 4 << 30;

fn read_entry(
    zip: &mut zip::ZipArchive<std::fs::File>,
    index: usize,
) -> std::result::Result<Vec<u8>, String> {
    let entry = zip.by_index(index).map_err(|e| e.to_string())?;
    let size = entry.size();
    if size > MAX_ENTRY_BYTES {
        return Err(format!(
            "the entry declares {size} bytes, more than Appel reads"
        ));
    }
    let mut out = Vec::with_capacity(size as usize);
    // At most the declared size plus one byte: an entry longer than it says is an error (the
    // zip crate checks the CRC at the end of a complete read).
    entry
        .take(size + 1)
        .read_to_end(&mut out)
        .map_err(|e| e.to_string())?;
    if out.len() as u64 != size {
        return Err(format!(
            "the entry holds {} bytes but declares {size}",
            out.len()
        ));
    }
    Ok(out)
}

/// `dir` + `relative` as an archive entry name: `\` as `/`, `.` and `..` resolved.
fn normalise(dir: &str, relative: &str) -> String {
    let joined = format!("{dir}{}", relative.replace('\\', "/"));
    let mut parts: Vec<&str> = vec![];
    for p in joined.split('/') {
        match p {
            "" | "." => {}
            ".." => {
                parts.pop();
            }
            p => parts.push(p),
        }
    }
    parts.join("/")
}

/// Opens `path`'s archive and picks its mesh file: the named entry, or the only mesh file in it.
/// Returns the entry's name, its bytes and the archive as the source of the files it refers to.
pub fn open_archive(
    path: &ArchivePath,
    is_mesh: impl Fn(&str) -> bool,
) -> Result<(String, Vec<u8>, Assets)> {
    let at = || Location::file(&path.archive);
    let file = std::fs::File::open(&path.archive).map_err(|e| Error::io(&path.archive, e))?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| Error::input(at(), format!("not a readable zip archive: {e}")))?;
    let names: Vec<String> = zip
        .file_names()
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(|e| Error::input(at(), format!("not a readable zip archive: {e}")))?
        .into_iter()
        .map(|n| n.into_owned())
        .collect();
    let mut meshes: Vec<&String> = names
        .iter()
        .filter(|n| !n.ends_with('/') && !n.starts_with("__MACOSX/") && is_mesh(n))
        .collect();
    meshes.sort();
    let list = |m: &[&String]| {
        if m.is_empty() {
            "none".to_string()
        } else {
            m.iter()
                .map(|s| format!("`{s}`"))
                .collect::<Vec<_>>()
                .join(", ")
        }
    };
    let inner =
        match &path.inner {
            Some(want) => {
                let want = normalise("", want);
                if !names.contains(&want) {
                    return Err(Error::input(
                        at(),
                        format!(
                            "`{want}` is not in the archive; its mesh files are: {}",
                            list(&meshes)
                        ),
                    ));
                }
                want
            }
            None => match meshes.as_slice() {
                [one] => one.to_string(),
                [] => return Err(Error::input(
                    at(),
                    "the archive holds no mesh file (.ply, .obj, .gltf, .glb, .ply.gz, .obj.gz)",
                )),
                many => {
                    return Err(Error::input(
                        at(),
                        format!(
                            "the archive holds several mesh files: {}; name one as `{}:PATH`",
                            list(many),
                            path.archive.display()
                        ),
                    ))
                }
            },
        };
    let index = zip
        .index_for_name(&inner)
        .ok_or_else(|| Error::input(at(), format!("`{inner}` is not in the archive")))?;
    let bytes = read_entry(&mut zip, index)
        .map_err(|e| Error::input(at(), format!("cannot read `{inner}`: {e}")))?;
    let dir = match inner.rfind('/') {
        Some(i) => inner[..=i].to_string(),
        None => String::new(),
    };
    Ok((
        inner,
        bytes,
        Assets::Zip {
            archive: path.archive.clone(),
            zip: Mutex::new(zip),
            dir,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn archive_paths() {
        let a = archive_path(Path::new("d/Sponza.ZIP")).unwrap();
        assert_eq!(a.archive, PathBuf::from("d/Sponza.ZIP"));
        assert_eq!(a.inner, None);
        let a = archive_path(Path::new("d/s.zip:x/y.obj")).unwrap();
        assert_eq!(a.archive, PathBuf::from("d/s.zip"));
        assert_eq!(a.inner.as_deref(), Some("x/y.obj"));
        assert_eq!(archive_path(Path::new("d/s.obj")), None);
    }

    #[test]
    fn names_resolve_dots_and_backslashes() {
        assert_eq!(normalise("a/b/", "..\\tex\\c.png"), "a/tex/c.png");
        assert_eq!(normalise("", "./c.png"), "c.png");
        assert_eq!(normalise("a/", "../../c.png"), "c.png");
    }
}
