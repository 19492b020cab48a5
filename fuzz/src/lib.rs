//! The readers of `crates/appel/tests/malformed` (the same table of targets, seeds and sibling
//! files that the stable mutation fuzzer uses) under libFuzzer. Each target writes its input as the
//! target's file, beside the target's sibling files, and reads it as the command line would.

#[path = "../../crates/appel/tests/malformed/seeds.rs"]
pub mod seeds;
#[path = "../../crates/appel/tests/malformed/targets.rs"]
pub mod targets;

use std::cell::RefCell;

thread_local! {
    static DIR: RefCell<Option<(&'static str, tempfile::TempDir)>> = const { RefCell::new(None) };
}

/// Reads `data` with the target `name`. Errors are fine; a panic, a hang or running out of memory
/// is what libFuzzer reports.
pub fn read(name: &'static str, data: &[u8]) {
    let target = targets::target(name);
    DIR.with(|d| {
        let mut d = d.borrow_mut();
        if d.as_ref().is_none_or(|(n, _)| *n != name) {
            let dir = tempfile::tempdir().expect("a temporary folder");
            for (file, bytes) in (target.siblings)() {
                std::fs::write(dir.path().join(file), bytes).expect("a sibling is written");
            }
            *d = Some((name, dir));
        }
        let (_, dir) = d.as_ref().expect("set above");
        let path = dir.path().join(target.file);
        std::fs::write(&path, data).expect("the input is written");
        let _ = (target.read)(&path);
    });
}

/// `fuzz_reader!("ply");` is a whole fuzz target.
#[macro_export]
macro_rules! fuzz_reader {
    ($name:literal) => {
        libfuzzer_sys::fuzz_target!(|data: &[u8]| $crate::read($name, data));
    };
}
