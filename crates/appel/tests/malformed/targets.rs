//! The readers under test, one entry each in [`TARGETS`]: the file name the input is written as,
//! its seeds, the files beside it, and how it is read. Reading goes as far as the command line
//! goes before rendering: a mesh file is loaded, built into a scene and framed; a scene file is
//! parsed, validated and built (with the files it names). Adding a reader is one entry here.

use super::seeds;
use appel::description::validate;
use appel::description::Description;
use appel::error::{Error, Result};
use appel::scene::Scene;
use std::path::Path;

/// What an error about this format must say besides the file: a line (text), a line or a byte
/// offset (formats with a text header and a binary body), or only the file (binary containers
/// whose decoders do not report positions; glTF, whose errors name the JSON path instead).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Located {
    Line,
    LineOrByte,
    File,
}

/// Errors that may be about no one place: a fact of the whole file, or (Mitsuba XML) a problem
/// that only the validation of the converted description finds in an entry no element made
/// (such errors are at the element's line where one did), which names the description's key.
pub const NOT_PLACED: &[&str] = &[
    "the mesh has no triangles",
    "the model cannot be viewed",
    "in the converted scene, ",
];

pub struct Target {
    /// Also the name of its regression corpus folder, `tests/corpus/NAME`.
    pub name: &'static str,
    /// The name the input is written as (its extension picks the reader).
    pub file: &'static str,
    pub seeds: fn() -> Vec<Vec<u8>>,
    /// Files written beside the input, which the seeds refer to.
    pub siblings: fn() -> Vec<(&'static str, Vec<u8>)>,
    pub read: fn(&Path) -> Result<()>,
    /// Whether token-level mutations (numbers, closing tags, lines, names) apply.
    pub text: bool,
    pub located: Located,
}

fn none() -> Vec<(&'static str, Vec<u8>)> {
    Vec::new()
}

pub const TARGETS: &[Target] = &[
    Target {
        name: "ply",
        file: "mesh.ply",
        seeds: seeds::ply,
        siblings: none,
        read: read_model,
        text: false,
        located: Located::LineOrByte,
    },
    Target {
        name: "obj",
        file: "mesh.obj",
        seeds: seeds::obj,
        siblings: obj_siblings,
        read: read_model,
        text: true,
        located: Located::Line,
    },
    Target {
        name: "mtl",
        file: "m.mtl",
        seeds: seeds::mtl,
        siblings: mtl_siblings,
        read: read_mtl,
        text: true,
        located: Located::Line,
    },
    Target {
        name: "gltf",
        file: "model.gltf",
        seeds: seeds::gltf,
        siblings: seeds::gltf_siblings,
        read: read_model,
        text: true,
        located: Located::File,
    },
    Target {
        name: "glb",
        file: "model.glb",
        seeds: seeds::glb,
        siblings: none,
        read: read_model,
        text: false,
        located: Located::File,
    },
    Target {
        name: "zip",
        file: "archive.zip",
        seeds: seeds::zip,
        siblings: none,
        read: read_model,
        text: false,
        located: Located::File,
    },
    Target {
        name: "image",
        file: "tex.png",
        seeds: seeds::images,
        siblings: none,
        read: read_image,
        text: false,
        located: Located::File,
    },
    Target {
        name: "toml",
        file: "scene.toml",
        seeds: seeds::toml,
        siblings: seeds::scene_siblings,
        read: read_scene,
        text: true,
        located: Located::Line,
    },
    Target {
        name: "json",
        file: "scene.json",
        seeds: seeds::json,
        siblings: seeds::scene_siblings,
        read: read_scene,
        text: true,
        located: Located::Line,
    },
    Target {
        name: "xml",
        file: "scene.xml",
        seeds: seeds::xml,
        siblings: seeds::scene_siblings,
        read: read_scene,
        text: true,
        located: Located::Line,
    },
];

pub fn target(name: &str) -> &'static Target {
    TARGETS
        .iter()
        .find(|t| t.name == name)
        .unwrap_or_else(|| panic!("no target {name}"))
}

fn obj_siblings() -> Vec<(&'static str, Vec<u8>)> {
    vec![
        ("m.mtl", seeds::MTL.as_bytes().to_vec()),
        ("tex.png", seeds::png_rgba()),
    ]
}

fn mtl_siblings() -> Vec<(&'static str, Vec<u8>)> {
    vec![
        ("mesh.obj", seeds::obj().remove(0)),
        ("tex.png", seeds::png_rgba()),
    ]
}

/// As `appel render mesh.ply` does: the mesh file framed by a camera of its own.
fn read_model(path: &Path) -> Result<()> {
    let dir = path.parent().expect("in a folder");
    let file = path.file_name().and_then(|f| f.to_str()).expect("a name");
    let description = appel::scene::model_description(file);
    let mut scene = Scene::new(&description, dir)?;
    let framed = appel::scene::view_model(&scene, &description, None)?;
    validate::validate(&framed).map_err(|e| Error::Invalid(e.message))?;
    scene.set_view(&framed)
}

/// An MTL library, alone and as the library of an OBJ file that uses its materials and maps.
fn read_mtl(path: &Path) -> Result<()> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    appel::io::obj::parse_mtl_with_maps(&bytes, path)?;
    read_model(&path.with_file_name("mesh.obj"))
}

fn read_image(path: &Path) -> Result<()> {
    let bitmap = appel::io::bitmap_read::read_bitmap(path, false)?;
    let expected = bitmap.width as usize * bitmap.height as usize * bitmap.channels as usize;
    assert_eq!(
        bitmap.data.len(),
        expected,
        "a bitmap's size agrees with its data"
    );
    Ok(())
}

/// Pixels are not allocated before rendering, but a scene's estimate counts them: the scene is
/// built at a small size so that the estimate measures what building it holds.
const MAX_SCENE_BYTES: u64 = 256 << 20;

/// As `appel render scene.toml` does before rendering: read, validate, check the memory estimate,
/// build.
fn read_scene(path: &Path) -> Result<()> {
    assert!(appel::format::find(path).is_some(), "{}", path.display());
    let loaded = appel::format::load(path, &Default::default())?;
    let mut d: Description = loaded.description;
    d.camera.width = d.camera.width.min(16);
    d.camera.height = d.camera.height.min(16);
    let estimate = appel::scene::estimate_memory(&d, &loaded.base_dir)?;
    if estimate.bytes > MAX_SCENE_BYTES {
        // The command line refuses such a scene before loading it.
        return Ok(());
    }
    Scene::new(&d, &loaded.base_dir).map(|_| ())
}
