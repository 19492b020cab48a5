//! OBJ and glTF readers on small inline files and on the shared models.

use appel::description::loaded_mesh::LoadedMesh;
use appel::io::gltf::parse_gltf_with;
use appel::io::load_mesh;
use appel::io::obj::{parse_obj, triangulate, MtlSource, NoMtl};
use appel::math::{Vec2, Vec3};
use std::path::{Path, PathBuf};

fn obj(text: &str) -> appel::Result<LoadedMesh> {
    parse_obj(text.as_bytes(), Path::new("t.obj"), &NoMtl)
}

fn area(a: Vec2, b: Vec2, c: Vec2) -> f32 {
    0.5 * (b - a).perp_dot(c - a)
}

#[test]
fn quads_are_split_and_attributes_follow_the_corners() {
    let m = obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n").unwrap();
    let mesh = &m.parts[0].mesh;
    assert_eq!(mesh.triangle_count(), 2);
    assert_eq!(mesh.positions.len(), 4);
    // `vt 1 1` with v flipped to Appel's (and Mitsuba's) top-row origin.
    assert_eq!(mesh.uvs.as_ref().unwrap()[2], Vec2::new(1.0, 0.0));
    assert_eq!(mesh.normals.as_ref().unwrap()[3], Vec3::Z);
    // Both triangles keep the quad's counter-clockwise winding (normal +z).
    for t in 0..2 {
        let [a, b, c] = mesh.vertices(t);
        assert!((b - a).cross(c - a).z > 0.0);
    }
}

#[test]
fn concave_polygon_is_ear_clipped_inside_itself() {
    // An arrow-head: the fan from vertex 0 would cover the notch at vertex 2.
    let pts = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 1.0, 0.0),
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::new(2.0, -1.0, 0.0),
    ]
    .map(|p| Vec3::new(p.x, p.z, p.y)); // in the xz plane, to exercise the projection
    let mut tris = vec![];
    triangulate(&pts, &mut tris);
    assert_eq!(tris.len(), 2);
    let flat: Vec<Vec2> = pts.iter().map(|p| Vec2::new(p.x, p.z)).collect();
    let polygon_area: f32 = (0..4)
        .map(|i| 0.5 * flat[i].perp_dot(flat[(i + 1) % 4]))
        .sum();
    let mut total = 0.0;
    for t in &tris {
        let a = area(flat[t[0]], flat[t[1]], flat[t[2]]);
        // Same orientation as the polygon: no triangle folds outside.
        assert!(a * polygon_area > 0.0, "{t:?}");
        total += a;
    }
    assert!(
        (total - polygon_area).abs() < 1e-6,
        "{total} vs {polygon_area}"
    );
    // The notch vertex 2 is reflex: it may not be the tip of an ear.
    assert!(!tris.iter().any(|t| t[1] == 2 && t[0] == 1 && t[2] == 3));
}

#[test]
fn negative_indices_count_back_from_the_last_vertex() {
    let a = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf 1 2 -1\n").unwrap();
    let mesh = &a.parts[0].mesh;
    assert_eq!(mesh.vertices(0), [Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!(mesh.vertices(1)[2], Vec3::splat(5.0));
}

#[test]
fn groups_do_not_split_and_materials_do_in_file_order() {
    struct OneMtl;
    impl MtlSource for OneMtl {
        fn read(&self, _: &Path, name: &str) -> Option<(PathBuf, Vec<u8>)> {
            (name == "m.mtl").then(|| {
                (
                    PathBuf::from("m.mtl"),
                    b"newmtl red\nKd 1 0 0\nKs 0.5 0.5 0.5\nNs 20\nNi 1.3\nd 0.75\nnewmtl blue\nKd 0 0 1\n"
                        .to_vec(),
                )
            })
        }
    }
    let text = "mtllib m.mtl\nmtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng first\nusemtl red\nf 1 2 3\no second\nusemtl blue\nf 2 4 3\ng third\nusemtl red\nf 3 2 1\n";
    let m = parse_obj(text.as_bytes(), Path::new("t.obj"), &OneMtl).unwrap();
    assert_eq!(m.parts.len(), 2);
    assert_eq!(m.materials.len(), 2);
    let red = &m.materials[m.parts[0].material.unwrap() as usize];
    assert_eq!(red.name, "red");
    assert_eq!(red.diffuse, [1.0, 0.0, 0.0]);
    assert_eq!(red.specular, [0.5; 3]);
    assert_eq!((red.shininess, red.ior, red.opacity), (20.0, 1.3, 0.75));
    // The red part holds faces 0 and 2 of the file, in that order: primid 1 is the file's third face.
    let red_mesh = &m.parts[0].mesh;
    assert_eq!(red_mesh.triangle_count(), 2);
    assert_eq!(red_mesh.vertices(1), [Vec3::Y, Vec3::X, Vec3::ZERO]);
    assert_eq!(
        m.materials[m.parts[1].material.unwrap() as usize].name,
        "blue"
    );
}

#[test]
fn obj_errors_name_the_line() {
    let cases = [
        (
            "v 0 0 0\nv 1 0 0\nf 1 2 3\n",
            "t.obj:3: vertex index 3 in `3` is out of range",
        ),
        ("v 0 0 0\nf 0 1 1\n", "t.obj:2: vertex index 0"),
        ("v 0 0\n", "t.obj:1: `v` needs at least 3 numbers"),
        (
            "v 0 0 nan\n",
            "t.obj:1: `v` has a value that is not a finite number",
        ),
        (
            "v 0 0 0\nf 1 1\n",
            "t.obj:2: a face needs at least 3 vertices",
        ),
        (
            "v 0 0 0\nf 1/x 1 1\n",
            "t.obj:2: `x` in `1/x` is not an integer index",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n",
            "texture coordinate index 1",
        ),
    ];
    for (text, want) in cases {
        let e = obj(text).unwrap_err().to_string();
        assert!(e.contains(want), "{e}\n  wanted: {want}");
    }
    let mut bad = b"v 0 0 0\n# caf".to_vec();
    bad.extend([0xe9, b'\n']);
    let e = parse_obj(&bad, Path::new("t.obj"), &NoMtl)
        .unwrap_err()
        .to_string();
    assert!(e.contains("t.obj:2: this line is not valid UTF-8"), "{e}");
}

#[test]
fn degenerate_triangles_load() {
    let m = obj("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n").unwrap();
    assert_eq!(m.triangle_count(), 2);
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn shared_obj_models_load() {
    for (rel, min_tris) in [
        ("common-3d-test-models/stanford-bunny.obj.gz", 60_000),
        ("common-3d-test-models/suzanne.obj", 900),
        ("common-3d-test-models/beetle.obj", 1000),
        ("odedstein-meshes/spot/spot_low_resolution.obj", 100),
    ] {
        let p = appel_testdata::path(rel);
        let m = load_mesh(&p).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            m.triangle_count() >= min_tris,
            "{rel}: {}",
            m.triangle_count()
        );
        assert!(!m.bounds().is_empty());
    }
}

/// A one-triangle glTF with its buffer as a data URI, under a node that translates it.
fn tiny_gltf(buffer_uri: &str, byte_length: usize) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"mesh":0,"translation":[10,0,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"material":0}}]}}],
        "materials":[{{"pbrMetallicRoughness":{{"baseColorFactor":[0.2,0.4,0.6,1.0]}}}}],
        "buffers":[{{"uri":"{buffer_uri}","byteLength":{byte_length}}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]}}"#
    )
}

fn triangle_bytes() -> Vec<u8> {
    [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect()
}

#[test]
fn gltf_data_uri_node_transform_and_base_colour() {
    use base64::Engine;
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(triangle_bytes())
    );
    let text = tiny_gltf(&uri, 36);
    let m = parse_gltf_with(text.as_bytes(), Path::new("t.gltf"), &|_| Err("no".into())).unwrap();
    assert_eq!(m.triangle_count(), 1);
    assert_eq!(
        m.parts[0].mesh.vertices(0),
        [
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(11.0, 0.0, 0.0),
            Vec3::new(10.0, 1.0, 0.0)
        ]
    );
    assert_eq!(m.materials[0].diffuse, [0.2, 0.4, 0.6]);
}

#[test]
fn gltf_missing_or_short_buffer_is_named() {
    let text = tiny_gltf("tri.bin", 36);
    let e = parse_gltf_with(text.as_bytes(), Path::new("t.gltf"), &|uri| {
        Err(format!("the buffer file `{uri}` does not exist"))
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("t.gltf: buffer 0 (`tri.bin`): the buffer file `tri.bin` does not exist"),
        "{e}"
    );
    let short = parse_gltf_with(text.as_bytes(), Path::new("t.gltf"), &|_| Ok(vec![0; 20]))
        .unwrap_err()
        .to_string();
    assert!(
        short.contains("buffer 0 holds 20 bytes but the file declares 36"),
        "{short}"
    );
    // The buffer view claims more than the buffer has.
    let text = tiny_gltf("tri.bin", 24);
    let e = parse_gltf_with(text.as_bytes(), Path::new("t.gltf"), &|_| Ok(vec![0; 24]))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("does not fit in buffer view") || e.contains("invalid glTF"),
        "{e}"
    );
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn shared_sponza_gltf_without_its_bin_names_the_missing_file() {
    let p = appel_testdata::path("gltf-models/Sponza/glTF/Sponza.gltf");
    let e = load_mesh(&p).unwrap_err().to_string();
    assert!(
        e.contains("Sponza.gltf") && e.contains("Sponza.bin") && e.contains("does not exist"),
        "{e}"
    );
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn shared_gltf_models_load() {
    for (rel, min_tris) in [
        (
            "gltf-models/DamagedHelmet/glTF-Binary/DamagedHelmet.glb",
            10_000,
        ),
        ("gltf-models/FlightHelmet/glTF/FlightHelmet.gltf", 10_000),
        ("gltf-models/Suzanne/glTF/Suzanne.gltf", 900),
    ] {
        let p = appel_testdata::path(rel);
        let m = load_mesh(&p).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            m.triangle_count() >= min_tris,
            "{rel}: {}",
            m.triangle_count()
        );
        assert!(!m.materials.is_empty(), "{rel}");
    }
}

/// Found by fuzzing: gltf-json's validation indexed the accessor list without a bounds check.
#[test]
fn gltf_position_referring_to_a_missing_accessor_is_an_error_not_a_panic() {
    let text =
        r#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#;
    let e = parse_gltf_with(text.as_bytes(), Path::new("t.gltf"), &|_| Err("no".into()))
        .unwrap_err()
        .to_string();
    assert!(e.contains("refers to accessor 0, but there are 0"), "{e}");
}

/// A glTF whose mesh (two triangles) is placed by three nodes: read once, placed three times.
#[test]
fn gltf_nodes_sharing_a_mesh_become_placements_of_one_copy() {
    use base64::Engine;
    let mut bytes = triangle_bytes();
    bytes.extend(
        [0f32, 0., 1., 1., 0., 1., 0., 1., 1.]
            .iter()
            .flat_map(|x| x.to_le_bytes()),
    );
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    );
    let text = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1,2,3]}}],
        "nodes":[{{"mesh":0,"translation":[10,0,0]}},{{"mesh":1}},{{"mesh":0,"scale":[2,2,2]}},
                 {{"mesh":0,"rotation":[0,0.7071068,0,0.7071068]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}},
                  {{"primitives":[{{"attributes":{{"POSITION":1}}}}]}}],
        "buffers":[{{"uri":"{uri}","byteLength":72}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":72}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":6,"type":"VEC3","min":[0,0,0],"max":[1,1,1]}},
                     {{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]}}"#
    );
    let m = parse_gltf_with(text.as_bytes(), Path::new("t.gltf"), &|_| Err("no".into())).unwrap();
    // Mesh 0 (placed three times) is shared; mesh 1 (placed once) is a part as before.
    assert_eq!(m.shared.len(), 1);
    assert_eq!(m.placements.len(), 3);
    assert_eq!(m.parts.len(), 1);
    assert_eq!(m.triangle_count(), 3);
    // File order: node 0's two triangles, node 1's one, node 2's two, node 3's two.
    let firsts: Vec<u32> = m.placements.iter().map(|p| p.first_triangle).collect();
    assert_eq!(firsts, vec![0, 3, 5]);
    assert_eq!(m.parts[0].file_triangles, Some(vec![2]));
    let flat = m.clone().flattened();
    assert_eq!(flat.triangle_count(), 7);
    let second = flat
        .parts
        .iter()
        .find(|p| p.file_triangles == Some(vec![3, 4]))
        .unwrap();
    assert_eq!(second.mesh.vertices(0)[1], Vec3::new(2.0, 0.0, 0.0));
    // In a scene: one prototype, three instances; hits report the file's triangle numbers.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("t.gltf"), &text).unwrap();
    let scene_text = "[camera]\neye = [0.5, 0.3, 20.0]\nlook_at = [0.5, 0.3, 0.0]\n\
        [[shape]]\ntype = \"sphere\"\ncenter = [0.0, 50.0, 0.0]\nradius = 1.0\n\
        [[shape]]\ntype = \"mesh\"\nfile = \"t.gltf\"\n";
    let d = appel::description::description_from_str(
        scene_text,
        appel::description::parse::Syntax::Toml,
        Path::new("s.toml"),
    )
    .unwrap();
    let scene = appel::scene::Scene::new(&d, dir.path()).unwrap();
    assert_eq!(scene.geometry.prototypes.len(), 1);
    assert_eq!(scene.geometry.instances.len(), 3);
    let mut stats = appel::accel::TraversalStats::default();
    // Along -z through (0.2, 0.2): node 0 sits at x = 10 and node 3's triangles stand in the
    // planes x = 0 and x = 1, so the nearest is node 2's second triangle (z = 2 once scaled):
    // file triangle 4, the second placement, in front of node 1's (z = 0).
    let ray = appel::math::Ray::new(Vec3::new(0.2, 0.2, 20.0), -Vec3::Z);
    let hit = scene.intersect(&ray, f32::INFINITY, &mut stats).unwrap();
    assert_eq!(scene.geometry.source_ids(&hit), (1, 4));
    assert_eq!(hit.instance, 1);
    assert!((hit.t - 18.0).abs() < 1e-5);
}

#[test]
fn convex_polygons_are_clipped_into_the_fan_from_their_first_corner() {
    // A convex pentagon, not planar by a little (the second half of a quad shares the diagonal
    // from corner 0, which the wide BVH pairs on).
    let pts = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.01),
        Vec3::new(3.0, 1.5, 0.0),
        Vec3::new(1.0, 3.0, 0.02),
        Vec3::new(-1.0, 1.5, 0.0),
    ];
    let mut tris = vec![];
    triangulate(&pts, &mut tris);
    assert_eq!(tris, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    let mut quad = vec![];
    triangulate(&pts[..4], &mut quad);
    assert_eq!(quad, vec![[0, 1, 2], [0, 2, 3]]);
}
