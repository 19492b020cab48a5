//! Any text given as a TOML scene is parsed and validated into a description or an error, never a
//! panic.
#![no_main]
use appel::scene::{description_from_str, parse::Syntax};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = description_from_str(text, Syntax::Toml, std::path::Path::new("fuzz.toml"));
    }
});
