//! Where the tests find the shared test data: the folder named by `APPEL_DATA` when it is set at
//! build time, otherwise `shared/data` beside the checkout (`../shared/data` from the repository's
//! root), so that nothing depends on where the repository lies.
//!
//! A crate whose tests read the data calls [`build_script`] from its `build.rs`; it sets the cfg
//! `shared_data` when the folder exists. Each such test is marked
//!
//! ```text
//! #[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
//! ```
//!
//! so that without the data the test summary counts it as ignored and names the reason, and with
//! the data (as in CI) it runs and a missing file fails it.

use std::path::{Path, PathBuf};

/// The reason printed beside a test ignored for want of the data.
pub const REASON: &str = "needs ../shared/data";

/// The shared data folder (it may not exist).
pub fn dir() -> PathBuf {
    match option_env!("APPEL_DATA") {
        Some(d) if !d.is_empty() => PathBuf::from(d),
        // This crate sits at `crates/appel-testdata` in the repository.
        _ => Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"),
    }
}

/// Whether the shared data folder exists.
pub fn present() -> bool {
    dir().is_dir()
}

/// The path of `rel` in the shared data. Call it from tests marked as the crate documentation
/// shows: it panics if the file is missing, because such a test runs only where the data is.
pub fn path(rel: &str) -> PathBuf {
    let p = dir().join(rel);
    assert!(
        p.exists(),
        "{rel} is missing from the shared data folder {}",
        dir().display()
    );
    p
}

/// Prints the line a test that returns early without checking anything prints, for a reason other
/// than the data (a peer library that is not installed, say): `SKIPPED: <test>: <why>`.
pub fn skip(test: &str, why: impl std::fmt::Display) {
    eprintln!("SKIPPED: {test}: {why}");
}

/// For a `build.rs`: declares the cfg `shared_data` and sets it when the data folder exists.
///
/// The script runs again when `APPEL_DATA` changes or anything in the folder does. A folder that
/// is absent cannot be watched without rebuilding on every run, so after adding the data to a
/// checkout that was built without it, touch the crate's `build.rs` (or `cargo clean`).
pub fn build_script() {
    println!("cargo::rustc-check-cfg=cfg(shared_data)");
    println!("cargo::rerun-if-env-changed=APPEL_DATA");
    println!("cargo::rerun-if-changed=build.rs");
    let dir = dir();
    if dir.is_dir() {
        println!("cargo::rustc-cfg=shared_data");
        println!("cargo::rerun-if-changed={}", dir.display());
    } else {
        println!(
            "cargo::warning=no shared test data at {}: the tests that need it are ignored",
            dir.display()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_folder_is_beside_the_checkout_unless_named() {
        if option_env!("APPEL_DATA").is_some_and(|d| !d.is_empty()) {
            return;
        }
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        assert!(root.join("Cargo.toml").is_file(), "the workspace root");
        assert_eq!(dir(), root.join("../shared/data"));
    }
}
