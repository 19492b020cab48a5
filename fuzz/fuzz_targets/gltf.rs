//! Any bytes given to the glTF reader (as .gltf JSON or .glb) give a mesh or an error, never a
//! panic. External buffers resolve to the input itself, so they exist but hold arbitrary bytes.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = appel::io::gltf::parse_gltf_with(data, std::path::Path::new("fuzz.gltf"), &|_| {
        Ok(data.to_vec())
    });
});
