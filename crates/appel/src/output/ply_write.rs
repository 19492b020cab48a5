//! Writing triangle meshes as binary little-endian PLY: the fastest format Appel reads back, and the
//! form in which `appel convert` hands a scene's triangles, in Appel's own order, to other tools.

use super::write_atomically;
use crate::error::{Error, Result};
use crate::geometry::TriangleMesh;
use std::io::Write;
use std::path::Path;

/// Writes the meshes as one PLY, in order. The header records where each mesh's triangles start as
/// `comment appel shape <shape id> <first triangle> <triangle count>`, so a reader can map a global
/// triangle index back to Appel's (`shapeid`, `primid`).
pub fn write_ply(path: &Path, meshes: &[(u32, &TriangleMesh)]) -> Result<()> {
    let vertices: usize = meshes.iter().map(|(_, m)| m.positions.len()).sum();
    let triangles: usize = meshes.iter().map(|(_, m)| m.triangle_count()).sum();
    let io = |e: std::io::Error| Error::io(path, e);
    write_atomically(path, |out| {
        writeln!(
            out,
            "ply\nformat binary_little_endian 1.0\ncomment written by appel"
        )
        .map_err(io)?;
        let mut first = 0;
        for (shape, m) in meshes {
            writeln!(
                out,
                "comment appel shape {shape} {first} {}",
                m.triangle_count()
            )
            .map_err(io)?;
            first += m.triangle_count();
        }
        writeln!(
            out,
            "element vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\n\
             element face {triangles}\nproperty list uchar int vertex_indices\nend_header"
        )
        .map_err(io)?;
        for (_, m) in meshes {
            for p in &m.positions {
                for c in p.to_array() {
                    out.write_all(&c.to_le_bytes()).map_err(io)?;
                }
            }
        }
        let mut base = 0u32;
        for (_, m) in meshes {
            for tri in &m.indices {
                out.write_all(&[3]).map_err(io)?;
                for i in tri {
                    out.write_all(&((i + base) as i32).to_le_bytes())
                        .map_err(io)?;
                }
            }
            base += m.positions.len() as u32;
        }
        Ok(())
    })
}
