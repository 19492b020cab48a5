//! The pbrt reader on small scenes written here: directives, the graphics state, mappings and
//! their errors.

use super::load_pbrt;
use crate::scene::description::*;
use std::path::PathBuf;

/// Writes `text` as `name` in a fresh folder and reads it.
fn load_text(name: &str, text: &str) -> crate::error::Result<super::PbrtScene> {
    let dir = tempdir();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    load_pbrt(&path)
}

fn tempdir() -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "appel-pbrt-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const HEADER: &str = "Camera \"perspective\" \"float fov\" 45\nWorldBegin\n";

#[test]
fn debug_veach() {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/bitterli-scenes/veach-mis/pbrt/scene-v4.pbrt");
    if !p.exists() {
        return;
    }
    let s = load_pbrt(&p).unwrap();
    eprintln!("{:#?}", s.description.materials);
    eprintln!("{:#?}", s.description.camera);
    eprintln!("{:#?}", s.warnings);
    let _ = load_text("a.pbrt", HEADER);
}
