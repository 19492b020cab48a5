//! glTF's `TANGENT` attribute orients normal maps as the specification says: tangent-space x
//! along the tangent, y along `cross(normal, tangent) * w`. Without it, x follows dp/du.
//!
//! The scenes are a unit quad facing the camera (+z) with uvs whose u runs along +x, under one
//! directional light 60 degrees off the normal, rendered with direct lighting only; its normal map
//! tilts every normal by 45 degrees. The quad is bright when the light stands on the side the
//! normal tilts to (cosine 0.97) and dim otherwise (0.35 from the side across, 0 from behind).

use appel::render::{render, RenderOptions};
use appel::scene::Scene;
use glam::Vec3;
use std::path::Path;

/// The normal map's colour for a tilt of 45 degrees toward tangent-space x or y.
const TILT_X: (f32, f32, f32) = (0.853_553_4, 0.5, 0.853_553_4);
const TILT_Y: (f32, f32, f32) = (0.5, 0.853_553_4, 0.853_553_4);

/// The quad's glTF: positions, normals, uvs (u along +x, v down the image, as glTF's are), and
/// `tangents` (one per vertex, written as an accessor of `tangent_type` with as many elements as
/// given) if any; `matrix` places its node. `instanced`: a second node, out of sight, places the
/// same mesh, which makes both placements instances of one shared mesh.
fn quad_gltf(
    tangents: Option<(&[[f32; 4]], &str)>,
    matrix: Option<[f32; 16]>,
    instanced: bool,
) -> (String, Vec<u8>) {
    let positions = [
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0f32],
    ];
    let uvs = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0f32]];
    let mut bin: Vec<u8> = vec![];
    let mut floats = |values: &[f32]| {
        let offset = bin.len();
        for v in values {
            bin.extend(v.to_le_bytes());
        }
        (offset, bin.len() - offset)
    };
    let p = floats(positions.as_flattened());
    let n = floats([[0.0, 0.0, 1.0f32]; 4].as_flattened());
    let t = floats(uvs.as_flattened());
    let tan = tangents.map(|(ts, _)| floats(ts.as_flattened()));
    let i = bin.len();
    for k in [0u16, 1, 2, 0, 2, 3] {
        bin.extend(k.to_le_bytes());
    }
    let mut views = vec![
        format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            p.0, p.1
        ),
        format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            n.0, n.1
        ),
        format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            t.0, t.1
        ),
        format!(r#"{{"buffer": 0, "byteOffset": {i}, "byteLength": 12}}"#),
    ];
    let mut accessors = vec![
        r#"{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}"#.to_string(),
        r#"{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}"#.to_string(),
        r#"{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}"#.to_string(),
        r#"{"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}"#.to_string(),
    ];
    let mut attributes = r#""POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2"#.to_string();
    if let (Some((ts, kind)), Some((offset, len))) = (tangents, tan) {
        let width = match kind {
            "VEC3" => 3,
            _ => 4,
        };
        let count = ts.len() * 4 / width;
        views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {offset}, "byteLength": {len}}}"#
        ));
        accessors.push(format!(
            r#"{{"bufferView": 4, "componentType": 5126, "count": {count}, "type": "{kind}"}}"#
        ));
        attributes.push_str(r#", "TANGENT": 4"#);
    }
    let mut node = match matrix {
        Some(m) => format!(r#"{{"mesh": 0, "matrix": {m:?}}}"#),
        None => r#"{"mesh": 0}"#.to_string(),
    };
    let mut roots = "0";
    if instanced {
        node.push_str(r#", {"mesh": 0, "translation": [100, 0, 0]}"#);
        roots = "0, 1";
    }
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}},
"buffers": [{{"byteLength": {}, "uri": "quad.bin"}}],
"bufferViews": [{}],
"accessors": [{}],
"images": [{{"uri": "normals.exr"}}], "textures": [{{"source": 0}}],
"materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 1}},
                "normalTexture": {{"index": 0}}}}],
"meshes": [{{"primitives": [{{"attributes": {{{attributes}}}, "indices": 3, "material": 0}}]}}],
"nodes": [{node}], "scenes": [{{"nodes": [{roots}]}}]}}"#,
        bin.len(),
        views.join(", "),
        accessors.join(",\n  "),
    );
    (json, bin)
}

/// The mean brightness of the quad filling the frame, with a constant normal map of colour
/// `tilt`, lit from `toward_light` (the direction to the light).
fn brightness(
    tangents: Option<&[[f32; 4]]>,
    matrix: Option<[f32; 16]>,
    instanced: bool,
    tilt: (f32, f32, f32),
    toward_light: Vec3,
) -> f32 {
    let dir = tempfile::tempdir().unwrap();
    let (json, bin) = quad_gltf(tangents.map(|t| (t, "VEC4")), matrix, instanced);
    std::fs::write(dir.path().join("quad.gltf"), json).unwrap();
    std::fs::write(dir.path().join("quad.bin"), bin).unwrap();
    exr::prelude::write_rgb_file(dir.path().join("normals.exr"), 2, 2, |_, _| tilt).unwrap();
    let d = -toward_light.normalize();
    let scene = format!(
        "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 20.0\nwidth = 12\nheight = 12\n\n\
         [render]\nintegrator = \"direct\"\nspp = 4\n\n\
         [[shape]]\ntype = \"mesh\"\nfile = \"quad.gltf\"\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [{}, {}, {}]\nintensity = 1.0\n",
        d.x, d.y, d.z
    );
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let loaded = appel::format::load(&path, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let scene = Scene::new(&loaded.description, &loaded.base_dir).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        scene.geometry.instances.len(),
        if instanced { 2 } else { 0 }
    );
    let film = render(&scene, &RenderOptions::default()).unwrap().0;
    film.rgb.iter().map(|c| c.element_sum() / 3.0).sum::<f32>() / film.rgb.len() as f32
}

/// 60 degrees off the quad's normal, toward `side`.
fn light_from(side: Vec3) -> Vec3 {
    0.866 * side + 0.5 * Vec3::Z
}

/// The light on the side the normal tilts to gives at least twice the light across.
fn assert_tilts_toward(bright: f32, dim: f32, what: &str) {
    eprintln!("{what}: {bright} against {dim}");
    assert!(
        bright > 2.0 * dim && bright > 0.05,
        "{what}: {bright} against {dim}"
    );
}

#[test]
fn without_tangents_the_map_s_x_follows_the_texture_u() {
    let x = brightness(None, None, false, TILT_X, light_from(Vec3::X));
    let y = brightness(None, None, false, TILT_X, light_from(Vec3::Y));
    assert_tilts_toward(
        x,
        y,
        "no TANGENT, map tilted to +x, lit from +x and from +y",
    );
}

/// The file's tangent is the uv tangent turned 90 degrees about the normal (+y instead of +x):
/// the map's x follows it, not the uvs.
#[test]
fn an_explicit_tangent_decides_where_the_map_s_x_points() {
    let along_y = [[0.0, 1.0, 0.0, 1.0f32]; 4];
    let y = brightness(Some(&along_y), None, false, TILT_X, light_from(Vec3::Y));
    let x = brightness(Some(&along_y), None, false, TILT_X, light_from(Vec3::X));
    assert_tilts_toward(
        y,
        x,
        "TANGENT +y, map tilted to +x, lit from +y and from +x",
    );
}

/// w = -1 turns the bitangent around: a map tilted toward its +y leans to -y on the surface.
#[test]
fn a_negative_handedness_flips_the_bitangent() {
    let right = [[1.0, 0.0, 0.0, 1.0f32]; 4];
    let left = [[1.0, 0.0, 0.0, -1.0f32]; 4];
    let plus = brightness(Some(&right), None, false, TILT_Y, light_from(Vec3::Y));
    let minus = brightness(Some(&right), None, false, TILT_Y, light_from(-Vec3::Y));
    assert_tilts_toward(
        plus,
        minus,
        "w = +1, map tilted to +y, lit from +y and from -y",
    );
    let plus = brightness(Some(&left), None, false, TILT_Y, light_from(Vec3::Y));
    let minus = brightness(Some(&left), None, false, TILT_Y, light_from(-Vec3::Y));
    assert_tilts_toward(
        minus,
        plus,
        "w = -1, map tilted to +y, lit from -y and from +y",
    );
}

/// Under a transform mirroring x (`instanced`: the transform of an instance of a shared mesh,
/// applied at the hit; else the node's, baked into the mesh), the tangent goes to -x and its
/// handedness turns around, so that the bitangent, which the mirror does not move, still points
/// to +y.
fn assert_a_mirror_keeps_the_bitangent(instanced: bool) {
    let right = [[1.0, 0.0, 0.0, 1.0f32]; 4];
    let mirror_x = [
        -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let lit = |tilt, side| {
        brightness(
            Some(&right),
            Some(mirror_x),
            instanced,
            tilt,
            light_from(side),
        )
    };
    let what = if instanced {
        "mirrored instance"
    } else {
        "mirrored"
    };
    assert_tilts_toward(
        lit(TILT_Y, Vec3::Y),
        lit(TILT_Y, -Vec3::Y),
        &format!("{what}, map tilted to +y, lit from +y and from -y"),
    );
    // And the tangent itself went to -x with the mirror.
    assert_tilts_toward(
        lit(TILT_X, -Vec3::X),
        lit(TILT_X, Vec3::X),
        &format!("{what}, map tilted to +x, lit from -x and from +x"),
    );
}

#[test]
fn a_mirroring_node_keeps_the_bitangent_where_it_was() {
    assert_a_mirror_keeps_the_bitangent(false);
}

#[test]
fn a_mirroring_instance_keeps_the_bitangent_where_it_was() {
    assert_a_mirror_keeps_the_bitangent(true);
}

/// A `TANGENT` accessor of the wrong type, with the wrong number of elements, or holding a
/// number that is not finite is an error naming the file and the attribute; none panics.
#[test]
fn malformed_tangent_accessors_are_errors_naming_the_file() {
    let parse = |json: &str, bin: Vec<u8>| {
        appel::io::gltf::parse_gltf_with(json.as_bytes(), Path::new("bad.gltf"), &move |uri| {
            match uri {
                "quad.bin" => Ok(bin.clone()),
                _ => Err(format!("`{uri}` does not exist")),
            }
        })
    };
    let good = [[0.0, 1.0, 0.0, 1.0f32]; 4];
    let (json, bin) = quad_gltf(Some((&good, "VEC4")), None, false);
    let m = parse(&json, bin).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        m.parts[0].tangents.as_deref(),
        Some(&[glam::Vec4::Y + glam::Vec4::W; 4][..])
    );
    let nan = [[f32::NAN, 1.0, 0.0, 1.0f32]; 4];
    for (what, tangents, kind) in [
        ("VEC3 tangents", &good[..], "VEC3"),
        ("three tangents for four vertices", &good[..3], "VEC4"),
        ("a NaN tangent", &nan[..], "VEC4"),
    ] {
        let (json, bin) = quad_gltf(Some((tangents, kind)), None, false);
        let e = parse(&json, bin)
            .err()
            .unwrap_or_else(|| panic!("{what}: accepted"))
            .to_string();
        eprintln!("{what}: {e}");
        assert!(
            e.contains("bad.gltf") && e.contains("TANGENT"),
            "{what}: {e}"
        );
    }
}

/// FlightHelmet (in the shared data) gives every primitive tangents: they load, one per vertex,
/// unit length with handedness +1 or -1, as the specification requires of them. Its exporter
/// computed them with MikkTSpace, so Appel's own MikkTSpace tangents, found from the positions,
/// normals and uvs alone, agree with them in handedness and direction on nearly every vertex
/// (vertices on a uv seam or a degenerate triangle may differ, as MikkTSpace welds and splits
/// them by its own rules).
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn flight_helmet_s_tangents_load() {
    let path = appel_testdata::path("gltf-models/FlightHelmet/glTF/FlightHelmet.gltf");
    let m = appel::io::load_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(!m.parts.is_empty());
    let (mut mirrored, mut total) = (0, 0);
    for part in &m.parts {
        let t = part.tangents.as_ref().expect("tangents");
        assert_eq!(t.len(), part.mesh.positions.len());
        for t in t {
            assert!((t.truncate().length() - 1.0).abs() < 1e-3, "{t}");
            assert!(t.w == 1.0 || t.w == -1.0, "{t}");
            mirrored += (t.w < 0.0) as usize;
            total += 1;
        }
    }
    eprintln!("FlightHelmet: {total} tangents, {mirrored} with w = -1");
    let mut agree = 0usize;
    for part in &m.parts {
        let ours = appel::io::mikktspace_tangents::mikktspace_tangents(&part.mesh)
            .expect("MikkTSpace tangents");
        for (given, o) in part.tangents.as_ref().unwrap().iter().zip(&ours) {
            agree += (given.w == o.w && given.truncate().dot(o.truncate()) > 0.9) as usize;
        }
    }
    let share = agree as f64 / total as f64;
    eprintln!("FlightHelmet: {agree} of {total} MikkTSpace tangents agree ({share:.4})");
    assert!(share > 0.95, "{agree} of {total} ({share})");
}
