//! MikkTSpace tangents for glTF primitives that have a normal texture but no `TANGENT`
//! (glTF 2.0, section 3.7.2.1): on a flat quad they follow the uvs, with a handedness that turns
//! over when the uvs are mirrored. (`gltf_tangents.rs` checks them against FlightHelmet's, which an
//! independent MikkTSpace, its exporter's, computed.)

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

/// Sanity of the encoding: MikkTSpace's tangents are unit vectors with a handedness of +-1.
#[test]
fn tangents_are_unit_with_a_sign() {
    for t in mikktspace_tangents(&quad(false)).unwrap() {
        assert!((t.truncate().length() - 1.0).abs() < 1e-5);
        assert!(t.w == 1.0 || t.w == -1.0, "{t}");
        let _: Vec4 = t;
    }
}
