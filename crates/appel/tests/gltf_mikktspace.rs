//! MikkTSpace tangents for glTF primitives that have a normal texture but no `TANGENT`
//! (glTF 2.0, section 3.7.2.1): on a flat quad they follow the uvs, with a handedness that turns
//! over when the uvs are mirrored, and on FlightHelmet they agree with the tangents its exporter
//! wrote, which an independent MikkTSpace (Blender's) computed.

use appel::geometry::TriangleMesh;
use appel::io::mikktspace_tangents::mikktspace_tangents;
use glam::{Vec2, Vec3, Vec4};

/// A unit quad facing +z; `u_along_x`: u grows along +x, else along -x (a mirrored uv island).
/// v grows down the image, toward -y, as glTF's does.
fn quad(u_along_x: bool) -> TriangleMesh {
    let u = |x: f32| if u_along_x { x } else { 1.0 - x };
    TriangleMesh {
        positions: vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        normals: Some(vec![Vec3::Z; 4]),
        uvs: Some(vec![
            Vec2::new(u(0.0), 1.0),
            Vec2::new(u(1.0), 1.0),
            Vec2::new(u(1.0), 0.0),
            Vec2::new(u(0.0), 0.0),
        ]),
    }
}

/// glTF's bitangent, `cross(normal, tangent) * w`, points up the image (toward smaller v), which
/// on both quads is +y.
#[test]
fn a_quad_s_tangents_follow_u_and_its_bitangent_points_up_the_image() {
    for (u_along_x, tangent) in [(true, Vec3::X), (false, -Vec3::X)] {
        let t = mikktspace_tangents(&quad(u_along_x)).expect("tangents");
        assert_eq!(t.len(), 4);
        for t in t {
            assert!(
                t.truncate().abs_diff_eq(tangent, 1e-5),
                "u along +x {u_along_x}: {t}"
            );
            let bitangent = Vec3::Z.cross(t.truncate()) * t.w;
            assert!(
                bitangent.abs_diff_eq(Vec3::Y, 1e-5),
                "u along +x {u_along_x}: {t}"
            );
        }
    }
}

#[test]
fn without_normals_or_uvs_there_are_no_tangents() {
    let mut m = quad(true);
    m.uvs = None;
    assert!(mikktspace_tangents(&m).is_none());
    let mut m = quad(true);
    m.normals = None;
    assert!(mikktspace_tangents(&m).is_none());
}

/// FlightHelmet's exporter wrote MikkTSpace tangents; ours, computed from its positions, normals
/// and uvs alone, agree with them in handedness and direction on nearly every vertex (vertices
/// on a uv seam or a degenerate triangle may differ, as MikkTSpace welds and splits them by its
/// own rules).
#[test]
fn flight_helmet_s_tangents_are_found_again() {
    let path = std::path::PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/data/gltf-models/FlightHelmet/glTF/FlightHelmet.gltf"
    ));
    if !path.exists() {
        eprintln!("skipped: {} not found", path.display());
        return;
    }
    let m = appel::io::load_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
    let (mut agree, mut total) = (0usize, 0usize);
    for part in &m.parts {
        let given = part.tangents.as_ref().expect("the file's tangents");
        let ours = mikktspace_tangents(&part.mesh).expect("MikkTSpace tangents");
        for (g, o) in given.iter().zip(&ours) {
            let same_side = g.w == o.w;
            let close = g.truncate().dot(o.truncate()) > 0.9;
            agree += (same_side && close) as usize;
            total += 1;
        }
    }
    let share = agree as f64 / total as f64;
    eprintln!("FlightHelmet: {agree} of {total} tangents agree ({share:.4})");
    assert!(share > 0.95, "{agree} of {total} ({share})");
}

/// Sanity of the encoding: MikkTSpace's tangents are unit vectors with a handedness of +-1.
#[test]
fn tangents_are_unit_with_a_sign() {
    for t in mikktspace_tangents(&quad(false)).unwrap() {
        assert!((t.truncate().length() - 1.0).abs() < 1e-5);
        assert!(t.w == 1.0 || t.w == -1.0, "{t}");
        let _: Vec4 = t;
    }
}
