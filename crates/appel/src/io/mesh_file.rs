//! Triangle meshes from files: the common result type and the entry point that picks a reader by the
//! file's extension (`.ply`, `.obj`, `.gltf`, `.glb`, and `.ply.gz` / `.obj.gz`).

use crate::error::{Error, Location, Result};
use crate::geometry::TriangleMesh;
use crate::math::{Aabb, Vec3};
use glam::{Mat3, Mat4};
use std::io::Read;
use std::path::Path;

/// A material as a mesh file states it, before it is mapped onto Appel's model (see
/// `docs/meshes.md`): OBJ's MTL `Kd Ks Ns Ni d`, or glTF's base colour factor.
#[derive(Clone, Debug, PartialEq)]
pub struct FileMaterial {
    pub name: String,
    /// Diffuse colour (MTL `Kd`, glTF `baseColorFactor` rgb), linear RGB.
    pub diffuse: [f32; 3],
    /// Specular colour (MTL `Ks`).
    pub specular: [f32; 3],
    /// Phong exponent (MTL `Ns`).
    pub shininess: f32,
    /// Index of refraction (MTL `Ni`).
    pub ior: f32,
    /// Opacity (MTL `d`, glTF base colour alpha); 1 is opaque.
    pub opacity: f32,
}

impl Default for FileMaterial {
    fn default() -> Self {
        Self {
            name: String::new(),
            diffuse: [0.8, 0.8, 0.8],
            specular: [0.0; 3],
            shininess: 32.0,
            ior: 1.5,
            opacity: 1.0,
        }
    }
}

/// One group of triangles sharing a material. `primid` of a hit is the triangle's index inside its
/// part, in the order the file lists that part's faces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshPart {
    pub mesh: TriangleMesh,
    /// Index into [`LoadedMesh::materials`], or `None` for the scene's default.
    pub material: Option<u32>,
    /// For each triangle of the part, its index among all the file's triangles in the file's order,
    /// where a reader regrouped them (OBJ groups faces by material). `None`: the parts hold the
    /// file's triangles in order, one part after the other.
    pub file_triangles: Option<Vec<u32>>,
}

/// Everything read from one mesh file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadedMesh {
    pub parts: Vec<MeshPart>,
    pub materials: Vec<FileMaterial>,
    /// Meshes the file places more than once (glTF nodes sharing a mesh), stored once in their own
    /// object space.
    pub shared: Vec<Vec<MeshPart>>,
    /// Where each shared mesh is placed, in the file's node order.
    pub placements: Vec<SharedPlacement>,
    /// Named per-vertex and per-triangle values (PLY's extra properties) of a file read as one
    /// part; textures read them by name (Mitsuba's `mesh_attribute`).
    pub attributes: Vec<MeshAttribute>,
}

/// Values given per vertex (interpolated over triangles) or per triangle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshAttribute {
    pub name: String,
    pub per_face: bool,
    pub channels: usize,
    /// `channels` values per vertex or per triangle.
    pub data: Vec<f32>,
}

/// One placement of a shared mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SharedPlacement {
    /// Index into [`LoadedMesh::shared`].
    pub mesh: u32,
    pub to_world: Mat4,
    /// Index, in the file's order, of the placement's first triangle: its triangles number on
    /// from there, as if the mesh had been copied.
    pub first_triangle: u32,
}

impl LoadedMesh {
    /// Triangles in the parts (not counting shared meshes).
    pub fn parts_triangles(&self) -> u32 {
        self.parts
            .iter()
            .map(|p| p.mesh.triangle_count() as u32)
            .sum()
    }

    /// Triangles stored: the parts, and each shared mesh once.
    pub fn triangle_count(&self) -> usize {
        let shared: usize = self
            .shared
            .iter()
            .flatten()
            .map(|p| p.mesh.triangle_count())
            .sum();
        self.parts
            .iter()
            .map(|p| p.mesh.triangle_count())
            .sum::<usize>()
            + shared
    }

    pub fn bounds(&self) -> Aabb {
        let placed = self.placements.iter().fold(Aabb::EMPTY, |b, pl| {
            self.shared[pl.mesh as usize].iter().fold(b, |b, part| {
                part.mesh
                    .positions
                    .iter()
                    .fold(b, |b, &p| b.include(pl.to_world.transform_point3(p)))
            })
        });
        self.parts
            .iter()
            .fold(placed, |b, p| b.union(p.mesh.bounds()))
    }

    /// The same triangles with every placement of a shared mesh copied into the parts, for tools
    /// that need one flat list (the scene keeps shared meshes as instances).
    pub fn flattened(mut self) -> LoadedMesh {
        for p in std::mem::take(&mut self.placements) {
            for part in &self.shared[p.mesh as usize] {
                let mut part = part.clone();
                transform_mesh(&mut part.mesh, p.to_world);
                let n = part.mesh.triangle_count() as u32;
                part.file_triangles = Some((p.first_triangle..p.first_triangle + n).collect());
                self.parts.push(part);
            }
        }
        self.shared.clear();
        self
    }

    /// Applies an affine transform: positions by `m`, normals by the inverse transpose of its linear
    /// part (so they stay perpendicular to the surface under non-uniform scaling), renormalised.
    pub fn transform(&mut self, m: Mat4) {
        for part in &mut self.parts {
            transform_mesh(&mut part.mesh, m);
        }
        for p in &mut self.placements {
            p.to_world = m * p.to_world;
        }
    }
}

pub(crate) fn transform_mesh(mesh: &mut TriangleMesh, m: Mat4) {
    if m == Mat4::IDENTITY {
        return;
    }
    for p in &mut mesh.positions {
        *p = m.transform_point3(*p);
    }
    let normal_matrix = Mat3::from_mat4(m).inverse().transpose();
    // A mirroring transform flips the winding, and with it the geometric normal; swapping two indices
    // keeps "counter-clockwise seen from outside" true.
    let flips = Mat3::from_mat4(m).determinant() < 0.0;
    if flips {
        for t in &mut mesh.indices {
            t.swap(1, 2);
        }
    }
    if let Some(ns) = &mut mesh.normals {
        for n in ns {
            *n = (normal_matrix * *n).normalize_or_zero();
        }
    }
}

/// Mesh formats by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    Ply,
    Obj,
    Gltf,
}

impl MeshFormat {
    /// The format of a file name and whether it is gzip-compressed, or `None` if it is no mesh file.
    pub fn from_path(path: &Path) -> Option<(MeshFormat, bool)> {
        let name = path.file_name()?.to_str()?.to_ascii_lowercase();
        let (stem, gz) = match name.strip_suffix(".gz") {
            Some(s) => (s.to_string(), true),
            None => (name, false),
        };
        let ext = stem.rsplit_once('.')?.1;
        let format = match ext {
            "ply" => MeshFormat::Ply,
            "obj" => MeshFormat::Obj,
            "gltf" | "glb" if !gz => MeshFormat::Gltf,
            _ => return None,
        };
        Some((format, gz))
    }
}

/// Whether `path` names a mesh file Appel can read (by its extension).
pub fn is_mesh_file(path: &Path) -> bool {
    MeshFormat::from_path(path).is_some()
}

/// Reads a mesh file. Errors name the file and the line (text formats) or byte offset (binary; for
/// `.gz` files the offset is into the decompressed data). A file without triangles is an error.
pub fn load_mesh(path: &Path) -> Result<LoadedMesh> {
    let (format, gz) = MeshFormat::from_path(path).ok_or_else(|| {
        Error::input(
            Location::file(path),
            "unknown mesh file extension: expected .ply, .obj, .gltf, .glb, .ply.gz or .obj.gz",
        )
    })?;
    let loaded = match (format, gz) {
        (MeshFormat::Ply, false) => {
            let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
            let len = file.metadata().map_err(|e| Error::io(path, e))?.len();
            if len == 0 {
                super::ply::parse_ply(&[], path)?
            } else {
                // SAFETY: the map is read-only and private to this call. Another process truncating
                // the file while we read it would fault (SIGBUS); that is the documented price of
                // mapping, paid for load speed on large scans.
                let map = unsafe { memmap2::Mmap::map(&file) }.map_err(|e| Error::io(path, e))?;
                super::ply::parse_ply(&map, path)?
            }
        }
        (MeshFormat::Ply, true) => super::ply::parse_ply(&read_gz(path)?, path)?,
        (MeshFormat::Obj, gz) => {
            let bytes = if gz {
                read_gz(path)?
            } else {
                std::fs::read(path).map_err(|e| Error::io(path, e))?
            };
            super::obj::parse_obj(&bytes, path, &super::obj::FsMtl)?
        }
        (MeshFormat::Gltf, _) => {
            let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
            super::gltf::parse_gltf(&bytes, path)?
        }
    };
    check_not_empty(loaded, path)
}

pub(crate) fn check_not_empty(loaded: LoadedMesh, path: &Path) -> Result<LoadedMesh> {
    if loaded.triangle_count() == 0 {
        return Err(Error::input(
            Location::file(path),
            "the mesh has no triangles: nothing to render",
        ));
    }
    Ok(loaded)
}

fn read_gz(path: &Path) -> Result<Vec<u8>> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(std::io::BufReader::new(file))
        .read_to_end(&mut out)
        .map_err(|e| {
            Error::input(
                Location::file(path),
                format!("cannot decompress gzip data: {e}"),
            )
        })?;
    Ok(out)
}

/// Positions must be finite: a NaN or infinite vertex would poison bounds and the acceleration
/// structure. Returns the index of the first bad one.
pub(crate) fn first_non_finite(positions: &[Vec3]) -> Option<usize> {
    positions.iter().position(|p| !p.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_pick_the_format() {
        let f = |s: &str| MeshFormat::from_path(Path::new(s));
        assert_eq!(f("a/b.PLY"), Some((MeshFormat::Ply, false)));
        assert_eq!(f("bunny.obj.gz"), Some((MeshFormat::Obj, true)));
        assert_eq!(f("x.glb"), Some((MeshFormat::Gltf, false)));
        assert_eq!(f("x.gltf.gz"), None);
        assert_eq!(f("scene.toml"), None);
        assert_eq!(f("noext"), None);
    }

    #[test]
    fn mirroring_transform_keeps_the_geometric_normal_outward() {
        let mut mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![[0, 1, 2]],
            normals: Some(vec![Vec3::Z; 3]),
            uvs: None,
        };
        transform_mesh(&mut mesh, Mat4::from_scale(Vec3::new(1.0, 1.0, -2.0)));
        let [a, b, c] = mesh.vertices(0);
        let n = (b - a).cross(c - a).normalize();
        assert_eq!(n, -Vec3::Z);
        assert_eq!(mesh.normals.unwrap()[0], -Vec3::Z);
    }

    #[test]
    fn normals_use_the_inverse_transpose() {
        // A 45-degree slope stretched 2x in x: the normal must stay perpendicular to the surface.
        let mut mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Z],
            indices: vec![[0, 1, 2]],
            normals: Some(vec![Vec3::new(1.0, -1.0, 0.0).normalize(); 3]),
            uvs: None,
        };
        transform_mesh(&mut mesh, Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)));
        let edge = mesh.positions[1] - mesh.positions[0];
        let n = mesh.normals.unwrap()[0];
        assert!(edge.dot(n).abs() < 1e-6, "{edge} . {n}");
        assert!((n.length() - 1.0).abs() < 1e-6);
    }
}
