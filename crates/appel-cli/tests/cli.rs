//! The command line as a user meets it: renders, built-in scenes, and every kind of bad input, which
//! must exit non-zero with a message naming the file, line and column, and leave no output file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn appel(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_appel"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("appel runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

const CAMERA: &str = "[camera]\neye = [0.0, 1.0, 5.0]\nlook_at = [0.0, 1.0, 0.0]\n";

/// Writes `scene` to a file, renders it, and checks the failure: non-zero exit, each of `expected`
/// in the message, no panic, no output file.
fn assert_rejected(name: &str, scene: &str, expected: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join(name), scene).unwrap();
    let out = appel(&["render", name, "-o", "out.png", "--quiet"], dir.path());
    let err = stderr(&out);
    assert!(!out.status.success(), "{name} was accepted");
    assert_eq!(out.status.code(), Some(1), "{name}: {err}");
    assert!(!err.contains("panicked"), "{name} panicked: {err}");
    for e in expected {
        assert!(err.contains(e), "{name}: expected `{e}` in: {err}");
    }
    let leftovers: Vec<PathBuf> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap() != name)
        .collect();
    assert!(leftovers.is_empty(), "{name} left {leftovers:?}");
}

#[test]
fn toml_syntax_error_names_line_and_column() {
    assert_rejected(
        "s.toml",
        "[camera]\neye = [0.0, 1.0\nlook_at = [0,0,0]\n",
        &["s.toml:3:1"],
    );
}

#[test]
fn unknown_key_is_rejected_with_the_expected_keys() {
    assert_rejected(
        "k.toml",
        &format!("{CAMERA}focal = 3.0\n"),
        &["k.toml:4:1", "unknown field `focal`", "expected one of"],
    );
}

#[test]
fn wrong_type_is_rejected() {
    assert_rejected(
        "t.toml",
        &format!("{CAMERA}width = \"wide\"\n"),
        &["t.toml:4:9", "expected u32"],
    );
}

#[test]
fn missing_camera_is_rejected() {
    assert_rejected(
        "c.toml",
        "[render]\nmax_depth = 3\n",
        &["c.toml", "missing field `camera`"],
    );
}

#[test]
fn negative_radius_is_rejected_at_its_line() {
    let s = format!(
        "{CAMERA}\n[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = -1.0\n"
    );
    assert_rejected(
        "r.toml",
        &s,
        &["r.toml:8:10", "shape[0].radius", "positive"],
    );
}

#[test]
fn zero_and_parallel_up_are_rejected() {
    let base = "[camera]\neye = [0.0, 1.0, 5.0]\nlook_at = [0.0, 1.0, 0.0]\n";
    assert_rejected(
        "z.toml",
        &format!("{base}up = [0.0, 0.0, 0.0]\n"),
        &["z.toml:4", "non-zero"],
    );
    assert_rejected(
        "p.toml",
        &format!("{base}up = [0.0, 0.0, -2.0]\n"),
        &["p.toml:4", "parallel"],
    );
}

#[test]
fn fov_outside_the_open_interval_is_rejected() {
    for fov in ["0.0", "180.0", "-10.0", "500.0"] {
        assert_rejected(
            "f.toml",
            &format!("{CAMERA}fov = {fov}\n"),
            &["f.toml:4:7", "(0, 180)"],
        );
    }
}

#[test]
fn unknown_accel_and_integrator_are_rejected_with_the_choices() {
    assert_rejected(
        "a.toml",
        &format!("{CAMERA}[render]\naccel = \"rtree\"\n"),
        &["a.toml:5:9", "unknown accel `rtree`", "brute"],
    );
    assert_rejected(
        "i.toml",
        &format!("{CAMERA}[render]\nintegrator = \"photon\"\n"),
        &[
            "i.toml:5:14",
            "unknown integrator `photon`",
            "raycast, whitted, path, direct, volpath, aov, bdpt, ptracer, sppm",
        ],
    );
}

#[test]
fn bad_structure_parameters_are_rejected_at_their_line() {
    assert_rejected(
        "w.toml",
        &format!("{CAMERA}[render.bvh]\nwidth = 3\n"),
        &["w.toml:5:9", "render.bvh.width", "2, 4 or 8, got 3"],
    );
    assert_rejected(
        "s.toml",
        &format!("{CAMERA}[render.bvh]\nsplit = \"octant\"\n"),
        &["s.toml:5:9", "`sah`, `midpoint`, `median`"],
    );
    assert_rejected(
        "g.toml",
        &format!("{CAMERA}[render.grid]\ndensity = -1.0\n"),
        &["g.toml:5:11", "render.grid.density"],
    );
    assert_rejected(
        "k.toml",
        &format!("{CAMERA}[render.kdtree]\nempty_bonus = 2.0\n"),
        &["k.toml:5:15", "between 0 and 1"],
    );
    assert_rejected(
        "u.toml",
        &format!("{CAMERA}[render.bvh]\nleaves = 4\n"),
        &["u.toml:5:1", "unknown field `leaves`"],
    );
    assert_rejected(
        "o.toml",
        &format!("{CAMERA}[render.octree]\nmax_prims = 4\nmax_depth = 30\n"),
        &[
            "o.toml:6:13",
            "render.octree.max_depth",
            "between 0 and 24, got 30",
        ],
    );
    assert_rejected(
        "b.toml",
        &format!("{CAMERA}[render]\naccel = \"bsp\"\n[render.bsp]\nbins = 100\n"),
        &["b.toml:7:8", "render.bsp.bins", "between 0 and 64, got 100"],
    );
    assert_rejected(
        "c.toml",
        &format!("{CAMERA}[render.bsp]\nintersect_cost = -2.0\n"),
        &["c.toml:5:18", "render.bsp.intersect_cost", "positive"],
    );
    assert_rejected(
        "n.toml",
        &format!("{CAMERA}[render.octree]\nmax_leaf = 4\n"),
        &[
            "n.toml:5:1",
            "unknown field `max_leaf`",
            "expected `max_prims` or `max_depth`",
        ],
    );
    assert_rejected(
        "d.toml",
        &format!("{CAMERA}[render.kdtree]\nmax_depth = -3\n"),
        &["d.toml:5:13", "invalid value: integer `-3`"],
    );
    assert_rejected(
        "r.toml",
        &format!("{CAMERA}[render.brute]\nleaf = 1\n"),
        &["r.toml:5:1", "unknown field `leaf`"],
    );
}

#[test]
fn stats_report_the_structure_built_from_the_scene_tables() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "{CAMERA}[render]\naccel = \"bvh\"\n[render.bvh]\nwidth = 4\nsplit = \"median\"\n\n[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 1.0, 0.0]\nradius = 1.0\n"
    );
    std::fs::write(dir.path().join("s.toml"), scene).unwrap();
    let out = appel(
        &[
            "render", "s.toml", "-o", "s.png", "--quiet", "--stats", "--size", "16x12",
        ],
        dir.path(),
    );
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("accel bvh (4-wide, median splits): 1 primitives"),
        "{err}"
    );
    assert!(err.contains("nodes visited"), "{err}");
}

#[test]
fn unknown_material_is_rejected() {
    let s = format!("{CAMERA}[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"gold\"\n");
    assert_rejected("m.toml", &s, &["m.toml:8:12", "unknown material `gold`"]);
}

#[test]
fn absurd_resolution_is_rejected_before_allocating() {
    assert_rejected(
        "h.toml",
        &format!("{CAMERA}width = 1000000\nheight = 1000000\n"),
        &["h.toml:4:9", "width"],
    );
    assert_rejected(
        "g.toml",
        &format!("{CAMERA}width = 60000\nheight = 60000\n"),
        &["g.toml", "GB"],
    );
}

#[test]
fn non_finite_numbers_are_rejected() {
    assert_rejected(
        "n.toml",
        "[camera]\neye = [0.0, nan, 5.0]\nlook_at = [0.0, 1.0, 0.0]\n",
        &["n.toml:2:7", "finite"],
    );
    assert_rejected(
        "i.toml",
        &format!("{CAMERA}[[light]]\ntype = \"point\"\nposition = [inf, 0.0, 0.0]\n"),
        &["i.toml:6:12", "finite"],
    );
}

#[test]
fn json_scenes_use_the_same_schema_and_checks() {
    assert_rejected(
        "j.json",
        r#"{"camera": {"eye": [0, 1, 5], "look_at": [0, 1, 0], "foo": 1}}"#,
        &["j.json:1:", "unknown field `foo`"],
    );
    assert_rejected(
        "k.json",
        r#"{"camera": {"eye": [0, 1, 5], "look_at": [0, 1, 0], "fov": -3}}"#,
        &["k.json", "fov"],
    );
}

#[test]
fn missing_scene_and_bad_output_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        vec!["render", "nope.toml", "-o", "x.png"],
        vec!["render", "nope", "-o", "x.png"],
        vec!["render", "-o", "x.jpg"],
        vec!["render", "-o", "missing/x.png"],
        vec!["render", "--aov", "depth,foo", "-o", "x.exr"],
        vec!["render", "--aov", "depth", "-o", "x.png"],
        vec!["render", "--size", "10", "-o", "x.png"],
    ] {
        let out = appel(&args, dir.path());
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(
            stderr(&out).starts_with("error: "),
            "{args:?}: {}",
            stderr(&out)
        );
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn default_render_writes_the_whitted_png_and_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = appel(&["render", "-o", "w.png", "--size", "64x48"], dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let summary = String::from_utf8_lossy(&out.stdout);
    for word in [
        "load",
        "build",
        "render",
        "camera 3072",
        "shadow",
        "reflection",
        "refraction",
        "Mrays/s",
    ] {
        assert!(summary.contains(word), "summary lacks {word}: {summary}");
    }
    let png = std::fs::read(dir.path().join("w.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
}

/// A Mitsuba scene asking for the `aov` integrator around a path tracer.
const AOV_XML: &str = r#"<scene version="3.0.0">
    <integrator type="aov">
        <string name="aovs" value="dd.y:depth,nn:sh_normal"/>
        <integrator type="path" name="my_image">
            <integer name="max_depth" value="3"/>
        </integrator>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <transform name="to_world">
            <lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <sampler type="independent"><integer name="sample_count" value="2"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="33"/>
            <integer name="height" value="33"/>
        </film>
    </sensor>
    <shape type="sphere"/>
    <emitter type="point">
        <point name="position" value="0, 3, 5"/>
        <rgb name="intensity" value="20"/>
    </emitter>
</scene>
"#;

#[test]
fn mitsubas_aov_integrator_renders_through_the_cli() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("aov.xml"), AOV_XML).unwrap();
    let out = appel(&["render", "aov.xml", "-o", "a.exr", "--quiet"], dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let image = read_all_flat_layers_from_file(dir.path().join("a.exr")).unwrap();
    let layer = &image.layer_data[0];
    let channel = |n: &str| -> Vec<f32> {
        let c = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == n)
            .unwrap_or_else(|| panic!("no channel {n}"));
        let FlatSamples::F32(v) = &c.sample_data else {
            panic!("{n} must be float32")
        };
        v.clone()
    };
    let centre = 16 * 33 + 16;
    // The unit sphere's nearest point, 4 from the camera, facing it; Mitsuba's rays start at the
    // near clipping plane (0.01 by default), from which it measures the depth.
    assert!((channel("dd.y.T")[centre] - 3.99).abs() < 1e-4);
    assert!((channel("nn.Z")[centre] - 1.0).abs() < 1e-4);
    assert!(channel("nn.X")[centre].abs() < 1e-4);
    assert_eq!(channel("dd.y.T")[0], 0.0, "a corner sees nothing");
    // The path tracer's image, in R, G, B and again under its name.
    assert!(channel("R")[centre] > 0.0);
    assert_eq!(channel("R"), channel("my_image.R"));
    assert_eq!(channel("my_image.A")[centre], 1.0);
    assert_eq!(channel("my_image.A")[0], 0.0);

    // An AOV type Appel does not know is an error at the line of the list.
    let bad = AOV_XML.replace("nn:sh_normal", "nn:sh_normals");
    std::fs::write(dir.path().join("bad.xml"), bad).unwrap();
    let out = appel(&["render", "bad.xml", "-o", "b.exr", "--quiet"], dir.path());
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(err.contains("bad.xml:3:"), "{err}");
    assert!(err.contains("unknown AOV type `sh_normals`"), "{err}");
    assert!(!dir.path().join("b.exr").exists());
}

#[test]
fn exr_carries_the_named_aov_channels() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let out = appel(
        &[
            "render",
            "--size",
            "32x24",
            "--aov",
            "depth,normal,primid",
            "-o",
            "a.exr",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let image = read_all_flat_layers_from_file(dir.path().join("a.exr")).unwrap();
    let layer = &image.layer_data[0];
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    for n in [
        "R", "G", "B", "depth", "N.X", "N.Y", "N.Z", "shapeid", "primid",
    ] {
        assert!(
            names.contains(&n.to_string()),
            "no channel {n} in {names:?}"
        );
    }
    let channel = |n: &str| {
        &layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == n)
            .unwrap()
            .sample_data
    };
    let (FlatSamples::U32(ids), FlatSamples::F32(depth)) = (channel("primid"), channel("depth"))
    else {
        panic!("primid must be uint32 and depth float32");
    };
    // Top row is sky: a miss everywhere.
    assert!(ids[..32].iter().all(|&i| i == u32::MAX));
    assert!(depth[..32].iter().all(|d| d.is_infinite()));
    // Bottom row is floor: shape 0, primitive 0, finite depth.
    assert!(ids[32 * 23..].iter().all(|&i| i == 0));
    assert!(depth[32 * 23..].iter().all(|d| d.is_finite() && *d > 0.0));
}

#[test]
fn built_in_scenes_are_listed_and_written_as_valid_scene_files() {
    let dir = tempfile::tempdir().unwrap();
    let list = appel(&["scenes"], dir.path());
    let list = String::from_utf8_lossy(&list.stdout);
    for name in ["whitted", "mirror-room", "glass-block"] {
        assert!(list.contains(name));
        let text = appel(&["scenes", "--write", name], dir.path());
        assert!(text.status.success());
        let file = format!("{name}.toml");
        std::fs::write(dir.path().join(&file), &text.stdout).unwrap();
        let out = appel(
            &[
                "render",
                &file,
                "--size",
                "32x24",
                "-o",
                "x.png",
                "--threads",
                "1",
            ],
            dir.path(),
        );
        assert!(out.status.success(), "{name}: {}", stderr(&out));
    }
    assert!(!appel(&["scenes", "--write", "nope"], dir.path())
        .status
        .success());
}

#[test]
fn a_mesh_file_renders_framed_and_a_bad_one_is_rejected_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    // A unit square as an OBJ quad: framed automatically, the centre pixel sees it.
    std::fs::write(
        dir.path().join("square.obj"),
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
    )
    .unwrap();
    let out = appel(
        &[
            "render",
            "square.obj",
            "-o",
            "sq.png",
            "--size",
            "32x24",
            "--quiet",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let img = image::open(dir.path().join("sq.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (32, 24));
    let background = *img.get_pixel(0, 0);
    assert_ne!(
        *img.get_pixel(16, 12),
        background,
        "centre pixel shows the model"
    );
    assert_rejected(
        "bad.obj",
        "v 0 0 0\nv 1 0 0\nf 1 2 7\n",
        &["bad.obj:3:", "vertex index 7"],
    );
}

#[test]
fn inside_classifies_points_of_a_closed_mesh() {
    let dir = tempfile::tempdir().unwrap();
    // The cube [-1, 1]^3 as an OBJ of quads.
    let cube =
        "v -1 -1 -1\nv -1 -1 1\nv -1 1 -1\nv -1 1 1\nv 1 -1 -1\nv 1 -1 1\nv 1 1 -1\nv 1 1 1\n\
                f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n";
    std::fs::write(dir.path().join("cube.obj"), cube).unwrap();
    std::fs::write(
        dir.path().join("p.csv"),
        "0,0,0\n2,0,0\n0.5 -0.5 0.9\n0,0,-1.01\n",
    )
    .unwrap();
    let out = appel(&["inside", "cube.obj", "p.csv"], dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "inside\noutside\ninside\noutside\n"
    );
    let out = appel(&["inside", "cube.obj", "p.csv", "--json"], dir.path());
    assert_eq!(
        String::from_utf8_lossy(&out.stdout).trim(),
        "[true,false,true,false]"
    );
    std::fs::write(dir.path().join("bad.csv"), "0,0,0\n1,2\n").unwrap();
    let out = appel(&["inside", "cube.obj", "bad.csv"], dir.path());
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("bad.csv:2:"), "{}", stderr(&out));
}

#[test]
fn bench_json_reports_every_structure_with_the_documented_keys() {
    let dir = tempfile::tempdir().unwrap();
    let out = appel(
        &[
            "bench",
            "uniform",
            "--triangles",
            "2000",
            "--size",
            "32x24",
            "--accel",
            "brute,grid,kdtree,bvh",
            "--builds",
            "1",
            "--runs",
            "1",
            "--json",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows.len(), 4, "{text}");
    for (row, name) in rows.iter().zip(["brute", "grid", "kdtree", "bvh"]) {
        for key in [
            "\"accel\"",
            "\"triangles\":2000",
            "\"build_ms\"",
            "\"bytes\"",
            "\"primary_mrays\"",
            "\"incoherent_mrays\"",
            "\"threads\"",
        ] {
            assert!(row.contains(key), "{name}: no {key} in {row}");
        }
        assert!(row.contains(&format!("\"accel\":\"{name}\"")), "{row}");
    }
    // Brute force tests every primitive for every ray; the others far fewer.
    assert!(rows[0].contains("\"tests_per_ray\":2000.0"), "{}", rows[0]);
    let bad = appel(&["bench", "uniform", "--accel", "rtree"], dir.path());
    assert_eq!(bad.status.code(), Some(1));
    assert!(stderr(&bad).contains("unknown structure `rtree`"));
}

#[test]
fn bench_embree_row_measures_embree_on_the_same_rays() {
    let dir = tempfile::tempdir().unwrap();
    // Not teapot-in-stadium: there Embree's robust mode reports another primitive than Appel's
    // watertight BVH on a third of the rays (so did Appel before the pairing).
    let out = appel(
        &[
            "bench",
            "uniform",
            "--triangles",
            "5000",
            "--size",
            "64x48",
            "--accel",
            "bvh",
            "--builds",
            "1",
            "--runs",
            "1",
            "--embree",
            "--json",
        ],
        dir.path(),
    );
    if !out.status.success() && std::env::var_os("APPEL_REQUIRE_EMBREE").is_none() {
        assert!(
            stderr(&out).contains("cannot load Embree 3"),
            "{}",
            stderr(&out)
        );
        appel_testdata::skip(
            "bench_embree_row_measures_embree_on_the_same_rays",
            stderr(&out),
        );
        return;
    }
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    let rows: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    // Both pairings on the same rays: watertight beside Embree's robust mode, Moller-Trumbore
    // beside its default.
    assert_eq!(rows.len(), 4, "{text}");
    for (pair, (test, peer)) in rows
        .chunks(2)
        .zip([("watertight", "embree-robust"), ("moller", "embree")])
    {
        let (bvh, embree) = (&pair[0], &pair[1]);
        assert_eq!(
            (bvh["accel"].as_str(), bvh["triangle"].as_str()),
            (Some("bvh"), Some(test)),
            "{bvh}"
        );
        assert_eq!(
            (embree["accel"].as_str(), embree["triangle"].as_str()),
            (Some(peer), Some(test))
        );
        assert_eq!(embree["triangles"], bvh["triangles"]);
        assert_eq!(embree["rays_primary"], 64 * 48);
        for key in [
            "primary_mrays",
            "incoherent_mrays",
            "shadow_mrays",
            "path_mrays",
            "packet8_mrays",
        ] {
            assert!(embree[key].as_f64().unwrap() > 0.0, "{key}: {embree}");
        }
        assert!(embree["agreement"].as_f64().unwrap() > 0.999, "{embree}");
        assert!(embree["bytes"].as_u64().unwrap() > 5000 * 12, "{embree}");
        // The ratios are of the two rows' figures.
        let v = &bvh["vs_embree"];
        assert_eq!(v["peer"], peer);
        for (ratio, key) in [
            ("camera_1t", "primary_mrays_1t"),
            ("shadow", "shadow_mrays"),
            ("path_1t", "path_mrays_1t"),
            ("build", "build_ms"),
        ] {
            let want = bvh[key].as_f64().unwrap() / embree[key].as_f64().unwrap();
            let got = v[ratio].as_f64().unwrap();
            assert!((got - want).abs() <= 1e-9 * want, "{ratio}: {got} {want}");
        }
    }
    let one = appel(
        &[
            "bench",
            "uniform",
            "--triangles",
            "2000",
            "--size",
            "16x12",
            "--accel",
            "bvh",
            "--builds",
            "1",
            "--runs",
            "1",
            "--embree",
            "--triangle",
            "moller",
            "--json",
        ],
        dir.path(),
    );
    assert!(one.status.success(), "{}", stderr(&one));
    let text = String::from_utf8_lossy(&one.stdout);
    assert_eq!(text.lines().count(), 2, "{text}");
    assert!(text.contains("\"accel\":\"embree\""), "{text}");
    let bad = appel(&["bench", "uniform", "--triangle", "moeller"], dir.path());
    assert_eq!(bad.status.code(), Some(1));
    assert!(
        stderr(&bad).contains("--triangle: unknown triangle test `moeller`"),
        "{}",
        stderr(&bad)
    );
    let bad = appel(&["bench", "uniform", "--threads", "0"], dir.path());
    assert_eq!(bad.status.code(), Some(1));
    assert!(
        stderr(&bad).contains("--threads: expected 1 to"),
        "{}",
        stderr(&bad)
    );
}

#[test]
fn bench_scene_frames_reports_fps_and_rays_by_kind() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "bench",
        "--scene",
        "whitted",
        "--frames",
        "3",
        "--size",
        "32x24",
        "--threads",
        "1",
        "--json",
    ];
    let out = appel(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    let v: serde_json::Value = serde_json::from_str(text.trim()).expect("one JSON object");
    assert_eq!(v["scene"], "whitted");
    assert_eq!(
        (v["width"].as_u64(), v["height"].as_u64()),
        (Some(32), Some(24))
    );
    assert_eq!(
        (v["spp"].as_u64(), v["max_depth"].as_u64()),
        (Some(1), Some(5))
    );
    assert_eq!(
        (v["frames"].as_u64(), v["threads"].as_u64()),
        (Some(3), Some(1))
    );
    assert_eq!(v["camera_rays"].as_u64(), Some(32 * 24));
    let kinds = [
        "camera_rays",
        "shadow_rays",
        "reflection_rays",
        "refraction_rays",
    ];
    let sum: u64 = kinds.iter().map(|k| v[k].as_u64().unwrap()).sum();
    assert_eq!(v["rays_per_frame"].as_u64(), Some(sum));
    assert!(kinds.iter().all(|k| v[k].as_u64().unwrap() > 0), "{v}");
    let (fps, ms) = (
        v["fps"].as_f64().unwrap(),
        v["frame_ms_median"].as_f64().unwrap(),
    );
    assert!((fps * ms - 1000.0).abs() < 1e-6, "{v}");
    // A shallower recursion traces fewer secondary rays; a structure by name is honoured.
    let shallow = appel(
        &[
            "bench",
            "--scene",
            "whitted",
            "--frames",
            "1",
            "--size",
            "32x24",
            "--max-depth",
            "1",
            "--accel",
            "brute",
            "--json",
        ],
        dir.path(),
    );
    assert!(shallow.status.success(), "{}", stderr(&shallow));
    let s: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&shallow.stdout).trim()).unwrap();
    assert_eq!(s["accel"], "brute");
    assert!(s["reflection_rays"].as_u64() < v["reflection_rays"].as_u64());
    let bad = appel(
        &["bench", "--scene", "whitted", "--frames", "0"],
        dir.path(),
    );
    assert_eq!(bad.status.code(), Some(1));
    assert!(
        stderr(&bad).contains("--frames must be at least 1"),
        "{}",
        stderr(&bad)
    );
}

#[test]
fn bench_scene_reports_samples_per_second_for_a_path_traced_scene() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("path.xml"),
        r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="2"/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/></film>
    </sensor>
    <shape type="sphere"><bsdf type="diffuse"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><translate x="0" y="0" z="3"/></transform>
        <emitter type="area"><rgb name="radiance" value="5"/></emitter>
    </shape>
</scene>"#,
    )
    .unwrap();
    let args = [
        "bench",
        "--scene",
        "path.xml",
        "--spp",
        "4",
        "--frames",
        "2",
        "--threads",
        "1",
        "--json",
    ];
    let out = appel(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()).expect("one JSON object");
    assert_eq!(v["integrator"], "path");
    assert_eq!((v["spp"].as_u64(), v["runs"].as_u64()), (Some(4), Some(2)));
    assert_eq!(v["max_depth"].as_i64(), Some(3));
    // One ray per sample: the benchmark skips the AOVs and their pass of centre rays.
    assert_eq!(v["camera_rays"].as_u64(), Some(16 * 12 * 4));
    let ms = v["render_ms_median"].as_f64().unwrap();
    let sps = v["msamples_per_second"].as_f64().unwrap();
    assert!((sps * ms * 1e3 - 16.0 * 12.0 * 4.0).abs() < 1e-6, "{v}");
    for (bad, message) in [
        (vec!["--spp", "0"], "--spp must be at least 1"),
        (vec!["--max-depth", "-2"], "--max-depth: expected -1"),
        (vec!["--frames", "0"], "--frames must be at least 1"),
    ] {
        let mut args = vec!["bench", "--scene", "path.xml"];
        args.extend(bad);
        let out = appel(&args, dir.path());
        assert_eq!(out.status.code(), Some(1));
        assert!(stderr(&out).contains(message), "{}", stderr(&out));
    }
    let out = appel(&["bench", "--scene", "whitted", "--spp", "4"], dir.path());
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("--spp applies to the path and direct integrators"));
}

/// The Bitterli Cornell box in Mitsuba 3's XML, which declares `spp`, `resx`, `resy` and
/// `max_depth` as `<default>` parameters.
fn cornell_box_xml() -> PathBuf {
    appel_testdata::path("bitterli-scenes/cornell-box/mitsuba/scene_v3.xml")
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn define_sets_the_parameters_of_a_mitsuba_scene() {
    let scene = cornell_box_xml();
    let scene = scene.to_str().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "render",
        scene,
        "-D",
        "spp=2",
        "-D",
        "resx=24",
        "-D",
        "resy=16",
        "-D",
        "max_depth=3",
        "-o",
        "box.png",
        "--quiet",
    ];
    let out = appel(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let img = image::open(dir.path().join("box.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (24, 16));
    // The light lands on the walls: not a black image.
    assert!(img.pixels().any(|p| p.0.iter().any(|&c| c > 64)));

    let args = [
        "bench",
        "--scene",
        scene,
        "-D",
        "spp=1",
        "-D",
        "resx=16",
        "-D",
        "resy=8",
        "-D",
        "max_depth=2",
        "--frames",
        "1",
        "--threads",
        "1",
        "--json",
    ];
    let out = appel(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()).expect("one JSON object");
    assert_eq!(
        (v["width"].as_u64(), v["height"].as_u64()),
        (Some(16), Some(8)),
        "{v}"
    );
    assert_eq!(
        (v["spp"].as_u64(), v["max_depth"].as_i64()),
        (Some(1), Some(2))
    );
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn define_is_rejected_where_it_cannot_apply() {
    let scene = cornell_box_xml();
    let scene = scene.to_str().unwrap();
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), CAMERA).unwrap();
    for (args, message) in [
        (
            vec!["render", scene, "-D", "spp"],
            "-D: expected NAME=VALUE",
        ),
        (vec!["render", scene, "-D", "=4"], "-D: expected NAME=VALUE"),
        (
            vec!["render", "s.toml", "-D", "spp=4"],
            "`s.toml` is not one",
        ),
        (
            vec!["render", "whitted", "-D", "spp=4"],
            "`whitted` is not one",
        ),
        (
            vec!["bench", "--scene", "s.toml", "-D", "spp=4"],
            "`s.toml` is not one",
        ),
        // A value the file cannot use is reported where it is used.
        (vec!["render", scene, "-D", "spp=many"], "scene_v3.xml:"),
    ] {
        let mut args = args;
        if args[0] == "render" {
            args.extend(["-o", "out.png", "--quiet"]);
        }
        let out = appel(&args, dir.path());
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(message), "{args:?}: {}", stderr(&out));
        assert!(!dir.path().join("out.png").exists());
    }
}

#[test]
fn unknown_shape_type_is_rejected_with_the_choices() {
    let shapes =
        "`sphere`, `plane`, `triangle`, `implicit`, `torus`, `mesh`, `rectangle`, `cube`, `disk`";
    assert_rejected(
        "t.toml",
        &format!("{CAMERA}[[shape]]\ntype = \"sphre\"\ncenter = [0.0, 0.0, 0.0]\n"),
        &["t.toml:5:8", "unknown variant `sphre`", shapes],
    );
    assert_rejected(
        "t.json",
        r#"{"camera": {"eye": [0, 1, 5], "look_at": [0, 0, 0]},
"shape": [{"type": "sphere", "center": [0, 0, 0], "radius": 1},
          {"type": "sphre", "center": [0, 0, 0]}]}"#,
        &["t.json:3:", "unknown variant `sphre`", shapes],
    );
    // Keys that belong to another kind of shape are named, with the keys this kind takes.
    assert_rejected(
        "k.toml",
        &format!(
            "{CAMERA}[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nsize = [1.0, 2.0]\n"
        ),
        &["k.toml:", "unknown field `size`", "`center`, `radius`"],
    );
    assert_rejected(
        "e.toml",
        &format!(
            "{CAMERA}[[shape]]\ntype = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nemitter = {{ radiance = 1.0 }}\n"
        ),
        &["e.toml:", "unknown field `emitter`", "`point`, `normal`"],
    );
}

/// Writes `files`, renders `scene` to `out.exr`, and checks the failure as `assert_rejected` does.
fn assert_files_rejected(files: &[(&str, &[u8])], scene: &str, expected: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    let out = appel(&["render", scene, "-o", "out.exr", "--quiet"], dir.path());
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{scene}: {err}");
    assert!(!err.contains("panicked"), "{scene} panicked: {err}");
    for e in expected {
        assert!(err.contains(e), "{scene}: expected `{e}` in: {err}");
    }
    assert!(!dir.path().join("out.exr").exists(), "{scene} wrote output");
}

/// Malformed files of every reader, end to end: exit status 1, the file and line (or byte) in the
/// message, no output file.
#[test]
fn malformed_files_of_every_reader_are_rejected_without_output() {
    // Mitsuba XML with a tag left open.
    assert_files_rejected(
        &[(
            "s.xml",
            b"<scene version=\"3.0.0\">\n  <sensor type=\"perspective\">\n  <shape type=\"sphere\"/>\n</scene>\n",
        )],
        "s.xml",
        &["s.xml:4:", "malformed XML"],
    );
    // JSON scene: validation errors are placed at the value's line and column.
    assert_files_rejected(
        &[(
            "s.json",
            b"{\"camera\": {\"eye\": [0, 1, 5], \"look_at\": [0, 1, 0]},\n \"shape\": [{\"type\": \"sphere\",\n  \"center\": [0, 0, 0], \"radius\": -1}]}\n",
        )],
        "s.json",
        &["s.json:3:34:", "radius"],
    );
    // A scene file that is not UTF-8: the first bad byte's line and column.
    assert_files_rejected(
        &[("s.toml", b"[camera]\neye = [0.0, \xff]\n")],
        "s.toml",
        &["s.toml:2:13:"],
    );
    // Binary PLY cut short: the byte where the data ends.
    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
    ply.extend([0u8; 20]);
    assert_files_rejected(&[("cut.ply", &ply)], "cut.ply", &["cut.ply: at byte"]);
    // A PLY header without coordinates: the element's line.
    assert_files_rejected(
        &[(
            "nox.ply",
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nproperty float z\nend_header\n0 0\n",
        )],
        "nox.ply",
        &["nox.ply:3:", "no `x` property"],
    );
    // glTF that is not JSON, and a zip archive that is not one.
    assert_files_rejected(
        &[("m.gltf", b"{\"asset\": ")],
        "m.gltf",
        &["m.gltf", "invalid glTF"],
    );
    assert_files_rejected(
        &[("a.zip", b"PK\x03\x04 not really")],
        "a.zip",
        &["a.zip", "zip"],
    );
    // A scene whose texture is a truncated PNG: the error names the image.
    let scene = format!(
        "{CAMERA}[materials.t]\ntype = \"diffuse\"\nreflectance = {{ type = \"bitmap\", file = \"t.png\" }}\n[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"t\"\n"
    );
    assert_files_rejected(
        &[
            ("s.toml", scene.as_bytes()),
            ("t.png", b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0"),
        ],
        "s.toml",
        &["t.png", "not a readable Png image"],
    );
}

/// A reader that closes the pipe early (`appel bench ... | head -1`) ends Appel quietly, as it
/// ends Unix tools (SIGPIPE), instead of a panic about printing to stdout.
#[cfg(unix)]
#[test]
fn a_closed_stdout_ends_appel_without_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_appel"))
        .args([
            "bench",
            "uniform",
            "--triangles",
            "20000",
            "--size",
            "64x48",
        ])
        .args(["--runs", "1", "--builds", "1"])
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("appel runs");
    // Closed before the benchmark has built anything, so its first line meets no reader.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = stderr(&out);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(
        out.status.signal(),
        Some(libc::SIGPIPE),
        "{:?} {err}",
        out.status
    );
}

/// A triangle (data URI) seen by one camera: `appel render x.gltf` reads it as a scene.
const GLTF_SCENE: &str = r#"{
  "asset": {"version": "2.0"},
  "buffers": [{"uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA", "byteLength": 36}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.01}}],
  "scene": 0,
  "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.3, 0.3, 2]}]
}
"#;

#[test]
fn a_gltf_file_renders_as_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tri.gltf"), GLTF_SCENE).unwrap();
    let out = appel(
        &[
            "render", "tri.gltf", "-o", "tri.png", "--size", "12x8", "--spp", "1",
        ],
        dir.path(),
    );
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("tri.gltf: the file has no lights"), "{err}");
    assert!(dir.path().join("tri.png").is_file());
    // A reference out of range is an error at its line.
    assert_rejected(
        "bad.gltf",
        &GLTF_SCENE.replace(r#"{"mesh": 0}, {"camera""#, r#"{"mesh": 4}, {"camera""#),
        &["bad.gltf:10: invalid glTF: `nodes[0].mesh`: index out of bounds"],
    );
}

/// A scene with a medium rendered by an integrator that traces none renders, with a warning
/// naming the integrator that would show the medium; `volpath` gives no such warning.
#[test]
fn media_under_an_integrator_that_ignores_them_are_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "{CAMERA}medium = \"fog\"\n\n[render]\nintegrator = \"path\"\nspp = 1\n\n\
         [media.fog]\ntype = \"homogeneous\"\nsigma_t = 0.5\nalbedo = 0.5\n"
    );
    std::fs::write(dir.path().join("fog.toml"), scene).unwrap();
    let render = |integrator: &str| {
        let out = appel(
            &[
                "render",
                "fog.toml",
                "-o",
                "out.png",
                "--size",
                "8x8",
                "--integrator",
                integrator,
            ],
            dir.path(),
        );
        assert!(out.status.success(), "{}", stderr(&out));
        stderr(&out)
    };
    let path = render("path");
    assert!(
        path.contains("participating media, which `path` does not trace")
            && path.contains("`volpath`"),
        "{path}"
    );
    assert!(!render("volpath").contains("participating media"));
}
