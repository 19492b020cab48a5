//! glTF files as scenes through `api::resolve_scene`, the path of `appel render x.glb`: the shared
//! Khronos models, a choice of camera, and a file inside a zip archive.

use appel::api::{resolve_scene, RequestNames, SceneRequest};
use appel::description::{CameraKind, Description};
use appel::format::FormatOptions;
use appel::scene_build::SceneOptions;
use appel::Error;

fn request<'a>(
    name: &'a str,
    camera: Option<usize>,
    overrides: &'a dyn Fn(&mut Description) -> appel::Result<()>,
) -> SceneRequest<'a, Error> {
    SceneRequest {
        name,
        params: FormatOptions::default(),
        camera,
        overrides,
        names: RequestNames::default(),
    }
}

/// A small image, so that building is all these tests cost.
fn small(d: &mut Description) -> appel::Result<()> {
    (d.camera.width, d.camera.height) = (16, 12);
    Ok(())
}

/// A triangle (data URI), seen by a perspective camera and an orthographic one.
const TWO_CAMERAS: &str = r#"{
  "asset": {"version": "2.0"},
  "buffers": [{"uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA", "byteLength": 36}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "cameras": [
    {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}},
    {"type": "orthographic", "orthographic": {"xmag": 2, "ymag": 1, "znear": 0, "zfar": 10}}
  ],
  "scenes": [{"nodes": [0, 1, 2]}],
  "nodes": [
    {"mesh": 0},
    {"camera": 0, "translation": [0.5, 0.5, 3], "name": "front"},
    {"camera": 1, "translation": [0.5, 0.5, 5], "name": "flat"}
  ]
}
"#;

#[test]
fn a_gltf_file_is_a_scene_seen_through_its_cameras() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("two.gltf");
    std::fs::write(&path, TWO_CAMERAS).unwrap();
    let name = path.to_str().unwrap();
    let (resolved, scene) =
        resolve_scene(&request(name, None, &small), SceneOptions::default()).unwrap();
    assert!(!resolved.framed_model, "read as a scene, not framed");
    assert_eq!(resolved.cameras.len(), 2);
    assert_eq!(resolved.description.camera.eye, [0.5, 0.5, 3.0]);
    assert_eq!(scene.geometry.triangle_count(), 1);
    // The second camera, by choice; the image size stays the caller's.
    let (resolved, _) =
        resolve_scene(&request(name, Some(1), &small), SceneOptions::default()).unwrap();
    let c = &resolved.description.camera;
    assert_eq!(c.kind, CameraKind::Orthographic);
    assert_eq!(c.eye, [0.5, 0.5, 5.0]);
    assert_eq!((c.width, c.height), (16, 12));
    // A camera the file does not have: the message lists those it has.
    let e = resolve_scene(&request(name, Some(2), &small), SceneOptions::default())
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("there is no camera 2: the file has 2 (0: front, 1: flat)"),
        "{e}"
    );
}

#[test]
fn a_gltf_file_inside_a_zip_archive_is_a_scene() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("assets.zip");
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&archive).unwrap());
    zip.start_file("dir/two.gltf", zip::write::SimpleFileOptions::default())
        .unwrap();
    zip.write_all(TWO_CAMERAS.as_bytes()).unwrap();
    zip.finish().unwrap();
    let name = format!("{}:dir/two.gltf", archive.display());
    let (resolved, scene) =
        resolve_scene(&request(&name, None, &small), SceneOptions::default()).unwrap();
    assert!(!resolved.framed_model);
    assert_eq!(resolved.base_dir, dir.path());
    assert_eq!(resolved.description.camera.eye, [0.5, 0.5, 3.0]);
    assert_eq!(scene.geometry.triangle_count(), 1);
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn shared_khronos_models_are_scenes() {
    for (rel, meshes) in [
        ("gltf-models/DamagedHelmet/glTF-Binary/DamagedHelmet.glb", 1),
        ("gltf-models/FlightHelmet/glTF/FlightHelmet.gltf", 6),
        ("gltf-models/Suzanne/glTF/Suzanne.gltf", 1),
    ] {
        let path = appel_testdata::path(rel);
        let (resolved, scene) = resolve_scene(
            &request(path.to_str().unwrap(), None, &small),
            SceneOptions::default(),
        )
        .unwrap_or_else(|e| panic!("{rel}: {e}"));
        assert!(!resolved.framed_model, "{rel}");
        assert!(
            resolved
                .warnings
                .iter()
                .any(|w| w.contains("has no lights")),
            "{rel}: {:?}",
            resolved.warnings
        );
        assert_eq!(scene.geometry.meshes.len(), meshes, "{rel}");
        // Framed from the accessors' bounds: the camera looks at the centre of what was built.
        let centre = scene.geometry.bounds().center();
        let look_at = appel::math::Vec3::from(resolved.description.camera.look_at);
        assert!(
            (centre - look_at).length() < 1e-3 * scene.geometry.bounds().extent().length(),
            "{rel}: {centre} vs {look_at}"
        );
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn shared_sponza_without_its_bin_is_an_error_naming_it() {
    let path = appel_testdata::path("gltf-models/Sponza/glTF/Sponza.gltf");
    let none = |_: &mut Description| Ok(());
    let e = resolve_scene(
        &request(path.to_str().unwrap(), None, &none),
        SceneOptions::default(),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.contains("Sponza.gltf") && e.contains("Sponza.bin") && e.contains("does not exist"),
        "{e}"
    );
}
