//! Any bytes given to the OBJ reader (and, through a fixed `mtllib`, the MTL reader) give a mesh or
//! an error, never a panic.
#![no_main]
use appel::io::obj::{parse_mtl, parse_obj, NoMtl};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let _ = parse_obj(data, Path::new("fuzz.obj"), &NoMtl);
    let _ = parse_mtl(data, Path::new("fuzz.mtl"));
});
