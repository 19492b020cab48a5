//! Meshes without vertex normals: Mitsuba XML `obj` and `ply` shapes get smooth ones, as Mitsuba 3
//! computes them (unless `face_normals`); pbrt's `plymesh` and Appel's own mesh shapes shade with
//! the triangles' normals unless `smooth_normals = true` asks otherwise.
//!
//! The mesh is a UV sphere of radius 2 around (1, 0, 0), written without normals: smooth normals
//! must be close to the radial direction, everywhere on the surface, and much closer than the
//! triangles' own normals.

use appel::accel::TraversalStats;
use appel::geometry::TriangleMesh;
use appel::math::Vec3;
use appel::scene::Scene;
use std::path::{Path, PathBuf};

const CENTRE: Vec3 = Vec3::new(1.0, 0.0, 0.0);
const RADIUS: f32 = 2.0;

/// A UV sphere: `rings` bands of latitude, `segments` of longitude, triangles wound outward.
fn uv_sphere(rings: u32, segments: u32) -> TriangleMesh {
    use std::f32::consts::PI;
    let mut positions = vec![CENTRE + RADIUS * Vec3::Z];
    for r in 1..rings {
        let theta = PI * r as f32 / rings as f32;
        for s in 0..segments {
            let phi = 2.0 * PI * s as f32 / segments as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            positions.push(CENTRE + RADIUS * d);
        }
    }
    positions.push(CENTRE - RADIUS * Vec3::Z);
    let south = positions.len() as u32 - 1;
    let ring = |r: u32, s: u32| 1 + (r - 1) * segments + s % segments;
    let mut indices = vec![];
    for s in 0..segments {
        indices.push([0, ring(1, s), ring(1, s + 1)]);
        indices.push([south, ring(rings - 1, s + 1), ring(rings - 1, s)]);
        for r in 1..rings - 1 {
            let (a, b) = (ring(r, s), ring(r, s + 1));
            let (c, d) = (ring(r + 1, s), ring(r + 1, s + 1));
            indices.push([a, c, d]);
            indices.push([a, d, b]);
        }
    }
    TriangleMesh {
        positions,
        indices,
        normals: None,
        uvs: None,
    }
}

fn write_obj(path: &Path, mesh: &TriangleMesh) {
    let mut text = String::new();
    for p in &mesh.positions {
        text += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for t in &mesh.indices {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(path, text).unwrap();
}

/// A folder holding the sphere as `sphere.obj` and `sphere.ply`, and `scene_file` with `text`.
fn scene_with(scene_file: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let mesh = uv_sphere(24, 48);
    write_obj(&dir.path().join("sphere.obj"), &mesh);
    appel::output::write_ply(&dir.path().join("sphere.ply"), &[(0, &mesh)]).unwrap();
    let path = dir.path().join(scene_file);
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn load(path: &Path) -> Scene {
    let loaded = appel::format::load(path, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    Scene::new(&loaded.description, &loaded.base_dir).unwrap_or_else(|e| panic!("{e}"))
}

/// The largest angle (degrees) between the shading normal and the radial direction over hits on
/// a grid of rays at the sphere from eight directions, and the same for the geometric normal.
fn worst_normal_angles(scene: &Scene) -> (f32, f32) {
    let mut stats = TraversalStats::default();
    let angle = |a: Vec3, b: Vec3| a.dot(b).clamp(-1.0, 1.0).acos().to_degrees();
    let (mut shading, mut geometric, mut hits) = (0.0f32, 0.0f32, 0);
    for k in 0..8 {
        let phi = k as f32 * 0.8;
        let dir = Vec3::new(phi.cos(), phi.sin(), 0.3 * (k as f32 - 3.5)).normalize();
        let (u, v) = appel::math::orthonormal_basis(dir);
        for i in 0..21 {
            for j in 0..21 {
                let offset = u * (i as f32 - 10.0) * 0.18 + v * (j as f32 - 10.0) * 0.18;
                let ray = appel::math::Ray::new(CENTRE - 10.0 * dir + offset, dir);
                let Some(hit) = scene.intersect(&ray, f32::INFINITY, &mut stats) else {
                    continue;
                };
                let si = scene.geometry.interaction_with(&ray, &hit, false);
                let radial = (si.p - CENTRE).normalize();
                shading = shading.max(angle(si.ns, radial));
                geometric = geometric.max(angle(si.n, radial));
                hits += 1;
            }
        }
    }
    assert!(hits > 8 * 200, "{hits} hits");
    (shading, geometric)
}

const XML_HEAD: &str = r#"<scene version="3.0.0">
  <sensor type="perspective">
    <transform name="to_world"><lookat origin="1, 0, 10" target="1, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
"#;

/// Smooth normals are within a degree of the radial direction (the 48 x 24 sphere's facets are
/// 7.5 degrees wide, so its triangles' own normals are off by several degrees).
fn assert_smooth(scene: &Scene, what: &str) {
    let (shading, geometric) = worst_normal_angles(scene);
    eprintln!("{what}: worst shading normal {shading} degrees, geometric {geometric}");
    assert!(shading < 1.0, "{what}: {shading}");
    assert!(geometric > 3.0, "{what}: {geometric}");
}

fn assert_flat(scene: &Scene, what: &str) {
    assert!(
        scene.geometry.meshes.iter().all(|m| m.normals.is_none()),
        "{what}"
    );
    let (shading, geometric) = worst_normal_angles(scene);
    assert_eq!(shading, geometric, "{what}");
}

#[test]
fn mitsuba_obj_and_ply_without_normals_get_smooth_ones() {
    for (file, kind) in [("sphere.obj", "obj"), ("sphere.ply", "ply")] {
        let xml = format!(
            "{XML_HEAD}  <shape type=\"{kind}\"><string name=\"filename\" value=\"{file}\"/></shape>\n</scene>\n"
        );
        let (_dir, path) = scene_with("scene.xml", &xml);
        assert_smooth(&load(&path), kind);
    }
}

/// Through a shapegroup the mesh is an instance's prototype: it gets its normals too.
#[test]
fn mitsuba_meshes_in_shapegroups_get_smooth_normals() {
    let xml = format!(
        "{XML_HEAD}  <shape type=\"shapegroup\" id=\"g\">\n    <shape type=\"ply\"><string name=\"filename\" value=\"sphere.ply\"/></shape>\n  </shape>\n  <shape type=\"instance\"><ref id=\"g\"/></shape>\n</scene>\n"
    );
    let (_dir, path) = scene_with("scene.xml", &xml);
    let scene = load(&path);
    assert_eq!(scene.geometry.instances.len(), 1);
    assert_smooth(&scene, "shapegroup");
}

#[test]
fn mitsuba_face_normals_keeps_the_facets() {
    let xml = format!(
        "{XML_HEAD}  <shape type=\"obj\"><string name=\"filename\" value=\"sphere.obj\"/><boolean name=\"face_normals\" value=\"true\"/></shape>\n</scene>\n"
    );
    let (_dir, path) = scene_with("scene.xml", &xml);
    assert_flat(&load(&path), "face_normals");
}

#[test]
fn pbrt_plymesh_without_normals_stays_faceted() {
    let pbrt = "LookAt 1 0 10  1 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n\
                Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n\
                WorldBegin\nShape \"plymesh\" \"string filename\" \"sphere.ply\"\n";
    let (_dir, path) = scene_with("scene.pbrt", pbrt);
    assert_flat(&load(&path), "pbrt plymesh");
}

const TOML_HEAD: &str =
    "[camera]\neye = [1.0, 0.0, 10.0]\nlook_at = [1.0, 0.0, 0.0]\nwidth = 8\nheight = 8\n\n";

#[test]
fn appel_mesh_shapes_are_faceted_unless_smooth_normals_asks() {
    let (_dir, path) = scene_with(
        "scene.toml",
        &format!("{TOML_HEAD}[[shape]]\ntype = \"mesh\"\nfile = \"sphere.obj\"\n"),
    );
    assert_flat(&load(&path), "mesh shape");
    let (_dir, path) = scene_with(
        "scene.toml",
        &format!(
            "{TOML_HEAD}[[shape]]\ntype = \"mesh\"\nfile = \"sphere.ply\"\nsmooth_normals = true\n"
        ),
    );
    assert_smooth(&load(&path), "smooth_normals");
    // Both at once is a contradiction, reported at its line.
    let (_dir, path) = scene_with(
        "scene.toml",
        &format!(
            "{TOML_HEAD}[[shape]]\ntype = \"mesh\"\nfile = \"sphere.ply\"\nsmooth_normals = true\nface_normals = true\n"
        ),
    );
    let Err(e) = appel::format::load(&path, &Default::default()) else {
        panic!("smooth_normals with face_normals accepted");
    };
    let e = e.to_string();
    assert!(
        e.contains("scene.toml:") && e.contains("smooth_normals"),
        "{e}"
    );
}

/// Mitsuba's own `sphere.ply` (no normals, 422 vertices) in the shared data: its smooth normals
/// are close to radial as well, much closer than its facets.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn mitsuba_s_shared_sphere_ply_gets_radial_normals() {
    let ply = appel_testdata::path("mitsuba-data/common/meshes/sphere.ply");
    let dir = tempfile::tempdir().unwrap();
    let xml = format!(
        "{XML_HEAD}  <shape type=\"ply\"><string name=\"filename\" value=\"{}\"/></shape>\n</scene>\n",
        ply.display()
    );
    let path = dir.path().join("scene.xml");
    std::fs::write(&path, xml).unwrap();
    let scene = load(&path);
    let mesh = &scene.geometry.meshes[0];
    let centre = mesh.bounds().center();
    let normals = mesh.normals.as_ref().expect("computed normals");
    let worst = mesh
        .positions
        .iter()
        .zip(normals)
        .map(|(p, n)| {
            n.dot((*p - centre).normalize())
                .clamp(-1.0, 1.0)
                .acos()
                .to_degrees()
        })
        .fold(0.0f32, f32::max);
    let facets = mesh
        .indices
        .iter()
        .flat_map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let n = (b - a).cross(c - a).normalize();
            [a, b, c].map(|p| {
                n.dot((p - centre).normalize())
                    .clamp(-1.0, 1.0)
                    .acos()
                    .to_degrees()
            })
        })
        .fold(0.0f32, f32::max);
    eprintln!(
        "shared sphere.ply: worst vertex normal {worst} degrees from radial, worst facet {facets}"
    );
    assert!(worst < facets / 3.0, "{worst} against {facets}");
}
