//! pbrt-v4 scene files (`.pbrt`): `tokenizer` and `params` read the text and its typed parameter
//! lists, `parser` the directives (following `Include` and `Import`), and `convert` walks them
//! with pbrt's graphics state, mapping the supported subset onto Appel's
//! [`Description`](crate::description::Description): `options` the camera, film, sampler, filter and
//! integrator, `shapes`, `materials` (with `textures` and `spectrum`) and `lights` the world.
//! docs/pbrt.md lists what is supported and how each piece maps.

mod convert;
mod lights;
mod materials;
mod media;
mod options;
mod origins;
mod params;
mod parser;
mod shapes;
mod spectrum;
mod textures;
mod tokenizer;

#[cfg(test)]
mod tests;

use crate::description::Description;
use crate::error::Result;
use std::path::Path;

/// A pbrt scene as Appel's description, with pbrt's warnings (parameters nobody used).
#[derive(Clone, Debug)]
pub struct PbrtScene {
    pub description: Description,
    pub warnings: Vec<String>,
    /// Where each entry of the description was written, to place the problems its validation
    /// finds.
    pub origins: crate::description::origins::Origins,
}

/// Reads a pbrt-v4 scene file (or `.pbrt.gz`); file names in the description are absolute.
pub fn load_pbrt(path: &Path) -> Result<PbrtScene> {
    let text = parser::read_text(path, None)?;
    pbrt_from_str(&text, path)
}

/// Reads pbrt-v4 scene text as if it were the file `path` (which names it in errors and whose
/// folder resolves relative file names).
pub fn pbrt_from_str(text: &str, path: &Path) -> Result<PbrtScene> {
    convert::convert(text, path)
}

/// Whether the file name says pbrt (`.pbrt`, `.pbrt.gz`).
pub fn is_pbrt(path: &Path) -> bool {
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    name.ends_with(".pbrt") || name.ends_with(".pbrt.gz")
}

/// pbrt-v4 scenes (`.pbrt`, `.pbrt.gz`; see docs/pbrt.md).
pub struct PbrtFormat;

impl super::SceneFormat for PbrtFormat {
    fn name(&self) -> &'static str {
        "pbrt"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".pbrt", ".pbrt.gz"]
    }

    fn recognises(&self, path: &Path) -> bool {
        is_pbrt(path)
    }

    /// File names come out absolute; the warnings list the parameters the scene gives and nothing
    /// read, as pbrt reports them.
    fn load(
        &self,
        path: &Path,
        _options: &super::FormatOptions,
    ) -> Result<super::LoadedDescription> {
        let scene = load_pbrt(path)?;
        super::validate_converted(scene.description, scene.origins, scene.warnings, path)
    }
}
