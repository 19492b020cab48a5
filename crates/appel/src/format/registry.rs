//! The scene formats, listed once: [`load`](super::load) asks each in turn whether it recognises
//! a path, and the error for a file none recognises lists their extensions. A format is added by
//! implementing [`SceneFormat`] in its own module and naming it here.

use super::SceneFormat;
use std::path::Path;

static FORMATS: &[&dyn SceneFormat] = &[
    &super::toml::TomlFormat,
    &super::mitsuba::MitsubaFormat,
    &super::pbrt::PbrtFormat,
    &super::gltf::GltfFormat,
];

/// Every registered format, in the order they are asked.
pub fn formats() -> &'static [&'static dyn SceneFormat] {
    FORMATS
}

/// The format that recognises `path`, if any.
pub fn find(path: &Path) -> Option<&'static dyn SceneFormat> {
    FORMATS.iter().copied().find(|f| f.recognises(path))
}

/// `.toml, .json, .xml, .pbrt, .pbrt.gz, .gltf or .glb`: the extensions of all formats, for messages.
pub fn extension_list() -> String {
    let all: Vec<&str> = FORMATS
        .iter()
        .flat_map(|f| f.extensions())
        .copied()
        .collect();
    match all.split_last() {
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_extensions_are_unique() {
        let mut names: Vec<&str> = formats().iter().map(|f| f.name()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), formats().len());
        let mut exts: Vec<&str> = formats()
            .iter()
            .flat_map(|f| f.extensions())
            .copied()
            .collect();
        let n = exts.len();
        exts.sort_unstable();
        exts.dedup();
        assert_eq!(exts.len(), n);
    }

    #[test]
    fn paths_find_their_format() {
        let name = |p: &str| find(Path::new(p)).map(|f| f.name());
        assert_eq!(name("a/scene.toml"), Some("toml"));
        assert_eq!(name("a/scene.JSON"), Some("toml"));
        assert_eq!(name("cbox.xml"), Some("mitsuba"));
        assert_eq!(name("k/killeroo.pbrt"), Some("pbrt"));
        assert_eq!(name("k/killeroo.pbrt.gz"), Some("pbrt"));
        assert_eq!(name("h/DamagedHelmet.glb"), Some("gltf"));
        assert_eq!(name("h/FlightHelmet.GLTF"), Some("gltf"));
        assert_eq!(name("assets.zip:dir/scene.gltf"), Some("gltf"));
        assert_eq!(name("assets.zip"), None);
        assert_eq!(name("bunny.ply"), None);
        assert_eq!(name("noext"), None);
    }

    #[test]
    fn an_unknown_extension_lists_the_registered_ones() {
        let e = crate::format::load(Path::new("scene.yaml"), &Default::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("scene.yaml"), "{e}");
        assert!(
            e.contains("expected .toml, .json, .xml, .pbrt, .pbrt.gz, .gltf or .glb"),
            "{e}"
        );
    }

    #[test]
    fn parameters_go_only_to_formats_that_take_them() {
        let options = super::super::FormatOptions {
            params: vec![("spp".into(), "4".into())],
        };
        let e = crate::format::load(Path::new("scene.toml"), &options)
            .unwrap_err()
            .to_string();
        assert!(e.contains("takes no parameters (given: spp)"), "{e}");
    }
}
