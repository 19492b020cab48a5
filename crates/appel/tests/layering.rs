//! The library's layers point down (docs/architecture.md): every top-level module of `src/` has a
//! floor, and the code of a module names only modules on lower floors (or itself). Read from the
//! source text: every `crate::NAME` and `super::` path outside comments and test code. A module
//! missing from the table below fails the test, so a new module must take a floor.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Bottom to top. Each module may name the modules of lower floors only.
const FLOORS: &[&[&str]] = &[
    &["math"],
    &["error"],
    &["geometry"],
    &["accel"],
    &["description"],
    &["io"],
    &["shading"],
    &["format"],
    &["scene"],
    &["scene_build"],
    &["render"],
    &["query"],
    &["output"],
    &["api"],
];

fn floor_of(module: &str) -> Option<usize> {
    FLOORS.iter().position(|floor| floor.contains(&module))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Whether a file holds test code only (a test module, a test helper).
fn is_test_file(rel: &Path) -> bool {
    let stem = rel.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    stem == "tests" || stem == "testutil" || stem.ends_with("_tests") || stem.starts_with("chi2")
}

/// The module path of a file: `accel/bvh/mod.rs` is `[accel, bvh]`, `accel/grid.rs` is
/// `[accel, grid]`.
fn module_path(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// The top-level modules a line of code names: `crate::NAME` directly, `super::...` resolved
/// from the file's module path.
fn named_modules(code: &str, module: &[String], out: &mut Vec<String>) {
    let bytes = code.as_bytes();
    let mut at = 0;
    while let Some(found) = code[at..].find("crate::") {
        let start = at + found;
        let preceded_by_ident = start > 0
            && (bytes[start - 1].is_ascii_alphanumeric()
                || bytes[start - 1] == b'_'
                || bytes[start - 1] == b':'
                || bytes[start - 1] == b'$');
        let rest = &code[start + "crate::".len()..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        if !preceded_by_ident && !name.is_empty() {
            out.push(name);
        }
        at = start + "crate::".len();
    }
    // `super::super::x` from `a/b/c.rs` (module [a, b, c]) names [a, x]: the top-level module
    // only changes when the supers climb to the crate root.
    let mut at = 0;
    while let Some(found) = code[at..].find("super::") {
        let start = at + found;
        if start > 0 && (bytes[start - 1].is_ascii_alphanumeric() || bytes[start - 1] == b':') {
            at = start + 7;
            continue;
        }
        let mut supers = 0;
        let mut rest = &code[start..];
        while let Some(r) = rest.strip_prefix("super::") {
            supers += 1;
            rest = r;
        }
        if supers >= module.len() {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.push(name);
            }
        }
        at = start + 7 * supers;
    }
}

#[test]
fn no_module_names_one_above_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut problems = Vec::new();
    let mut unplaced = BTreeMap::new();
    for file in &files {
        let rel = file.strip_prefix(&src).unwrap();
        if rel == Path::new("lib.rs") || is_test_file(rel) {
            continue;
        }
        let module = module_path(rel);
        let top = module[0].clone();
        let Some(floor) = floor_of(&top) else {
            unplaced.insert(top, rel.display().to_string());
            continue;
        };
        let text = std::fs::read_to_string(file).unwrap();
        for (number, line) in text.lines().enumerate() {
            let code = line.trim_start();
            // Test modules sit at the end of a file, after their cfg attribute.
            if code.starts_with("#[cfg(test)]") {
                break;
            }
            if code.starts_with("//") {
                continue;
            }
            let code = code.split(" //").next().unwrap_or(code);
            let mut named = Vec::new();
            named_modules(code, &module, &mut named);
            for name in named {
                if name == top {
                    continue;
                }
                match floor_of(&name) {
                    Some(f) if f < floor => {}
                    Some(_) => problems.push(format!(
                        "{}:{}: `{top}` names `{name}`, which is not beneath it",
                        rel.display(),
                        number + 1
                    )),
                    // Crate-root items (`crate::Error`, `crate::Result`) re-exported by lib.rs.
                    None if name.chars().next().is_some_and(char::is_uppercase) => {}
                    None => problems.push(format!(
                        "{}:{}: `{top}` names `{name}`, a module with no floor",
                        rel.display(),
                        number + 1
                    )),
                }
            }
        }
    }
    assert!(
        unplaced.is_empty() && problems.is_empty(),
        "modules with no floor in this test's table (give each one): {unplaced:?}\n\
         {} upward references:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn the_scanner_sees_crate_and_super_paths() {
    let module = ["scene".to_string(), "geometry".to_string()];
    let mut named = Vec::new();
    named_modules(
        "use crate::accel::Accel; let x = super::super::render::Film; y::crate::z; super::queries::q",
        &module,
        &mut named,
    );
    assert_eq!(named, vec!["accel".to_string(), "render".to_string()]);
}
