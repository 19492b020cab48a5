//! Any text given as a pbrt-v4 scene is read into a description or an error, never a panic.
#![no_main]
use appel::format::pbrt::pbrt_from_str;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        // A folder that holds nothing, so that `Include` and file names find no files.
        let _ = pbrt_from_str(text, std::path::Path::new("/nonexistent/fuzz.pbrt"));
    }
});
