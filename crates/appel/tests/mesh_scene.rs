//! `type = "mesh"` shapes in scene files, and framing a bare model.

use appel::math::Vec3;
use appel::output::write_ply;
use appel::render::{render, RenderOptions, MISS_ID};
use appel::scene::{frame_model, model_description, Scene};
use std::path::{Path, PathBuf};

fn write_scene(dir: &Path, shapes: &str) -> PathBuf {
    let p = dir.join("scene.toml");
    let text = format!(
        "[camera]\neye = [0.0, 0.0, 10.0]\nlook_at = [0.0, 0.0, 0.0]\nwidth = 8\nheight = 8\n\n[materials.red]\ncolor = [1.0, 0.0, 0.0]\n\n{shapes}"
    );
    std::fs::write(&p, text).unwrap();
    p
}

fn unit_triangle_ply(dir: &Path) {
    let mesh = appel::geometry::TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        indices: vec![[0, 1, 2]],
        normals: None,
        uvs: None,
    };
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    write_ply(&dir.join("meshes/tri.ply"), &[(0, &mesh)]).unwrap();
}

#[test]
fn transform_applies_scale_then_rotate_then_translate() {
    let dir = tempfile::tempdir().unwrap();
    unit_triangle_ply(dir.path());
    let p = write_scene(
        dir.path(),
        "[[shape]]\ntype = \"mesh\"\nfile = \"meshes/tri.ply\"\nmaterial = \"red\"\ntransform = { translate = [1.0, 0.0, 0.0], rotate = { axis = [0.0, 0.0, 1.0], degrees = 90.0 }, scale = [2.0, 3.0, 1.0] }\n",
    );
    let loaded = appel::format::load(&p, &Default::default()).unwrap();
    let scene = Scene::new(&loaded.description, &loaded.base_dir).unwrap();
    let v = scene.geometry.meshes[0].vertices(0);
    // (1,0,0) -> scale (2,0,0) -> rotate (0,2,0) -> translate (1,2,0); (0,1,0) -> (0,3,0) -> (-3,0,0) -> (-2,0,0).
    assert!((v[1] - Vec3::new(1.0, 2.0, 0.0)).length() < 1e-6, "{v:?}");
    assert!((v[2] - Vec3::new(-2.0, 0.0, 0.0)).length() < 1e-6, "{v:?}");
    assert_eq!(v[0], Vec3::new(1.0, 0.0, 0.0));
    // The shape's material wins: materials are [default, red].
    assert_eq!(scene.geometry.shapes[0].material, 1);
}

#[test]
fn scaled_scene_scales_mesh_transforms() {
    let dir = tempfile::tempdir().unwrap();
    unit_triangle_ply(dir.path());
    let p = write_scene(
        dir.path(),
        "[[shape]]\ntype = \"mesh\"\nfile = \"meshes/tri.ply\"\ntransform = { translate = [1.0, 0.0, 0.0], scale = 2.0 }\n",
    );
    let loaded = appel::format::load(&p, &Default::default()).unwrap();
    let scaled = loaded.description.scaled(10.0);
    let scene = Scene::new(&scaled, &loaded.base_dir).unwrap();
    assert_eq!(
        scene.geometry.meshes[0].vertices(0)[1],
        Vec3::new(30.0, 0.0, 0.0)
    );
}

#[test]
fn missing_mesh_file_is_reported_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = write_scene(
        dir.path(),
        "[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n\n[[shape]]\ntype = \"mesh\"\nfile = \"nope.ply\"\n",
    );
    let e = appel::format::load(&p, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("scene.toml:17:8:"), "{e}");
    assert!(
        e.contains("shape[1].file: the mesh file") && e.contains("nope.ply` does not exist"),
        "{e}"
    );
}

#[test]
fn mesh_keys_are_checked_per_type() {
    let dir = tempfile::tempdir().unwrap();
    unit_triangle_ply(dir.path());
    let cases = [
        ("[[shape]]\ntype = \"mesh\"\n", "missing field `file`"),
        ("[[shape]]\ntype = \"mesh\"\nfile = \"meshes/tri.ply\"\nradius = 1.0\n", "unknown field `radius`"),
        ("[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nfile = \"meshes/tri.ply\"\n", "unknown field `file`"),
        ("[[shape]]\ntype = \"mesh\"\nfile = \"meshes/tri.ply\"\ntransform = { scale = 0.0 }\n", "`scale` must not be zero"),
        ("[[shape]]\ntype = \"mesh\"\nfile = \"meshes/tri.ply\"\ntransform = { rotate = { axis = [0.0, 0.0, 0.0], degrees = 3.0 } }\n", "`axis` must be a non-zero vector"),
        ("[[shape]]\ntype = \"mesh\"\nfile = \"meshes/tri.ply\"\ntransform = { shear = 1.0 }\n", "unknown field `shear`"),
    ];
    for (shapes, want) in cases {
        let p = write_scene(dir.path(), shapes);
        let e = appel::format::load(&p, &Default::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(want) && e.contains("scene.toml:"),
            "{e}\n  wanted: {want}"
        );
    }
}

#[test]
fn bad_mesh_file_error_names_the_mesh_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    let p = write_scene(
        dir.path(),
        "[[shape]]\ntype = \"mesh\"\nfile = \"bad.obj\"\n",
    );
    let loaded = appel::format::load(&p, &Default::default()).unwrap();
    let e = Scene::new(&loaded.description, &loaded.base_dir)
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.obj:2: vertex index 2"), "{e}");
}

/// The bunny, framed automatically, fills a good part of a small image and covers its centre.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn framed_bunny_is_in_view() {
    let p = appel_testdata::path("common-3d-test-models/stanford-bunny.obj.gz");
    let mut d = model_description("stanford-bunny.obj.gz");
    d.camera.width = 64;
    d.camera.height = 48;
    d.render.integrator = appel::scene::IntegratorKind::Raycast;
    let mut scene = Scene::new(&d, p.parent().unwrap()).unwrap();
    assert!(scene.geometry.triangle_count() > 60_000);
    let framed = frame_model(&d, scene.geometry.bounds());
    scene.set_view(&framed).unwrap();
    let (film, _) = render(&scene, &RenderOptions::default()).unwrap();
    let hits = film.shape_id.iter().filter(|&&s| s != MISS_ID).count();
    let fraction = hits as f64 / film.shape_id.len() as f64;
    // The box is framed tightly; the bunny fills about a sixth of it seen on the diagonal.
    assert!(fraction > 0.1 && fraction < 0.9, "{fraction}");
    assert_ne!(film.shape_id[film.index(32, 24)], MISS_ID);
    // Nothing is cut off: the border rows and columns see only background.
    for x in 0..64 {
        assert_eq!(film.shape_id[film.index(x, 0)], MISS_ID);
        assert_eq!(film.shape_id[film.index(x, 47)], MISS_ID);
    }
}
