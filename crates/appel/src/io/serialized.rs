//! Mitsuba's `.serialized` meshes (the format of Mitsuba 0.6, read by Mitsuba 2 and 3): a little
//! endian header (`0x041C`, version 3 or 4) and then a zlib stream with a flag word, the shape's
//! name (version 4), the vertex and triangle counts (u64), positions, optional normals, uvs and
//! colours (f32 or f64 by flag) and u32 index triples. A file may hold several meshes one after
//! the other, with their offsets at its end; Appel reads the first, Mitsuba's default
//! `shape_index`. Vertex colours are skipped, as Mitsuba skips them. As in Mitsuba 3, a mesh
//! without normals gets smooth ones, angle-weighted (see `vertex_normals`), and the file's
//! face-normals flag is not read: the shape's `face_normals` parameter alone asks for the
//! triangles' own normals (Mitsuba 0.6 honoured the flag; Mitsuba 3 does not).

use crate::description::loaded_mesh::{first_non_finite, LoadedMesh, MeshPart};
use crate::error::{Error, Location, Result};
use crate::geometry::TriangleMesh;
use crate::math::{Vec2, Vec3};
use std::io::Read;
use std::path::Path;

const MAGIC: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_UVS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
/// Set by Mitsuba 0.6's writer for meshes meant to be shaded flat; Mitsuba 3 ignores it.
#[cfg(test)]
const FACE_NORMALS: u32 = 0x0010;
const DOUBLE: u32 = 0x2000;

/// Reads the first mesh of a `.serialized` file. Errors name the file and the byte offset (into the
/// decompressed stream past the 4-byte header for the mesh data).
pub fn parse_serialized(bytes: &[u8], path: &Path) -> Result<LoadedMesh> {
    let fail = |msg: String| Error::input(Location::file(path), msg);
    if bytes.len() < 4 {
        return Err(fail(
            "not a Mitsuba serialized mesh: the file is too short".into(),
        ));
    }
    let magic = u16::from_le_bytes([bytes[0], bytes[1]]);
    let version = u16::from_le_bytes([bytes[2], bytes[3]]);
    if magic != MAGIC {
        return Err(fail(format!(
            "not a Mitsuba serialized mesh: the file starts with {magic:#06x}, not 0x041c"
        )));
    }
    if version != 3 && version != 4 {
        return Err(fail(format!(
            "serialized mesh version {version} is not supported (versions 3 and 4 are)"
        )));
    }
    let mut s = Stream {
        z: flate2::read::ZlibDecoder::new(&bytes[4..]),
        offset: 0,
        path,
    };
    let flags = s.u32()?;
    if version == 4 {
        // The shape's name, NUL-terminated.
        while s.bytes::<1>()?[0] != 0 {}
    }
    let vertex_count = s.u64()?;
    let triangle_count = s.u64()?;
    // Every vertex takes at least 12 bytes and every triangle 12: counts beyond what 4 GiB of
    // decompressed data could hold are corrupt, and would otherwise reserve absurd memory.
    const MAX: u64 = u32::MAX as u64 / 12;
    if vertex_count > MAX || triangle_count > MAX {
        return Err(fail(format!(
            "implausible counts: {vertex_count} vertices, {triangle_count} triangles"
        )));
    }
    let n = vertex_count as usize;
    let double = flags & DOUBLE != 0;
    let positions: Vec<Vec3> = s
        .floats(n * 3, double)?
        .chunks(3)
        .map(Vec3::from_slice)
        .collect();
    let normals = if flags & HAS_NORMALS != 0 {
        let v: Vec<Vec3> = s
            .floats(n * 3, double)?
            .chunks(3)
            .map(Vec3::from_slice)
            .collect();
        Some(v.into_iter().map(|n| n.normalize_or_zero()).collect())
    } else {
        None
    };
    let uvs = if flags & HAS_UVS != 0 {
        Some(
            s.floats(n * 2, double)?
                .chunks(2)
                .map(Vec2::from_slice)
                .collect(),
        )
    } else {
        None
    };
    if flags & HAS_COLORS != 0 {
        s.floats(n * 3, double)?;
    }
    let mut indices = Vec::with_capacity(triangle_count as usize);
    for t in 0..triangle_count {
        let at = s.offset;
        let tri = [s.u32()?, s.u32()?, s.u32()?];
        if tri.iter().any(|&i| i as u64 >= vertex_count) {
            return Err(fail(format!(
                "triangle {t} (decompressed byte {at}) names vertex {} of {vertex_count}",
                tri.iter().max().expect("three")
            )));
        }
        indices.push(tri);
    }
    if let Some(i) = first_non_finite(&positions) {
        return Err(fail(format!("vertex {i} is not finite")));
    }
    let normals =
        normals.unwrap_or_else(|| super::vertex_normals::angle_weighted(&positions, &indices));
    let mesh = TriangleMesh {
        positions,
        indices,
        normals: Some(normals),
        uvs,
    };
    Ok(LoadedMesh {
        parts: vec![MeshPart {
            mesh,
            material: None,
            file_triangles: None,
            tangents: None,
        }],
        ..Default::default()
    })
}

/// The decompressed stream, counting bytes for messages.
struct Stream<'a, R: Read> {
    z: R,
    offset: u64,
    path: &'a Path,
}

impl<R: Read> Stream<'_, R> {
    fn bytes<const N: usize>(&mut self) -> Result<[u8; N]> {
        let mut b = [0u8; N];
        self.z.read_exact(&mut b).map_err(|e| {
            let what = if e.kind() == std::io::ErrorKind::UnexpectedEof {
                "the compressed data ends early".to_string()
            } else {
                format!("cannot decompress: {e}")
            };
            Error::input(
                Location::file(self.path),
                format!("{what} (at decompressed byte {})", self.offset),
            )
        })?;
        self.offset += N as u64;
        Ok(b)
    }

    fn u32(&mut self) -> Result<u32> {
        Ok(u32::from_le_bytes(self.bytes()?))
    }

    fn u64(&mut self) -> Result<u64> {
        Ok(u64::from_le_bytes(self.bytes()?))
    }

    fn floats(&mut self, count: usize, double: bool) -> Result<Vec<f32>> {
        (0..count)
            .map(|_| {
                Ok(if double {
                    f64::from_le_bytes(self.bytes()?) as f32
                } else {
                    f32::from_le_bytes(self.bytes()?)
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// A version-4 file of one triangle with normals and uvs, in single or double precision.
    fn file(double: bool, extra: &[u8]) -> Vec<u8> {
        let flags = HAS_NORMALS | HAS_UVS | if double { DOUBLE } else { 0x1000 };
        file_with(flags, extra)
    }

    fn file_with(flags: u32, extra: &[u8]) -> Vec<u8> {
        let double = flags & DOUBLE != 0;
        let mut body = Vec::new();
        body.extend(flags.to_le_bytes());
        body.extend(b"tri\0");
        body.extend(3u64.to_le_bytes());
        body.extend(1u64.to_le_bytes());
        let mut put = |v: f64| {
            if double {
                body.extend(v.to_le_bytes())
            } else {
                body.extend((v as f32).to_le_bytes())
            }
        };
        for v in [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.0] {
            put(v);
        }
        if flags & HAS_NORMALS != 0 {
            for _ in 0..3 {
                for v in [0.0, 3.0, 4.0] {
                    put(v);
                }
            }
        }
        if flags & HAS_UVS != 0 {
            for v in [0.0, 0.0, 1.0, 0.0, 0.0, 1.0] {
                put(v);
            }
        }
        for i in [0u32, 1, 2] {
            body.extend(i.to_le_bytes());
        }
        body.extend(extra);
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&body).unwrap();
        let mut out = vec![0x1C, 0x04, 4, 0];
        out.extend(z.finish().unwrap());
        out
    }

    #[test]
    fn reads_positions_normals_uvs_in_either_precision() {
        for double in [false, true] {
            let m = parse_serialized(&file(double, &[]), Path::new("t.serialized")).unwrap();
            let mesh = &m.parts[0].mesh;
            assert_eq!(mesh.positions[2], Vec3::new(0.0, 2.0, 0.0));
            assert_eq!(mesh.indices, vec![[0, 1, 2]]);
            let n = mesh.normals.as_ref().unwrap()[1];
            assert!((n - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6, "{n:?}");
            assert_eq!(mesh.uvs.as_ref().unwrap()[1], Vec2::new(1.0, 0.0));
        }
    }

    /// Mitsuba 3 computes smooth vertex normals where the file has none, and reads the file's
    /// normals whatever its face-normals flag says.
    #[test]
    fn normals_are_computed_where_missing_and_the_face_normals_flag_is_ignored() {
        let p = Path::new("t.serialized");
        // The triangle (0,0,0), (1,0,0), (0,2,0) faces +z.
        let m = parse_serialized(&file_with(0x1000, &[]), p).unwrap();
        let mesh = &m.parts[0].mesh;
        assert_eq!(mesh.normals.as_deref(), Some(&[Vec3::Z; 3][..]));
        assert!(mesh.uvs.is_none());
        // The file's normals, (0, 0.6, 0.8), not the triangle's.
        let m = parse_serialized(&file_with(HAS_NORMALS | FACE_NORMALS | 0x1000, &[]), p).unwrap();
        let normals = m.parts[0].mesh.normals.clone().unwrap();
        assert!(normals
            .iter()
            .all(|n| (*n - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6));
    }

    #[test]
    fn bad_files_are_errors_naming_the_problem() {
        let p = Path::new("bad.serialized");
        let err = |b: &[u8]| parse_serialized(b, p).unwrap_err().to_string();
        assert!(err(&[1, 2]).contains("too short"));
        assert!(err(&[0, 0, 4, 0]).contains("not a Mitsuba serialized mesh"));
        assert!(err(&[0x1C, 0x04, 9, 0]).contains("version 9"));
        let good = file(false, &[]);
        // Cut short: the stream ends before the indices.
        let e = err(&good[..good.len() - 8]);
        assert!(e.contains("bad.serialized"), "{e}");
        assert!(err(&[0x1C, 0x04, 4, 0, 1, 2, 3]).contains("decompress"));
    }

    #[test]
    #[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
    fn the_shared_test_mesh_reads_as_its_obj_twin() {
        let dir = appel_testdata::path("mitsuba-data/tests");
        let bytes = std::fs::read(dir.join("serialized/rectangle_normals_uv.serialized")).unwrap();
        let m = parse_serialized(&bytes, Path::new("rectangle_normals_uv.serialized")).unwrap();
        let mesh = &m.parts[0].mesh;
        assert!(mesh.normals.is_some() && mesh.uvs.is_some());
        let obj =
            crate::io::mesh_file::load_mesh(&dir.join("obj/rectangle_normals_uv.obj")).unwrap();
        let area = |m: &TriangleMesh| -> f32 {
            (0..m.triangle_count())
                .map(|t| {
                    let [a, b, c] = m.vertices(t);
                    0.5 * (b - a).cross(c - a).length()
                })
                .sum()
        };
        assert!((area(mesh) - area(&obj.parts[0].mesh)).abs() < 1e-4 * area(mesh));
    }
}
