//! Small glTF files written here, with their buffers embedded as data URIs: the node hierarchy,
//! cameras, lights and errors of the glTF scene format.

use super::GltfFormat;
use crate::description::{DiffuseDesc, IntegratorName, MaterialDesc, ShapeDesc, TextureDesc};
use crate::format::{FormatOptions, LoadedDescription, SceneFormat};
use crate::math::Vec3;
use crate::scene::Scene;
use base64::Engine;
use std::path::{Path, PathBuf};

/// A mesh's buffer: `positions` (and one +y normal per vertex if `normals`) as little-endian
/// f32, then the u16 `indices` padded to 4 bytes.
struct MeshData {
    positions: Vec<[f32; 3]>,
    indices: Vec<u16>,
    normals: bool,
}

impl MeshData {
    /// The triangle (0,0,0), (1,0,0), (0,1,0).
    fn triangle() -> Self {
        Self {
            positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            indices: vec![0, 1, 2],
            normals: false,
        }
    }

    /// A square of side `2 * half` in the plane y = 0, facing +y.
    fn floor(half: f32) -> Self {
        Self {
            positions: vec![
                [-half, 0.0, -half],
                [-half, 0.0, half],
                [half, 0.0, half],
                [half, 0.0, -half],
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            normals: true,
        }
    }

    /// `buffers`, `bufferViews`, `accessors` and `meshes`, as JSON members.
    fn json(&self) -> String {
        let mut bytes: Vec<u8> = vec![];
        let floats = |bytes: &mut Vec<u8>, v: &[[f32; 3]]| {
            for p in v {
                for x in p {
                    bytes.extend_from_slice(&x.to_le_bytes());
                }
            }
        };
        floats(&mut bytes, &self.positions);
        let n = self.positions.len();
        let normals_at = bytes.len();
        if self.normals {
            floats(&mut bytes, &vec![[0.0, 1.0, 0.0]; n]);
        }
        let indices_at = bytes.len();
        for i in &self.indices {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
        while !bytes.len().is_multiple_of(4) {
            bytes.push(0);
        }
        let (lo, hi) = self
            .positions
            .iter()
            .fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), p| {
                (
                    [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                    [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
                )
            });
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&bytes)
        );
        let (normal_attr, normal_view, normal_accessor) = if self.normals {
            (
                r#", "NORMAL": 2"#.to_string(),
                format!(
                    r#", {{"buffer": 0, "byteOffset": {normals_at}, "byteLength": {}}}"#,
                    12 * n
                ),
                format!(
                    r#", {{"bufferView": 2, "componentType": 5126, "count": {n}, "type": "VEC3"}}"#
                ),
            )
        } else {
            Default::default()
        };
        format!(
            r#""buffers": [{{"uri": "{uri}", "byteLength": {len}}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": {pos_len}}},
    {{"buffer": 0, "byteOffset": {indices_at}, "byteLength": {idx_len}}}{normal_view}
  ],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": {n}, "type": "VEC3",
      "min": {lo:?}, "max": {hi:?}}},
    {{"bufferView": 1, "componentType": 5123, "count": {count}, "type": "SCALAR"}}{normal_accessor}
  ],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0{normal_attr}}}, "indices": 1}}]}}]"#,
            len = bytes.len(),
            pos_len = 12 * n,
            idx_len = 2 * self.indices.len(),
            count = self.indices.len(),
        )
    }
}

/// A glTF file of `mesh` and the JSON members `rest` (`"nodes": [...]` and the like).
fn gltf(mesh: &MeshData, rest: &str) -> String {
    format!(
        "{{\n  \"asset\": {{\"version\": \"2.0\"}},\n  {},\n  {rest}\n}}\n",
        mesh.json()
    )
}

/// Writes `text` as `name` in a fresh folder.
fn write(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn load(path: &Path) -> crate::error::Result<LoadedDescription> {
    GltfFormat.load(path, &FormatOptions::default())
}

fn build(loaded: &LoadedDescription) -> Scene {
    Scene::new_with(&loaded.description, &loaded.base_dir, Default::default()).unwrap()
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!((a - b).abs().max_element() < 1e-4, "{a} != {b}");
}

/// Unit quaternion `[x, y, z, w]` of `degrees` about a coordinate axis.
fn rotation(axis: [f32; 3], degrees: f32) -> String {
    let (s, c) = (degrees.to_radians() / 2.0).sin_cos();
    format!("[{}, {}, {}, {c}]", axis[0] * s, axis[1] * s, axis[2] * s)
}

#[test]
fn nested_node_transforms_compose_down_the_tree() {
    // Root: translate by (10, 0, 0); child: rotate 90 degrees about z, then scale by 2 (TRS);
    // grandchild: a matrix translating by (0, 0, 3) (column-major), which the child's scale
    // doubles. The triangle's corners (0,0,0), (1,0,0) and (0,1,0) end at (10, 0, 6),
    // (10, 2, 6) and (8, 0, 6).
    let nodes = format!(
        r#""scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [
    {{"translation": [10, 0, 0], "children": [1]}},
    {{"rotation": {}, "scale": [2, 2, 2], "children": [2]}},
    {{"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,3,1], "mesh": 0}}
  ]"#,
        rotation([0.0, 0.0, 1.0], 90.0)
    );
    let (_dir, path) = write("tree.gltf", &gltf(&MeshData::triangle(), &nodes));
    let loaded = load(&path).unwrap();
    let scene = build(&loaded);
    let bounds = scene.geometry.bounds();
    assert_close(bounds.min, Vec3::new(8.0, 0.0, 6.0));
    assert_close(bounds.max, Vec3::new(10.0, 2.0, 6.0));
    // A ray down -z through the triangle's inside meets it at z = 6.
    let ray = crate::math::Ray::new(Vec3::new(9.5, 0.5, 10.0), Vec3::new(0.0, 0.0, -1.0));
    let hit = scene
        .intersect(&ray, f32::INFINITY, &mut Default::default())
        .expect("the placed triangle is hit");
    assert!((hit.t - 4.0).abs() < 1e-4, "t = {}", hit.t);
    // The framing (no camera in the file) looks at the box the accessors' bounds give.
    assert_close(
        Vec3::from(loaded.description.camera.look_at),
        Vec3::new(9.0, 1.0, 6.0),
    );
}

#[test]
fn a_mesh_placed_by_two_nodes_is_instanced() {
    let nodes = r#""scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [0, 0, -5]}]"#;
    let (_dir, path) = write("twice.gltf", &gltf(&MeshData::triangle(), nodes));
    let scene = build(&load(&path).unwrap());
    assert_eq!(scene.geometry.prototypes.len(), 1);
    assert_eq!(scene.geometry.instances.len(), 2);
    assert_close(scene.geometry.bounds().min, Vec3::new(0.0, 0.0, -5.0));
}

#[test]
fn the_first_camera_in_traversal_order_is_the_view() {
    // Node 0 (a root) holds node 2's camera below it, before root 1's: traversal meets the
    // camera of node 2 first. That camera stands at (1, 2, 3) turned 90 degrees about +y, so it
    // looks down -x with +y up.
    let nodes = format!(
        r#""scene": 0, "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [
    {{"translation": [1, 2, 3], "children": [2], "mesh": 0}},
    {{"camera": 1, "translation": [0, 0, 9]}},
    {{"camera": 0, "rotation": {}, "name": "side"}}
  ],
  "cameras": [
    {{"type": "perspective", "perspective": {{"yfov": 0.5, "aspectRatio": 2.0, "znear": 0.1, "zfar": 100}}}},
    {{"type": "orthographic", "orthographic": {{"xmag": 3, "ymag": 1.5, "znear": 0, "zfar": 10}}}}
  ]"#,
        rotation([0.0, 1.0, 0.0], 90.0)
    );
    let (_dir, path) = write("cameras.gltf", &gltf(&MeshData::triangle(), &nodes));
    let loaded = load(&path).unwrap();
    let c = &loaded.description.camera;
    assert_close(Vec3::from(c.eye), Vec3::new(1.0, 2.0, 3.0));
    assert_close(Vec3::from(c.look_at), Vec3::new(0.0, 2.0, 3.0));
    assert_close(Vec3::from(c.up), Vec3::Y);
    assert!((c.fov - 0.5f32.to_degrees()).abs() < 1e-3, "{}", c.fov);
    assert_eq!(c.near_clip, 0.1);
    assert_eq!((c.width, c.height), (640, 320));
    assert_eq!(c.kind, crate::description::CameraKind::Perspective);
    // The other camera is there to be chosen: orthographic, half as high as wide.
    assert_eq!(loaded.cameras.len(), 2);
    assert_eq!(loaded.cameras[0].name, "side");
    let ortho = &loaded.cameras[1];
    assert_eq!(
        ortho.camera.kind,
        crate::description::CameraKind::Orthographic
    );
    assert_eq!(ortho.camera.half_width, Some(3.0));
    assert_eq!(ortho.aspect, Some(2.0));
    assert_close(Vec3::from(ortho.camera.eye), Vec3::new(0.0, 0.0, 9.0));
    assert_close(Vec3::from(ortho.camera.look_at), Vec3::new(0.0, 0.0, 8.0));
    // A file with a camera and no lights is lit as a bare model is (without materials, by a
    // point light beside the framing's eye and a directional one), and says so.
    assert!(
        loaded.warnings.iter().any(|w| w.contains("has no lights")),
        "{:?}",
        loaded.warnings
    );
    assert!(matches!(
        loaded.description.lights.as_slice(),
        [
            crate::description::LightDesc::Point(_),
            crate::description::LightDesc::Directional(_)
        ]
    ));
}

/// The radiance seen straight down at the origin of a white diffuse floor lit by the file's
/// `light` node (direct light only), through a narrow camera 1 above it.
fn floor_radiance(light_node: &str, light: &str) -> f32 {
    let nodes = format!(
        r#""scenes": [{{"nodes": [0, 1, 2]}}],
  "nodes": [
    {{"mesh": 0}},
    {{"camera": 0, "translation": [0, 1, 0], "rotation": {down}}},
    {light_node}
  ],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.01, "znear": 0.001}}}}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {{"KHR_lights_punctual": {{"lights": [{light}]}}}}"#,
        down = rotation([1.0, 0.0, 0.0], -90.0)
    );
    let (_dir, path) = write("lit.gltf", &gltf(&MeshData::floor(50.0), &nodes));
    let mut loaded = load(&path).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &mut loaded.description;
    d.materials.insert(
        "white".into(),
        MaterialDesc::Diffuse(DiffuseDesc {
            reflectance: TextureDesc::Value(1.0),
        }),
    );
    let ShapeDesc::Mesh(m) = &mut d.shapes[0] else {
        panic!("the file is one mesh shape")
    };
    m.material = Some("white".into());
    d.render.integrator = IntegratorName::Direct;
    (d.render.spp, d.camera.width, d.camera.height) = (4, 2, 2);
    let scene = build(&loaded);
    let (film, _) = crate::render::render(&scene, &Default::default()).unwrap();
    let mean = (0..4)
        .map(|i| film.pixel(i % 2, i / 2))
        .fold(Vec3::ZERO, |a, b| a + b)
        / 4.0;
    assert!(
        (mean.x - mean.z).abs() <= 1e-4 * mean.x,
        "white light: {mean}"
    );
    mean.y
}

/// Within 1% of the irradiance `e` on a white Lambertian floor: radiance `e / pi`.
fn assert_irradiance(radiance: f32, e: f32) {
    let expected = e / std::f32::consts::PI;
    assert!(
        (radiance - expected).abs() < 0.01 * expected,
        "radiance {radiance}, expected {expected}"
    );
}

#[test]
fn a_point_light_gives_the_inverse_square_irradiance() {
    // 8 W/sr from 2 above: E = 8 / 2^2.
    let l = floor_radiance(
        r#"{"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}"#,
        r#"{"type": "point", "intensity": 8}"#,
    );
    assert_irradiance(l, 2.0);
}

#[test]
fn a_spot_light_gives_its_intensity_inside_the_inner_cone() {
    // Pointing down (its -z turned onto -y) from 2 above: the floor's origin is on its axis.
    let node = format!(
        r#"{{"translation": [0, 2, 0], "rotation": {},
      "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}"#,
        rotation([1.0, 0.0, 0.0], -90.0)
    );
    let light = r#"{"type": "spot", "intensity": 8, "color": [1, 1, 1],
      "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.5}}"#;
    assert_irradiance(floor_radiance(&node, light), 2.0);
    // Tilted by 40 degrees, the origin lies outside the 0.5 rad (28.6 degree) cone: dark.
    let away = format!(
        r#"{{"translation": [0, 2, 0], "rotation": {},
      "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}"#,
        rotation([1.0, 0.0, 0.0], -50.0)
    );
    assert_eq!(floor_radiance(&away, light), 0.0);
}

#[test]
fn a_directional_light_gives_its_lux_times_the_cosine() {
    // Turned -60 degrees about x, the light travels along (0, -sin 60, -cos 60): 3 W/m^2 at
    // normal incidence, times cos 30 on the floor.
    let node = format!(
        r#"{{"rotation": {}, "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}"#,
        rotation([1.0, 0.0, 0.0], -60.0)
    );
    let l = floor_radiance(&node, r#"{"type": "directional", "intensity": 3}"#);
    assert_irradiance(l, 3.0 * 30f32.to_radians().cos());
}

#[test]
fn a_light_range_is_ignored_with_a_warning() {
    let nodes = r#""scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0}, {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 5, "range": 3}]}}"#;
    let (_dir, path) = write("range.gltf", &gltf(&MeshData::triangle(), nodes));
    let loaded = load(&path).unwrap();
    assert_eq!(loaded.description.lights.len(), 1);
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.contains("`range` (3) is ignored")),
        "{:?}",
        loaded.warnings
    );
}

/// The error loading a file with `rest` as its nodes and the like.
fn error(rest: &str) -> String {
    let (_dir, path) = write("bad.gltf", &gltf(&MeshData::triangle(), rest));
    match load(&path) {
        Ok(_) => panic!("loaded a bad file: {rest}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn out_of_range_indices_are_errors_naming_the_file() {
    for (rest, what) in [
        (
            r#""scenes": [{"nodes": [0]}], "nodes": [{"mesh": 5}]"#,
            "nodes[0].mesh",
        ),
        (
            r#""scenes": [{"nodes": [3]}], "nodes": [{"mesh": 0}]"#,
            "scenes[0].nodes[0]",
        ),
        (
            r#""scene": 2, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}]"#,
            "scene",
        ),
        (
            r#""scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "camera": 0}]"#,
            "nodes[0].camera",
        ),
        (
            r#""scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "children": [7]}]"#,
            "nodes[0].children[0]",
        ),
        (
            r#""scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "extensions": {"KHR_lights_punctual": {"light": 1}}}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point"}]}}"#,
            "nodes[0].extensions",
        ),
    ] {
        let e = error(rest);
        assert!(e.contains("bad.gltf:"), "{e}");
        assert!(e.contains(&format!("invalid glTF: `{what}")), "{what}: {e}");
        assert!(e.contains("index out of bounds"), "{e}");
    }
}

#[test]
fn a_node_cycle_is_an_error() {
    let e = error(
        r#""scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "children": [1]}, {"children": [2]}, {"children": [1]}]"#,
    );
    // Placed at node 2's `children`: on the line of the nodes, the file's last but one.
    let line = gltf(&MeshData::triangle(), "").lines().count() - 1;
    assert!(e.contains(&format!("bad.gltf:{line}: ")), "{e}");
    assert!(
        e.contains("node 1 is its own ancestor (nodes 1 -> 2 -> 1)"),
        "{e}"
    );
}

#[test]
fn a_syntax_error_names_the_line() {
    let (_dir, path) = write(
        "broken.gltf",
        "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"nodes\": [,]\n}\n",
    );
    let e = load(&path).unwrap_err().to_string();
    assert!(e.contains("broken.gltf:3"), "{e}");
}
