//! Malformed files never panic: every reader (PLY, OBJ, MTL, glTF, GLB, zip archives, images, TOML,
//! JSON and Mitsuba XML scenes) is fed mutants of small valid files (a seeded, deterministic
//! mutation fuzzer: truncations, bit flips, inserted, deleted and duplicated bytes, lying integers,
//! and for text formats NaN and huge numbers, missing closing tags and brackets, shuffled lines)
//! and the inputs that once failed (`tests/corpus/TARGET/`). Each must give a scene or an error
//! naming the file (and the line or byte where the format has them) within seconds.
//!
//! `APPEL_FUZZ_ITERATIONS`, `APPEL_FUZZ_SECONDS` (per target) and `APPEL_FUZZ_SEED` run it longer
//! or differently; failing inputs are saved under `target/tmp/malformed-failures/TARGET/`.

mod malformed;

use malformed::runner::{run, Budget, Report};
use malformed::targets::{target, TARGETS};
use std::path::Path;
use std::time::Duration;

/// Mutants per target in CI: a second or so per target in release on two cores.
const ITERATIONS: usize = 1000;

fn env_number(name: &str) -> Option<u64> {
    let v = std::env::var(name).ok()?;
    Some(
        v.parse()
            .unwrap_or_else(|_| panic!("{name} must be a whole number, not {v:?}")),
    )
}

fn budget() -> Budget {
    let seconds = env_number("APPEL_FUZZ_SECONDS");
    Budget {
        iterations: env_number("APPEL_FUZZ_ITERATIONS")
            .map(|n| n as usize)
            .unwrap_or(if seconds.is_some() {
                usize::MAX
            } else {
                ITERATIONS
            }),
        // A cap for slow machines: CI time is shared.
        time: Duration::from_secs(seconds.unwrap_or(20)),
        seed: env_number("APPEL_FUZZ_SEED").unwrap_or(0),
    }
}

/// The saved inputs of a target's regression corpus.
fn corpus(name: &str) -> Vec<Vec<u8>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/corpus")
        .join(name);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut files: Vec<_> = entries.map(|e| e.unwrap().path()).collect();
    files.sort();
    files.iter().map(|f| std::fs::read(f).unwrap()).collect()
}

fn check(name: &str, report: &Report) {
    eprintln!(
        "{name}: {} inputs in {:.2} s ({} accepted, {} rejected), slowest {:.0} ms",
        report.inputs,
        report.elapsed.as_secs_f64(),
        report.accepted,
        report.rejected,
        report.slowest.as_secs_f64() * 1e3
    );
    if report.slowest > Duration::from_millis(500) {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("malformed-failures");
        let _ = std::fs::create_dir_all(&dir);
        let path = dir.join(format!("{name}-slowest"));
        let _ = std::fs::write(&path, &report.slowest_input);
        eprintln!("{name}: the slowest input is saved as {}", path.display());
    }
    if !report.failures.is_empty() {
        let list: Vec<String> = report
            .failures
            .iter()
            .map(|f| format!("- {} (input saved as {:?})", f.what, f.saved))
            .collect();
        panic!(
            "{name}: {} kinds of failure:\n{}",
            report.failures.len(),
            list.join("\n")
        );
    }
}

fn fuzz(name: &str) {
    let t = target(name);
    let report = run(t, corpus(name), Some(budget()));
    check(name, &report);
    // Seeds must reach past the parser: most are whole files that read (a few are fragments, or
    // archives that must be named into, which are errors by design).
    let seeds = run(t, (t.seeds)(), None);
    assert!(
        seeds.accepted * 2 >= seeds.inputs,
        "{name}: only {} of {} seeds read",
        seeds.accepted,
        seeds.inputs
    );
}

#[test]
fn every_target_has_seeds_and_a_unique_name() {
    let mut names: Vec<&str> = TARGETS.iter().map(|t| t.name).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), TARGETS.len());
    // `APPEL_FUZZ_WRITE_SEEDS=fuzz/corpus` also writes them out as libFuzzer's starting corpora.
    let out = std::env::var_os("APPEL_FUZZ_WRITE_SEEDS").map(std::path::PathBuf::from);
    for t in TARGETS {
        let seeds = (t.seeds)();
        assert!(!seeds.is_empty(), "{}", t.name);
        if let Some(out) = &out {
            let dir = out.join(t.name);
            std::fs::create_dir_all(&dir).unwrap();
            for (i, seed) in seeds.iter().enumerate() {
                std::fs::write(dir.join(format!("seed-{i}-{}", t.file)), seed).unwrap();
            }
        }
    }
}

#[test]
fn malformed_ply() {
    fuzz("ply");
}

#[test]
fn malformed_obj() {
    fuzz("obj");
}

#[test]
fn malformed_mtl() {
    fuzz("mtl");
}

#[test]
fn malformed_gltf() {
    fuzz("gltf");
}

#[test]
fn malformed_glb() {
    fuzz("glb");
}

#[test]
fn malformed_zip() {
    fuzz("zip");
}

#[test]
fn malformed_image() {
    fuzz("image");
}

#[test]
fn malformed_toml() {
    fuzz("toml");
}

#[test]
fn malformed_json() {
    fuzz("json");
}

#[test]
fn malformed_xml() {
    fuzz("xml");
}
