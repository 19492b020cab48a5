//! Any bytes given to the PLY reader give a mesh or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = appel::io::ply::parse_ply(data, std::path::Path::new("fuzz.ply"));
});
