//! PLY reader: the three encodings agree, gzip works, and every kind of bad file gets an error that
//! says where and why.

use appel::description::loaded_mesh::LoadedMesh;
use appel::io::load_mesh;
use appel::io::ply::parse_ply;
use appel::math::Vec3;
use std::io::Write;
use std::path::Path;

const HEADER_TAIL: &str = "element face 2\nproperty list uchar int vertex_indices\nend_header\n";

/// A unit square as a quad plus a lone triangle, with normals and extra vertex and face properties
/// (read as attributes, Mitsuba's `vertex_red` and `face_flags`).
fn ascii() -> Vec<u8> {
    b"ply\nformat ascii 1.0\ncomment test\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nelement face 2\nproperty list uchar int vertex_indices\nproperty int flags\nend_header\n0 0 0 0 0 1 255\n1 0 0 0 0 1 255\n1 1 0 0 0 1 255\n0 1 0 0 0 1 255\n0 0 1 0 0 1 0\n4 0 1 2 3 7\n3 0 1 4 9\n".to_vec()
}

fn put(out: &mut Vec<u8>, big: bool, bytes: &[u8]) {
    if big {
        out.extend(bytes.iter().rev());
    } else {
        out.extend(bytes);
    }
}

/// The same mesh as `ascii()`, binary, with double coordinates, a ushort count, uint indices.
fn binary(big: bool) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_{}_endian 1.0\nelement vertex 5\nproperty double x\nproperty double y\nproperty double z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nelement edge 1\nproperty list uchar short junk\nelement face 2\nproperty list ushort uint vertex_index\nproperty int flags\nend_header\n",
        if big { "big" } else { "little" }
    )
    .into_bytes();
    let verts: [[f64; 3]; 5] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
    ];
    for (v, red) in verts.into_iter().zip([255u8, 255, 255, 255, 0]) {
        for x in v {
            put(&mut out, big, &x.to_le_bytes());
        }
        for n in [0f32, 0.0, 1.0] {
            put(&mut out, big, &n.to_le_bytes());
        }
        out.push(red);
    }
    out.push(2); // edge: list of 2 shorts
    put(&mut out, big, &5i16.to_le_bytes());
    put(&mut out, big, &6i16.to_le_bytes());
    for (face, flags) in [(&[0u32, 1, 2, 3][..], 7i32), (&[0, 1, 4], 9)] {
        put(&mut out, big, &(face.len() as u16).to_le_bytes());
        for &i in face {
            put(&mut out, big, &i.to_le_bytes());
        }
        put(&mut out, big, &flags.to_le_bytes());
    }
    out
}

/// The common layout the fast path reads: float xyz, uchar/int triangles.
fn fast(verts: &[[f32; 3]], faces: &[&[i32]]) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        verts.len(),
        faces.len()
    )
    .into_bytes();
    for v in verts {
        for x in v {
            out.extend(x.to_le_bytes());
        }
    }
    for f in faces {
        out.push(f.len() as u8);
        for i in *f {
            out.extend(i.to_le_bytes());
        }
    }
    out
}

fn parse(bytes: &[u8]) -> appel::Result<LoadedMesh> {
    parse_ply(bytes, Path::new("test.ply"))
}

fn err(bytes: &[u8]) -> String {
    match parse(bytes) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e.to_string(),
    }
}

fn check_square_mesh(m: &LoadedMesh) {
    assert_eq!(m.parts.len(), 1);
    let mesh = &m.parts[0].mesh;
    assert_eq!(mesh.positions.len(), 5);
    assert_eq!(mesh.positions[2], Vec3::new(1.0, 1.0, 0.0));
    // The quad is fanned from its first corner; then the triangle.
    assert_eq!(mesh.indices, vec![[0, 1, 2], [0, 2, 3], [0, 1, 4]]);
    assert_eq!(mesh.normals.as_ref().unwrap()[4], Vec3::Z);
    assert!(mesh.uvs.is_none());
}

#[test]
fn ascii_and_both_binary_encodings_read_the_same_mesh() {
    let a = parse(&ascii()).unwrap();
    check_square_mesh(&a);
    // Face values follow the quad into both triangles of its fan.
    let values: Vec<(&str, &[f32])> = a
        .attributes
        .iter()
        .map(|x| (x.name.as_str(), &x.data[..]))
        .collect();
    assert_eq!(
        values,
        [
            ("vertex_red", &[255.0, 255.0, 255.0, 255.0, 0.0][..]),
            ("face_flags", &[7.0, 7.0, 9.0][..])
        ]
    );
    let le = parse(&binary(false)).unwrap();
    let be = parse(&binary(true)).unwrap();
    assert_eq!(a, le);
    assert_eq!(a, be);
}

#[test]
fn fast_path_agrees_with_the_general_reader() {
    let verts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 2.0],
    ];
    let faces: [&[i32]; 3] = [&[0, 1, 2], &[0, 1, 3, 2], &[3, 2, 1]];
    let fast_bytes = fast(&verts, &faces);
    let fast_mesh = parse(&fast_bytes).unwrap();
    // The same data, big-endian, goes through the general reader.
    let header_len = fast_bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let mut be = b"ply\nformat binary_big_endian 1.0".to_vec();
    be.extend(&fast_bytes[b"ply\nformat binary_little_endian 1.0".len()..header_len]);
    let body = &fast_bytes[header_len..];
    // Byte-swap every 4-byte field, leaving the 1-byte counts alone.
    let mut pos = 0;
    for _ in 0..verts.len() * 3 {
        be.extend(body[pos..pos + 4].iter().rev());
        pos += 4;
    }
    while pos < body.len() {
        let n = body[pos] as usize;
        be.push(body[pos]);
        pos += 1;
        for _ in 0..n {
            be.extend(body[pos..pos + 4].iter().rev());
            pos += 4;
        }
    }
    let general_mesh = parse(&be).unwrap();
    assert_eq!(fast_mesh, general_mesh);
    assert_eq!(fast_mesh.triangle_count(), 1 + 2 + 1);
}

#[test]
fn texture_coordinates_under_their_several_names() {
    for (u, v) in [("u", "v"), ("s", "t"), ("texture_u", "texture_v")] {
        let text = format!("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float {u}\nproperty float {v}\n{HEADER_TAIL}0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 0.5\n3 0 1 2\n3 2 1 0\n");
        let m = parse(text.as_bytes()).unwrap();
        let uvs = m.parts[0].mesh.uvs.as_ref().unwrap();
        assert_eq!(uvs[2], appel::math::Vec2::new(0.0, 0.5), "{u} {v}");
    }
}

#[test]
fn gzip_files_load_like_plain_ones() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("m.ply");
    std::fs::write(&plain, binary(false)).unwrap();
    let gz = dir.path().join("m.ply.gz");
    let mut enc = flate2::write::GzEncoder::new(
        std::fs::File::create(&gz).unwrap(),
        flate2::Compression::fast(),
    );
    enc.write_all(&binary(false)).unwrap();
    enc.finish().unwrap();
    let a = load_mesh(&plain).unwrap();
    let b = load_mesh(&gz).unwrap();
    assert_eq!(a, b);
    check_square_mesh(&a);
}

#[test]
fn truncated_binary_file_names_the_byte_offset() {
    let full = fast(
        &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[&[0, 1, 2], &[0, 2, 1]],
    );
    // Cut inside the last face: the size check passes (each face needs at least its count byte),
    // the read runs off the end.
    let cut = &full[..full.len() - 3];
    let e = err(cut);
    assert!(e.contains("test.ply: at byte"), "{e}");
    assert!(e.contains("ends in the middle of a `face` record"), "{e}");
    // Cut in the vertices: caught from the header's counts before reading.
    let header_len = full.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let e = err(&full[..header_len + 20]);
    assert!(e.contains("too short for its header"), "{e}");
    assert!(e.contains("3 `vertex` records"), "{e}");
}

#[test]
fn header_counts_that_lie_are_caught() {
    // More faces declared than present.
    let lie = String::from_utf8(ascii())
        .unwrap()
        .replace("element face 2", "element face 3");
    let e = err(lie.as_bytes());
    assert!(
        e.contains("the file ends after 2 of the 3 `face` records"),
        "{e}"
    );
    // Fewer vertices declared than present: the extra vertex line is read as a face.
    let lie = String::from_utf8(ascii())
        .unwrap()
        .replace("element vertex 5", "element vertex 4");
    let e = err(lie.as_bytes());
    assert!(e.contains("test.ply:"), "{e}");
    // Binary: fewer faces than the data holds leaves bytes over.
    let mut b = fast(
        &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[&[0, 1, 2], &[0, 2, 1]],
    );
    let s = String::from_utf8_lossy(&b).replace("element face 2", "element face 1");
    let header_len = b.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let mut lie = s.as_bytes()[..header_len].to_vec();
    lie.extend(b.split_off(header_len));
    let e = err(&lie);
    assert!(e.contains("13 bytes of data after the last element"), "{e}");
    // A count far beyond the file is refused before anything is allocated.
    let huge = String::from_utf8(ascii())
        .unwrap()
        .replace("element vertex 5", "element vertex 4000000000");
    let e = err(huge.as_bytes());
    assert!(e.contains("too short for its header"), "{e}");
}

#[test]
fn index_out_of_range_is_an_error() {
    let e = err(&fast(
        &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[&[0, 1, 3]],
    ));
    assert!(
        e.contains("face 0: vertex index 3 is out of range (the file has 3 vertices)"),
        "{e}"
    );
    let e = err(&fast(
        &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[&[0, -1, 2]],
    ));
    assert!(e.contains("vertex index -1 is out of range"), "{e}");
    // The byte offset is that of the bad index: header + 36 vertex bytes + count byte + 4.
    let b = fast(
        &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[&[0, -1, 2]],
    );
    let header_len = b.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    assert!(
        e.contains(&format!("at byte {}", header_len + 36 + 1 + 4)),
        "{e}"
    );
    let text = String::from_utf8(ascii())
        .unwrap()
        .replace("3 0 1 4 9", "3 0 1 5 9");
    let e = err(text.as_bytes());
    assert!(
        e.contains("test.ply:22: face 1: vertex index 5 is out of range"),
        "{e}"
    );
}

#[test]
fn nan_and_infinite_coordinates_are_errors() {
    let e = err(&fast(
        &[[0.0; 3], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[&[0, 1, 2]],
    ));
    assert!(
        e.contains("vertex 1 has a coordinate that is not a finite number"),
        "{e}"
    );
    let text = String::from_utf8(ascii())
        .unwrap()
        .replace("1 1 0 0 0 1 255", "1 inf 0 0 0 1 255");
    let e = err(text.as_bytes());
    assert!(
        e.contains("test.ply:18: vertex 2 has a coordinate that is not a finite number"),
        "{e}"
    );
    let e = err(&binary(true)
        .iter()
        .enumerate()
        .map(|(i, &b)| {
            // Overwrite vertex 0's x (first 8 bytes after the header) with a big-endian NaN.
            let h = binary(true)
                .windows(11)
                .position(|w| w == b"end_header\n")
                .unwrap()
                + 11;
            if i >= h && i < h + 8 {
                f64::NAN.to_be_bytes()[i - h]
            } else {
                b
            }
        })
        .collect::<Vec<u8>>());
    assert!(
        e.contains("vertex 0 has a coordinate that is not a finite number"),
        "{e}"
    );
}

#[test]
fn unknown_property_type_names_the_header_line() {
    let text = String::from_utf8(ascii())
        .unwrap()
        .replace("property uchar red", "property quad red");
    let e = err(text.as_bytes());
    assert!(
        e.contains("test.ply:11: unknown property type `quad`"),
        "{e}"
    );
}

#[test]
fn missing_vertex_element_or_coordinates_are_errors() {
    let e = err(b"ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n");
    // Header problems are placed at their header line: `end_header`, or the element's line.
    assert!(e.starts_with("test.ply:5: "), "{e}");
    assert!(e.contains("declares no `vertex` element"), "{e}");
    let e = err(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n");
    assert!(
        e.starts_with("test.ply:3: the `vertex` element has no `z` property"),
        "{e}"
    );
    let e = err(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty int n\nend_header\n0 0 0\n1\n");
    assert!(
        e.starts_with("test.ply:7: the `face` element has no `vertex_indices`"),
        "{e}"
    );
    let e = err(b"ply\nelement vertex 0\nproperty float x\nend_header\n");
    assert!(
        e.starts_with("test.ply:4: the PLY header has no `format` line"),
        "{e}"
    );
    let e = err(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n");
    assert!(e.contains("no `end_header`"), "{e}");
    let e = err(b"plx\n");
    assert!(e.contains("not a PLY file"), "{e}");
}

#[test]
fn a_mesh_without_triangles_is_refused_by_load_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("empty.ply");
    std::fs::write(&p, b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap();
    let e = load_mesh(&p).unwrap_err().to_string();
    assert!(e.contains("empty.ply") && e.contains("no triangles"), "{e}");
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn shared_igea_scan_loads_if_present() {
    let p = appel_testdata::path("common-3d-test-models/igea.ply.gz");
    let m = load_mesh(&p).unwrap();
    assert!(m.triangle_count() > 1000, "{}", m.triangle_count());
    assert!(!m.bounds().is_empty());
}

#[test]
fn triangle_strips_alternate_winding_and_restart_at_minus_one() {
    let text = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 2 0\n8 0 1 2 3 -1 3 2 4\n";
    let m = parse(text.as_bytes()).unwrap();
    assert_eq!(
        m.parts[0].mesh.indices,
        vec![[0, 1, 2], [2, 1, 3], [3, 2, 4]]
    );
}
