//! `appel gen`: the same seed gives the same bytes, another seed other bytes, and what it writes
//! renders; the scale guards around rendering (instanceid AOV, memory estimate) as a user meets them.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output};

fn appel(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_appel"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("appel runs")
}

fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let p = e.unwrap().path();
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect()
}

fn generate(scene: &str, out: &str, seed: &str, dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let o = appel(
        &[
            "gen",
            scene,
            "-o",
            out,
            "--seed",
            seed,
            "--detail",
            "0.001",
            "--density",
            "0.05",
            "-q",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    files(&dir.join(out))
}

#[test]
fn gen_is_reproducible_from_its_seed_and_renders() {
    let dir = tempfile::tempdir().unwrap();
    for scene in ["ecosystem", "city"] {
        let a = generate(scene, &format!("{scene}-a"), "7", dir.path());
        let b = generate(scene, &format!("{scene}-b"), "7", dir.path());
        let c = generate(scene, &format!("{scene}-c"), "8", dir.path());
        assert_eq!(
            a.keys().collect::<Vec<_>>(),
            b.keys().collect::<Vec<_>>(),
            "{scene}"
        );
        for (name, bytes) in &a {
            assert!(
                bytes == &b[name],
                "{scene}: {name} differs for the same seed"
            );
        }
        assert!(a != c, "{scene}: another seed gives the same scene");
        if scene == "ecosystem" {
            // Twenty species, two meshes and one placement list each, plus terrain and scene.
            assert_eq!(a.len(), 62);
            assert!(a.contains_key("oak-foliage.ply") && a.contains_key("fescue.txt"));
        }
        let toml = format!("{scene}-a/{scene}.toml");
        let o = appel(
            &[
                "render",
                &toml,
                "-o",
                "x.exr",
                "--size",
                "96x54",
                "--aov",
                "instanceid,primid",
                "--quiet",
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(dir.path().join("x.exr").is_file());
    }
}

#[test]
fn gen_rejects_bad_arguments() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["gen", "forest", "-o", "x"][..],
        &["gen", "city", "-o", "x", "--detail", "0"],
        &["gen", "ecosystem", "-o", "x", "--density", "nan"],
    ] {
        let o = appel(args, dir.path());
        assert!(!o.status.success(), "{args:?} accepted");
        assert!(!String::from_utf8_lossy(&o.stderr).contains("panicked"));
    }
}

#[test]
fn a_scene_too_large_for_memory_fails_before_loading_and_names_its_need() {
    // A PLY whose header declares a trillion faces: the estimate, made from the header alone,
    // exceeds any machine's memory, and the render stops before reading the data.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("huge.ply"),
        "ply\nformat binary_little_endian 1.0\nelement vertex 500000000000\nproperty float x\n\
         property float y\nproperty float z\nelement face 1000000000000\n\
         property list uchar int vertex_indices\nend_header\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n\
         [[shape]]\ntype = \"mesh\"\nfile = \"huge.ply\"\n",
    )
    .unwrap();
    let o = appel(
        &["render", "s.toml", "-o", "out.png", "--quiet"],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("the scene needs an estimated"), "{err}");
    assert!(err.contains("1000000000000 triangles"), "{err}");
    assert!(err.contains("GB is available"), "{err}");
    assert!(!dir.path().join("out.png").exists());
}

#[test]
fn ctrl_c_stops_promptly_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let o = appel(
        &[
            "gen",
            "ecosystem",
            "-o",
            "eco",
            "--detail",
            "0.05",
            "--density",
            "0.2",
            "-q",
        ],
        dir.path(),
    );
    assert!(o.status.success());
    for delay_ms in [100, 1500] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_appel"))
            .args([
                "render",
                "eco/ecosystem.toml",
                "-o",
                "out.exr",
                "--aov",
                "depth",
                // Many samples per pixel: the render lasts seconds, so the second signal lands
                // while it runs however fast the machine builds.
                "--spp",
                "16",
                "--quiet",
            ])
            .current_dir(dir.path())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let sent = std::time::Instant::now();
        Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        let status = child.wait().unwrap();
        let waited = sent.elapsed();
        assert!(
            !status.success(),
            "finished before the signal at {delay_ms} ms"
        );
        assert!(waited.as_secs_f64() < 5.0, "took {waited:?} to stop");
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n != "eco")
            .collect();
        assert!(left.is_empty(), "left {left:?}");
    }
}

#[test]
fn ctrl_c_stops_gen_without_a_scene_file_or_a_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_appel"))
        .args(["gen", "ecosystem", "-o", "eco", "--detail", "0.3", "-q"])
        .current_dir(dir.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(250));
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let status = child.wait().unwrap();
    let names: Vec<String> = std::fs::read_dir(dir.path().join("eco"))
        .map(|d| {
            d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    assert!(!names.iter().any(|n| n.contains(".tmp")), "{names:?}");
    if !status.success() {
        assert!(!names.contains(&"ecosystem.toml".to_string()), "{names:?}");
    }
}

#[test]
fn exr_instanceid_channel_names_the_placement_hit() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    // A unit triangle (in x, y) placed three times along x by a placement list, seen head-on.
    std::fs::write(
        dir.path().join("t.obj"),
        "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0 0.5 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("row.txt"),
        "1 0 0 -2 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 2 0 1 0 0 0 0 1 0\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        "[camera]\neye = [0.0, 0.0, 8.0]\nlook_at = [0.0, 0.0, 0.0]\nwidth = 60\nheight = 20\nfov = 20.0\n\
         [meshes.tri]\nfile = \"t.obj\"\n[[instance]]\nmesh = \"tri\"\nplacements = \"row.txt\"\n",
    )
    .unwrap();
    let o = appel(
        &[
            "render",
            "s.toml",
            "-o",
            "i.exr",
            "--aov",
            "instanceid,primid",
            "--quiet",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let image = read_all_flat_layers_from_file(dir.path().join("i.exr")).unwrap();
    let layer = &image.layer_data[0];
    let channel = |n: &str| {
        &layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == n)
            .unwrap_or_else(|| panic!("no channel {n}"))
            .sample_data
    };
    let (FlatSamples::U32(inst), FlatSamples::U32(shape)) =
        (channel("instanceid"), channel("shapeid"))
    else {
        panic!("instanceid and shapeid must be uint32");
    };
    // The middle row crosses the three triangles left to right, with sky around them.
    let row: Vec<u32> = inst[60 * 10..60 * 11].to_vec();
    let mut seen: Vec<u32> = row.iter().copied().filter(|&i| i != u32::MAX).collect();
    seen.dedup();
    assert_eq!(seen, vec![0, 1, 2], "{row:?}");
    assert_eq!(row[0], u32::MAX);
    assert!(inst[..60].iter().all(|&i| i == u32::MAX), "top row is sky");
    // The `[[instance]]` entry is shape 0 (there are no `[[shape]]`s).
    for (i, s) in inst.iter().zip(shape.iter()) {
        assert_eq!(*i == u32::MAX, *s == u32::MAX);
        if *i != u32::MAX {
            assert_eq!(*s, 0);
        }
    }
}
