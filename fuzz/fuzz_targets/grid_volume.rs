//! Any bytes given to the Mitsuba grid volume reader give a grid or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = appel::io::grid_volume::parse_grid_volume(data, std::path::Path::new("fuzz.vol"));
});
