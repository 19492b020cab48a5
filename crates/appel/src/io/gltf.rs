//! glTF 2.0 (`.gltf` with external or data-URI buffers, and binary `.glb`) through the `gltf` crate.
//!
//! Every triangle-mode primitive of every mesh instanced in the default scene (or the first scene,
//! or every root node if the file has no scene) becomes one part, transformed by its node's world
//! matrix. A mesh that several nodes place is read once, into [`LoadedMesh::shared`], and each
//! node becomes a placement of it (an instance in the scene) instead of a copy. Its material's base colour factor becomes the part's diffuse colour (alpha -> opacity);
//! textures are not read. Buffers are loaded here rather than by `gltf::import`, so that a missing
//! `.bin` gives an error naming it, and no image decoder is pulled in.
//!
//! The `gltf` crate's accessor readers slice and index without checking that an accessor fits its
//! buffer or has the expected type (they assume validated data), so every accessor is checked here
//! before it is read.

use super::mesh_file::{transform_mesh, FileMaterial, LoadedMesh, MeshPart, SharedPlacement};
use crate::error::{Error, Location, Result};
use crate::geometry::TriangleMesh;
use crate::math::{Vec2, Vec3};
use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::mesh::Mode;
use ::gltf::{Accessor, Gltf, Node};
use base64::Engine;
use glam::Mat4;
use std::collections::HashMap;
use std::path::Path;

/// Deeper node hierarchies are refused: real files are a few levels deep, and a cycle (which the
/// `gltf` crate's validation does not catch) would otherwise recurse forever.
const MAX_DEPTH: usize = 256;

/// External buffers are read from files relative to the glTF file.
pub fn parse_gltf(data: &[u8], path: &Path) -> Result<LoadedMesh> {
    parse_gltf_with(data, path, &|uri| {
        let file = path.parent().unwrap_or(Path::new(".")).join(uri);
        std::fs::read(&file).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                format!("the buffer file `{}` does not exist", file.display())
            } else {
                format!("cannot read the buffer file `{}`: {e}", file.display())
            }
        })
    })
}

/// `external(uri)` supplies a buffer that is neither embedded nor a data URI.
pub fn parse_gltf_with(
    data: &[u8],
    path: &Path,
    external: &dyn Fn(&str) -> std::result::Result<Vec<u8>, String>,
) -> Result<LoadedMesh> {
    let err = |msg: String| Error::input(Location::file(path), msg);
    let raw =
        Gltf::from_slice_without_validation(data).map_err(|e| err(format!("invalid glTF: {e}")))?;
    // gltf-json 1.4's validation indexes `accessors[POSITION]` without a bounds check (found by
    // fuzzing): check that reference before letting it validate the rest.
    let json = raw.document.as_json();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= json.accessors.len() {
                    return Err(err(format!(
                        "invalid glTF: mesh {m} primitive {p}: attribute {semantic:?} refers to accessor {}, but there are {}",
                        index.value(),
                        json.accessors.len()
                    )));
                }
            }
        }
    }
    let gltf = Gltf {
        document: ::gltf::Document::from_json(raw.document.into_json())
            .map_err(|e| err(format!("invalid glTF: {e}")))?,
        blob: raw.blob,
    };
    let mut buffers: Vec<Vec<u8>> = Vec::new();
    for b in gltf.document.buffers() {
        let bytes = match b.source() {
            ::gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                err(format!(
                    "buffer {} refers to the GLB binary chunk, which the file does not have",
                    b.index()
                ))
            })?,
            ::gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let (_, payload) = rest.split_once(";base64,").ok_or_else(|| {
                        err(format!(
                            "buffer {}: only base64 data URIs are supported",
                            b.index()
                        ))
                    })?;
                    base64::engine::general_purpose::STANDARD
                        .decode(payload)
                        .map_err(|e| err(format!("buffer {}: bad base64 data: {e}", b.index())))?
                } else if uri.contains("://") {
                    return Err(err(format!(
                        "buffer {}: `{uri}` is not a local file; only relative paths and data URIs are supported",
                        b.index()
                    )));
                } else {
                    external(&percent_decode(uri))
                        .map_err(|m| err(format!("buffer {} (`{uri}`): {m}", b.index())))?
                }
            }
        };
        if bytes.len() < b.length() {
            return Err(err(format!(
                "buffer {} holds {} bytes but the file declares {}",
                b.index(),
                bytes.len(),
                b.length()
            )));
        }
        buffers.push(bytes);
    }

    let mut out = LoadedMesh::default();
    let mut material_ids: HashMap<Option<usize>, Option<u32>> = HashMap::new();
    let roots: Vec<Node> = match gltf
        .document
        .default_scene()
        .or_else(|| gltf.document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            let children: std::collections::HashSet<usize> = gltf
                .document
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()).collect::<Vec<_>>())
                .collect();
            gltf.document
                .nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    };
    let mut uses: HashMap<usize, usize> = HashMap::new();
    for node in &roots {
        count_mesh_uses(node, &mut uses, 0);
    }
    let mut ctx = Ctx {
        path,
        buffers: &buffers,
        out: &mut out,
        material_ids: &mut material_ids,
        uses: &uses,
        shared_index: HashMap::new(),
        triangles: 0,
    };
    for node in roots {
        ctx.node(&node, Mat4::IDENTITY, 0)?;
    }
    Ok(out)
}

/// How many nodes under `node` place each mesh (cycles end at the depth limit, which `node`
/// then reports as an error).
fn count_mesh_uses(node: &Node, uses: &mut HashMap<usize, usize>, depth: usize) {
    if depth > MAX_DEPTH {
        return;
    }
    if let Some(m) = node.mesh() {
        *uses.entry(m.index()).or_default() += 1;
    }
    for child in node.children() {
        count_mesh_uses(&child, uses, depth + 1);
    }
}

struct Ctx<'a> {
    path: &'a Path,
    buffers: &'a [Vec<u8>],
    out: &'a mut LoadedMesh,
    material_ids: &'a mut HashMap<Option<usize>, Option<u32>>,
    /// Nodes placing each mesh: meshes placed more than once are shared.
    uses: &'a HashMap<usize, usize>,
    /// Index in `out.shared` of each shared mesh read so far.
    shared_index: HashMap<usize, u32>,
    /// Triangles so far in the file's order (placements of shared meshes included).
    triangles: u32,
}

impl Ctx<'_> {
    fn err(&self, msg: String) -> Error {
        Error::input(Location::file(self.path), msg)
    }

    fn node(&mut self, node: &Node, parent: Mat4, depth: usize) -> Result<()> {
        if depth > MAX_DEPTH {
            return Err(self.err(format!(
                "node {}: the node hierarchy is deeper than {MAX_DEPTH} levels (is there a cycle?)",
                node.index()
            )));
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let world = parent * local;
        if !world.is_finite() {
            return Err(self.err(format!(
                "node {}: its transform is not finite",
                node.index()
            )));
        }
        if let Some(mesh) = node.mesh().filter(|m| self.uses.get(&m.index()) > Some(&1)) {
            let index = match self.shared_index.get(&mesh.index()) {
                Some(&i) => i,
                None => {
                    let mut parts = vec![];
                    for prim in mesh.primitives() {
                        if prim.mode() != Mode::Triangles {
                            continue;
                        }
                        let what = format!("mesh {} primitive {}", mesh.index(), prim.index());
                        let tm = self.primitive(&prim, &what)?;
                        let material = self.material(&prim.material());
                        parts.push(MeshPart {
                            mesh: tm,
                            material,
                            file_triangles: None,
                        });
                    }
                    self.out.shared.push(parts);
                    let i = self.out.shared.len() as u32 - 1;
                    self.shared_index.insert(mesh.index(), i);
                    i
                }
            };
            let count: usize = self.out.shared[index as usize]
                .iter()
                .map(|p| p.mesh.triangle_count())
                .sum();
            self.out.placements.push(SharedPlacement {
                mesh: index,
                to_world: world,
                first_triangle: self.triangles,
            });
            self.triangles += count as u32;
        } else if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                if prim.mode() != Mode::Triangles {
                    continue;
                }
                let what = format!("mesh {} primitive {}", mesh.index(), prim.index());
                let mut tm = self.primitive(&prim, &what)?;
                transform_mesh(&mut tm, world);
                if !tm.positions.iter().all(|p| p.is_finite()) {
                    return Err(
                        self.err(format!("{what}: a vertex position is not a finite number"))
                    );
                }
                let material = self.material(&prim.material());
                // Parts number their triangles from where they stand in the file's order, which
                // placements of shared meshes may interleave.
                let count = tm.triangle_count() as u32;
                let file_triangles = (self.triangles != self.out.parts_triangles())
                    .then(|| (self.triangles..self.triangles + count).collect());
                self.out.parts.push(MeshPart {
                    mesh: tm,
                    material,
                    file_triangles,
                });
                self.triangles += count;
            }
        }
        for child in node.children() {
            self.node(&child, world, depth + 1)?;
        }
        Ok(())
    }

    fn material(&mut self, m: &::gltf::Material) -> Option<u32> {
        if let Some(&id) = self.material_ids.get(&m.index()) {
            return id;
        }
        // A primitive without a material uses the scene's default.
        let id = m.index().map(|i| {
            let [r, g, b, a] = m.pbr_metallic_roughness().base_color_factor();
            self.out.materials.push(FileMaterial {
                name: m
                    .name()
                    .map_or_else(|| format!("material {i}"), str::to_string),
                diffuse: [r, g, b],
                opacity: a,
                ..Default::default()
            });
            self.out.materials.len() as u32 - 1
        });
        self.material_ids.insert(m.index(), id);
        id
    }

    /// Checks that `a` has one of the allowed element types and lies inside its buffer, so that the
    /// `gltf` crate's reader can neither panic nor read garbage.
    fn check(&self, a: &Accessor, allowed: &[(Dimensions, DataType)], what: &str) -> Result<()> {
        let fail = |m: String| self.err(format!("{what}: accessor {}: {m}", a.index()));
        if !allowed.contains(&(a.dimensions(), a.data_type())) {
            return Err(fail(format!(
                "unsupported element type {:?} of {:?}",
                a.dimensions(),
                a.data_type()
            )));
        }
        if a.sparse().is_some() {
            return Err(fail("sparse accessors are not supported".into()));
        }
        let Some(view) = a.view() else {
            return Err(fail("it has no buffer view".into()));
        };
        if a.count() == 0 {
            return Err(fail("it has no elements".into()));
        }
        let size = a.size();
        let stride = view.stride().unwrap_or(size);
        if stride < size {
            return Err(fail(format!(
                "byte stride {stride} is smaller than an element ({size} bytes)"
            )));
        }
        let buffer_len = self.buffers.get(view.buffer().index()).map_or(0, Vec::len);
        let view_end = view.offset().checked_add(view.length());
        let need = (a.count() - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(size))
            .and_then(|x| x.checked_add(a.offset()));
        match (view_end, need) {
            (Some(end), Some(need)) if end <= buffer_len && need <= view.length() => Ok(()),
            _ => Err(fail(format!(
                "its data does not fit in buffer view {} (offset {}, {} bytes) of a {buffer_len}-byte buffer",
                view.index(),
                view.offset(),
                view.length()
            ))),
        }
    }

    fn primitive(&self, prim: &::gltf::Primitive, what: &str) -> Result<TriangleMesh> {
        use DataType::{F32, U16, U32, U8};
        use Dimensions::Scalar;
        let (vec2, vec3) = (Dimensions::Vec2, Dimensions::Vec3);
        let buffers = self.buffers;
        let reader = prim.reader(|b| buffers.get(b.index()).map(|v| v.as_slice()));
        let pos_acc = prim
            .get(&::gltf::Semantic::Positions)
            .ok_or_else(|| self.err(format!("{what}: no POSITION attribute")))?;
        self.check(&pos_acc, &[(vec3, F32)], &format!("{what} POSITION"))?;
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| self.err(format!("{what}: cannot read POSITION")))?
            .map(Vec3::from)
            .collect();
        let nv = positions.len();
        if nv > u32::MAX as usize {
            return Err(self.err(format!("{what}: too many vertices")));
        }
        let normals = match prim.get(&::gltf::Semantic::Normals) {
            Some(a) if a.count() == nv => {
                self.check(&a, &[(vec3, F32)], &format!("{what} NORMAL"))?;
                reader
                    .read_normals()
                    .map(|it| it.map(Vec3::from).collect::<Vec<_>>())
            }
            _ => None,
        };
        let uvs = match prim.get(&::gltf::Semantic::TexCoords(0)) {
            Some(a) if a.count() == nv => {
                self.check(
                    &a,
                    &[(vec2, F32), (vec2, U8), (vec2, U16)],
                    &format!("{what} TEXCOORD_0"),
                )?;
                reader
                    .read_tex_coords(0)
                    .map(|it| it.into_f32().map(Vec2::from).collect::<Vec<_>>())
            }
            _ => None,
        };
        let flat: Vec<u32> = match prim.indices() {
            Some(a) => {
                self.check(
                    &a,
                    &[(Scalar, U8), (Scalar, U16), (Scalar, U32)],
                    &format!("{what} indices"),
                )?;
                let idx: Vec<u32> = reader
                    .read_indices()
                    .ok_or_else(|| self.err(format!("{what}: cannot read the indices")))?
                    .into_u32()
                    .collect();
                if let Some(bad) = idx.iter().find(|&&i| i as usize >= nv) {
                    return Err(self.err(format!(
                        "{what}: vertex index {bad} is out of range ({nv} vertices)"
                    )));
                }
                idx
            }
            None => (0..nv as u32).collect(),
        };
        Ok(TriangleMesh {
            positions,
            indices: flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
            normals,
            uvs,
        })
    }
}

/// `%20` and friends in relative URIs.
fn percent_decode(uri: &str) -> String {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        if b[i] == b'%' && i + 2 < b.len() {
            if let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}
