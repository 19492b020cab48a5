//! Mitsuba's file resolver: a relative file name is looked for in each folder of a list in turn.
//! A scene file's folder starts the list of names written in it, each `<path>` is put in front
//! (so the last one declared is searched first), and an included file's folder is put in front
//! of its includer's list as it stands at the `<include>`. Mitsuba also searches the working
//! directory last; Appel does not, so that a scene means the same wherever it is run from.

use std::path::{Path, PathBuf};

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FileResolver {
    folders: Vec<PathBuf>,
}

impl FileResolver {
    pub fn prepend(&mut self, folder: PathBuf) {
        self.folders.insert(0, folder);
    }

    /// The folders searched, first to last.
    pub fn folders(&self) -> &[PathBuf] {
        &self.folders
    }

    /// The first existing `folder/name`; an absolute name if it exists.
    pub fn resolve(&self, name: &str) -> Option<PathBuf> {
        let path = Path::new(name);
        if path.is_absolute() {
            return path.exists().then(|| path.to_path_buf());
        }
        self.folders
            .iter()
            .map(|f| f.join(path))
            .find(|p| p.exists())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_last_prepended_folder_is_searched_first() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        for f in [&a, &b] {
            std::fs::create_dir(f).unwrap();
            std::fs::write(f.join("m.obj"), "").unwrap();
        }
        std::fs::write(a.join("only_a.obj"), "").unwrap();
        let mut r = FileResolver::default();
        r.prepend(a.clone());
        r.prepend(b.clone());
        assert_eq!(r.folders(), [b.clone(), a.clone()]);
        assert_eq!(r.resolve("m.obj"), Some(b.join("m.obj")));
        assert_eq!(r.resolve("only_a.obj"), Some(a.join("only_a.obj")));
        assert_eq!(r.resolve("missing.obj"), None);
        let abs = a.join("m.obj");
        assert_eq!(r.resolve(abs.to_str().unwrap()), Some(abs));
    }
}
