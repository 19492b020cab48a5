//! `shapeid` is the `[[shape]]`'s index in the scene file and `primid` the triangle's index in the mesh
//! file, even when a mesh file with several materials becomes several surfaces inside Appel.

use appel::description::description_from_str;
use appel::description::parse::Syntax;
use appel::render::{render, RenderOptions, MISS_ID};
use appel::scene::Scene;

#[test]
fn multi_material_obj_reports_scene_shape_and_file_triangle() {
    let dir = tempfile::tempdir().unwrap();
    // Three unit squares side by side along x (two triangles each), materials interleaved A, B, A,
    // so the reader's per-material parts regroup them: file triangles 0,1 (A), 2,3 (B), 4,5 (A).
    std::fs::write(
        dir.path().join("m.mtl"),
        "newmtl A\nKd 1 0 0\nnewmtl B\nKd 0 0 1\n",
    )
    .unwrap();
    let mut obj = String::from("mtllib m.mtl\n");
    for i in 0..3 {
        let x = i as f32 * 1.0;
        obj += &format!(
            "v {x} 0 0\nv {} 0 0\nv {} 1 0\nv {x} 1 0\n",
            x + 1.0,
            x + 1.0
        );
    }
    for (i, m) in ["A", "B", "A"].iter().enumerate() {
        let b = 4 * i + 1;
        obj += &format!(
            "usemtl {m}\nf {} {} {}\nf {} {} {}\n",
            b,
            b + 1,
            b + 2,
            b,
            b + 2,
            b + 3
        );
    }
    std::fs::write(dir.path().join("strip.obj"), obj).unwrap();
    let scene_text = r#"
        [camera]
        eye = [1.5, 0.5, 10.0]
        look_at = [1.5, 0.5, 0.0]
        fov = 20.0
        width = 300
        height = 100

        [[shape]]
        type = "sphere"
        center = [100.0, 0.0, 0.0]
        radius = 1.0

        [[shape]]
        type = "mesh"
        file = "strip.obj"
    "#;
    let path = dir.path().join("s.toml");
    let d = description_from_str(scene_text, Syntax::Toml, &path).unwrap();
    let scene = Scene::new(&d, dir.path()).unwrap();
    assert!(
        scene.geometry.shapes.len() >= 3,
        "the OBJ should load as two parts"
    );
    let (film, _) = render(&scene, &RenderOptions::default()).unwrap();
    // Find, for each file triangle, a pixel whose camera ray hits inside it (centre of the triangle's
    // projection: the squares span x in [0, 3], y in [0, 1]).
    let mut seen = [false; 6];
    for y in 0..film.height {
        for x in 0..film.width {
            let i = film.index(x, y);
            if film.shape_id[i] == MISS_ID {
                continue;
            }
            assert_eq!(film.shape_id[i], 1, "the mesh is the second [[shape]]");
            let ray = scene.camera.pixel_ray(x, y);
            let p = ray.at(film.depth[i]);
            let square = (p.x.floor() as i32).clamp(0, 2) as u32;
            let (fx, fy) = (p.x - square as f32, p.y);
            // Triangle (b, b+1, b+2) is below the diagonal fy = fx, (b, b+2, b+3) above it.
            if (fy - fx).abs() < 0.05 || !(0.02..=0.98).contains(&fx) {
                continue;
            }
            let expected = 2 * square + if fy < fx { 0 } else { 1 };
            assert_eq!(film.prim_id[i], expected, "pixel ({x}, {y}) at {p}");
            seen[expected as usize] = true;
        }
    }
    assert!(seen.iter().all(|&s| s), "{seen:?}");
}
