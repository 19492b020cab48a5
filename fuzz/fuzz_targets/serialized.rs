//! Any bytes given to the Mitsuba serialized mesh reader give a mesh or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = appel::io::serialized::parse_serialized(data, std::path::Path::new("fuzz.serialized"));
});
