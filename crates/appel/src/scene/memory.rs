//! How much memory a scene will need, estimated from its description and its mesh files' headers
//! before anything large is loaded, so that a scene too large for the machine fails at once with
//! a clear message instead of being killed by the kernel half-way through a long build.

use crate::description::{Description, ShapeDesc};
use crate::error::Result;
use crate::io::mesh_file::MeshFormat;
use crate::io::ply::read_ply_counts;
use std::path::Path;

/// Bytes per stored triangle besides its vertices: the index triple (12) and the finished 8-wide
/// BVH with its triangle blocks (56, above what docs/performance.md records for large meshes, so
/// that the estimate errs high). A mesh's triangles have no reference
/// each in the scene's primitive list (one run per mesh, `scene::PrimRefs`).
const PER_TRIANGLE: u64 = 12 + 56;
/// Per vertex: position, normal and texture coordinates (assumed present: an upper bound).
const PER_VERTEX: u64 = 12 + 12 + 8;
/// The BVH builder's scratch, per primitive of the structure being built (bounds and indices,
/// docs/accel.md); one structure is built at a time, so only the largest counts.
const BUILD_SCRATCH: u64 = 40;
/// Per instance: its two affine maps and ids (144), its share of the top-level BVH (36), and its
/// parsed placement (72) while the instances are made.
const PER_INSTANCE: u64 = 144 + 36 + 72;
/// Per pixel: the film (RGB, depth, normal, three ids: 44) and the finished tiles before they are
/// copied into it (another 44).
const PER_PIXEL: u64 = 88;

/// The estimate and what it was made of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Triangles stored (each instanced mesh once).
    pub triangles: u64,
    pub instances: u64,
    pub pixels: u64,
    pub bytes: u64,
}

/// Triangles and vertices of a mesh file, from its header (PLY) or its size (other formats: about
/// one triangle per 24 bytes of file, which over-counts for text formats).
fn mesh_counts(path: &Path) -> Result<(u64, u64)> {
    // A zip archive: its size, as for a compressed file (about 5:1 for mesh text).
    if let Some(a) = crate::io::assets::archive_path(path) {
        let size = std::fs::metadata(&a.archive)
            .map_err(|e| crate::error::Error::io(&a.archive, e))?
            .len();
        return Ok((5 * size / 24, 5 * size / 48));
    }
    match MeshFormat::from_path(path) {
        Some((MeshFormat::Ply, _)) => {
            let c = read_ply_counts(path)?;
            Ok((c.faces, c.vertices))
        }
        _ => {
            let size = std::fs::metadata(path)
                .map_err(|e| crate::error::Error::io(path, e))?
                .len();
            let gz = if path.extension().is_some_and(|e| e == "gz") {
                5
            } else {
                1
            };
            Ok((gz * size / 24, gz * size / 48))
        }
    }
}

/// Placements in a list: its lines, counted without parsing them (an upper bound: comments and
/// blank lines count too).
fn placement_count(path: &Path) -> Result<u64> {
    use std::io::Read;
    let mut file = std::fs::File::open(path).map_err(|e| crate::error::Error::io(path, e))?;
    let mut buf = vec![0u8; 1 << 20];
    let mut lines = 1;
    loop {
        let n = file
            .read(&mut buf)
            .map_err(|e| crate::error::Error::io(path, e))?;
        if n == 0 {
            return Ok(lines);
        }
        lines += buf[..n].iter().filter(|&&b| b == b'\n').count() as u64;
    }
}

/// Estimates the peak memory of loading, building and rendering `d` (files relative to
/// `base_dir`). Errors only when a file cannot be read.
pub fn estimate_memory(d: &Description, base_dir: &Path) -> Result<MemoryEstimate> {
    // An animation holds one frame at a time: its first stands for all.
    let first_frame;
    let d = if crate::description::animation::is_animated(d) {
        first_frame = crate::description::animation::at_frame(d, 0);
        &first_frame
    } else {
        d
    };
    let mut e = MemoryEstimate {
        pixels: d.camera.width as u64 * d.camera.height as u64,
        ..Default::default()
    };
    let mut bytes = e.pixels * PER_PIXEL;
    let mut top_level = 0u64;
    let mut largest_structure = 0u64;
    for s in &d.shapes {
        let (t, v) = match s {
            ShapeDesc::Mesh(m) => mesh_counts(&base_dir.join(&m.file))?,
            ShapeDesc::TriangleMesh(m) => (m.indices.len() as u64, m.positions.len() as u64),
            _ => (1, 3),
        };
        e.triangles += t;
        top_level += t;
        bytes += t * PER_TRIANGLE + v * PER_VERTEX;
    }
    for (name, m) in &d.meshes {
        if d.instances.iter().any(|i| &i.mesh == name) {
            let (t, v) = if m.file.is_empty() {
                m.triangles.iter().fold((0, 0), |(t, v), x| {
                    (t + x.indices.len() as u64, v + x.positions.len() as u64)
                })
            } else {
                mesh_counts(&base_dir.join(&m.file))?
            };
            e.triangles += t;
            largest_structure = largest_structure.max(t);
            bytes += t * PER_TRIANGLE + v * PER_VERTEX;
        }
    }
    for i in &d.instances {
        e.instances += match &i.placements {
            Some(f) => placement_count(&base_dir.join(f))?,
            None => 1,
        };
    }
    top_level += e.instances;
    largest_structure = largest_structure.max(top_level);
    bytes += e.instances * PER_INSTANCE + largest_structure * BUILD_SCRATCH;
    e.bytes = bytes;
    Ok(e)
}
