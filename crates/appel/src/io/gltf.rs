//! glTF 2.0 (`.gltf` with external or data-URI buffers, and binary `.glb`) through the `gltf` crate.
//!
//! Every triangle-mode primitive of every mesh instanced in the default scene (or the first scene,
//! or every root node if the file has no scene) becomes one part, transformed by its node's world
//! matrix. A mesh that several nodes place is read once, into [`LoadedMesh::shared`], and each
//! node becomes a placement of it (an instance in the scene) instead of a copy. Materials are read
//! whole (metallic-roughness, textures with their samplers, texture coordinate sets and
//! `KHR_texture_transform`, alpha modes, and the `KHR_materials_*` extensions listed in
//! `docs/meshes.md`) into [`FileMaterial`]s, whose images are read here and decoded when the scene
//! is built. Lights (`KHR_lights_punctual`) and cameras placed by nodes come out in world space.
//! Buffers and images are loaded here rather than by `gltf::import`, so that a missing `.bin`
//! gives an error naming it (a missing image is a warning: the model renders without it).
//!
//! The `gltf` crate's accessor readers slice and index without checking that an accessor fits its
//! buffer or has the expected type (they assume validated data), so every accessor is checked here
//! before it is read.

use super::assets::Assets;
use super::mikktspace_tangents::mikktspace_tangents;
use crate::description::loaded_mesh::{
    AlphaMode, FileCamera, FileImage, FileMaterial, FileTexture, LoadedMesh, MeshPart, PbrParams,
    SharedPlacement,
};
use crate::description::texture_lookup::{Filter, Wrap};
use crate::description::{CameraDesc, CameraKind};
use crate::error::{Error, Location, Result};
use crate::geometry::TriangleMesh;
use crate::math::{Vec2, Vec3};
use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::mesh::Mode;
use ::gltf::{Accessor, Gltf, Node};
use base64::Engine;
use glam::{Mat3, Mat4, Vec3 as GVec3, Vec4};
use std::collections::HashMap;
use std::path::Path;
use std::path::PathBuf;
use std::sync::Arc;

/// Deeper node hierarchies are refused: real files are a few levels deep, and a cycle (which the
/// `gltf` crate's validation does not catch) would otherwise recurse forever.
const MAX_DEPTH: usize = 256;

/// External buffers and images are read from files relative to the glTF file.
pub fn parse_gltf(data: &[u8], path: &Path) -> Result<LoadedMesh> {
    parse_gltf_from(data, path, &Assets::beside(path))
}

/// External buffers and images come from `assets` (a folder or a zip archive); `path` names the
/// file in messages.
pub fn parse_gltf_from(data: &[u8], path: &Path, assets: &Assets) -> Result<LoadedMesh> {
    parse(data, path, &|uri| assets.read(uri), &|uri| assets.name(uri))
}

/// `external(uri)` supplies a buffer or image that is neither embedded nor a data URI.
pub fn parse_gltf_with(
    data: &[u8],
    path: &Path,
    external: &dyn Fn(&str) -> std::result::Result<Vec<u8>, String>,
) -> Result<LoadedMesh> {
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    parse(data, path, external, &|uri| dir.join(uri))
}

type External<'a> = &'a dyn Fn(&str) -> std::result::Result<Vec<u8>, String>;

/// The file's JSON (of a `.gltf`, or of a `.glb`'s first chunk, with its binary chunk), checked
/// against the specification's schema and references (every index in range), and for what the
/// `gltf` crate would otherwise panic on. Buffers and images are not read.
pub fn read_document(data: &[u8], path: &Path) -> Result<Gltf> {
    let err = |msg: String| Error::input(Location::file(path), msg);
    // Problems of a `.gltf` (text, not a `.glb`'s binary container) are placed at their line.
    let text = !data.starts_with(b"glTF");
    let raw = Gltf::from_slice_without_validation(data).map_err(|e| match &e {
        ::gltf::Error::Deserialize(json) if text && json.line() > 0 => Error::input(
            Location::line(path, json.line(), Some(json.column())),
            format!("invalid glTF: {e}"),
        ),
        _ => err(format!("invalid glTF: {e}")),
    })?;
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
    // Nor does it check what the gltf crate's `Image::source` and `Camera::projection` unwrap
    // (found by fuzzing): an image from a buffer view needs a MIME type, any other a URI; a
    // camera needs the projection its type names.
    for (i, image) in json.images.iter().enumerate() {
        let complete = match image.buffer_view {
            Some(_) => image.mime_type.is_some(),
            None => image.uri.is_some(),
        };
        if !complete {
            return Err(err(format!(
                "invalid glTF: image {i} needs a `uri`, or a `bufferView` with a `mimeType`"
            )));
        }
    }
    for (i, camera) in json.cameras.iter().enumerate() {
        use ::gltf::json::camera::Type;
        use ::gltf::json::validation::Checked;
        let complete = match camera.type_ {
            Checked::Valid(Type::Perspective) => camera.perspective.is_some(),
            Checked::Valid(Type::Orthographic) => camera.orthographic.is_some(),
            Checked::Invalid => false,
        };
        if !complete {
            return Err(err(format!(
                "invalid glTF: camera {i} needs a `type` of \"perspective\" or \"orthographic\" and the object of that name"
            )));
        }
    }
    Ok(Gltf {
        document: ::gltf::Document::from_json(raw.document.into_json()).map_err(|e| match e {
            ::gltf::Error::Validation(problems) => {
                let line = problems.first().and_then(|(at, _)| {
                    let json = std::str::from_utf8(data).ok().filter(|_| text)?;
                    super::json_path::line_of(json, &at.to_string())
                });
                let message = problems
                    .iter()
                    .map(|(at, problem)| format!("`{at}`: {}", problem.to_string().to_lowercase()))
                    .collect::<Vec<_>>()
                    .join("; ");
                let location = match line {
                    Some(line) => Location::line(path, line, None),
                    None => Location::file(path),
                };
                Error::input(location, format!("invalid glTF: {message}"))
            }
            e => err(format!("invalid glTF: {e}")),
        })?,
        blob: raw.blob,
    })
}

fn parse(
    data: &[u8],
    path: &Path,
    external: External,
    namer: &dyn Fn(&str) -> PathBuf,
) -> Result<LoadedMesh> {
    let err = |msg: String| Error::input(Location::file(path), msg);
    let gltf = read_document(data, path)?;
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
    let roots = scene_roots(&gltf.document);
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
        external,
        namer,
        image_ids: HashMap::new(),
        uv_sets: vec![],
        document: &gltf.document,
    };
    for node in roots {
        ctx.node(&node, Mat4::IDENTITY, 0)?;
    }
    out.warnings
        .extend(crate::description::loaded_mesh::unreadable_images(
            &out.images,
        ));
    Ok(out)
}

/// The nodes a file's scene starts from: the default scene's (glTF 2.0 section 3.5.4: `scene`),
/// else the first scene's, else, for a file without scenes, every node that is no node's child.
pub fn scene_roots(document: &::gltf::Document) -> Vec<Node<'_>> {
    match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            let children: std::collections::HashSet<usize> = document
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()).collect::<Vec<_>>())
                .collect();
            document
                .nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    }
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
    external: External<'a>,
    namer: &'a dyn Fn(&str) -> PathBuf,
    /// The file's image index -> index in `out.images`.
    image_ids: HashMap<usize, u32>,
    /// The texture coordinate set of each material in `out.materials`.
    uv_sets: Vec<u32>,
    document: &'a ::gltf::Document,
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
        if let Some(light) = node.light() {
            self.light(&light, world);
        }
        if let Some(camera) = node.camera() {
            self.camera(&camera, world, node);
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
                        let material = self.material(&prim.material())?;
                        let (tm, tangents) = self.primitive(&prim, &what, self.uv_set(material))?;
                        parts.push(MeshPart {
                            mesh: tm,
                            material,
                            file_triangles: None,
                            tangents,
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
                let material = self.material(&prim.material())?;
                let (tm, tangents) = self.primitive(&prim, &what, self.uv_set(material))?;
                let mut part = MeshPart {
                    mesh: tm,
                    material,
                    file_triangles: None,
                    tangents,
                };
                part.transform(world);
                if !part.mesh.positions.iter().all(|p| p.is_finite()) {
                    return Err(
                        self.err(format!("{what}: a vertex position is not a finite number"))
                    );
                }
                // Parts number their triangles from where they stand in the file's order, which
                // placements of shared meshes may interleave.
                let count = part.mesh.triangle_count() as u32;
                part.file_triangles = (self.triangles != self.out.parts_triangles())
                    .then(|| (self.triangles..self.triangles + count).collect());
                self.out.parts.push(part);
                self.triangles += count;
            }
        }
        for child in node.children() {
            self.node(&child, world, depth + 1)?;
        }
        Ok(())
    }

    fn uv_set(&self, material: Option<u32>) -> u32 {
        material.map_or(0, |m| self.uv_sets[m as usize])
    }

    fn material(&mut self, m: &::gltf::Material) -> Result<Option<u32>> {
        if let Some(&id) = self.material_ids.get(&m.index()) {
            return Ok(id);
        }
        // A primitive without a material uses the scene's default.
        let Some(i) = m.index() else {
            self.material_ids.insert(None, None);
            return Ok(None);
        };
        let (fm, uv_set) = self.read_material(m, i)?;
        self.out.materials.push(fm);
        self.uv_sets.push(uv_set);
        let id = Some(self.out.materials.len() as u32 - 1);
        self.material_ids.insert(m.index(), id);
        Ok(id)
    }

    /// A glTF material as a [`FileMaterial`], with the texture coordinate set its textures read
    /// (that of the base colour texture, else of the first texture it has: Appel's meshes carry
    /// one set).
    fn read_material(&mut self, m: &::gltf::Material, i: usize) -> Result<(FileMaterial, u32)> {
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, a] = pbr.base_color_factor();
        let what = format!("material {i}");
        let mut sets: Vec<u32> = vec![];
        let mut info =
            |ctx: &mut Self, t: Option<::gltf::texture::Info>| -> Result<Option<FileTexture>> {
                let Some(t) = t else { return Ok(None) };
                let transform = t.texture_transform();
                let set = transform
                    .as_ref()
                    .and_then(|x| x.tex_coord())
                    .unwrap_or(t.tex_coord());
                sets.push(set);
                let to_uv = transform.map_or(Mat3::IDENTITY, |x| {
                    texture_transform(x.offset(), x.rotation(), x.scale())
                });
                ctx.texture(&t.texture(), set, to_uv, &what).map(Some)
            };
        let diffuse_map = info(self, pbr.base_color_texture())?;
        let metallic_roughness_map = info(self, pbr.metallic_roughness_texture())?;
        let emissive_map = info(self, m.emissive_texture())?;
        let transmission = m.transmission();
        let transmission_map = info(
            self,
            transmission.as_ref().and_then(|t| t.transmission_texture()),
        )?;
        let normal_map = match m.normal_texture() {
            Some(n) => {
                sets.push(n.tex_coord());
                Some((
                    self.texture(&n.texture(), n.tex_coord(), Mat3::IDENTITY, &what)?,
                    n.scale(),
                ))
            }
            None => None,
        };
        let occlusion_map = match m.occlusion_texture() {
            Some(o) => {
                sets.push(o.tex_coord());
                Some(self.texture(&o.texture(), o.tex_coord(), Mat3::IDENTITY, &what)?)
            }
            None => None,
        };
        // KHR_materials_clearcoat: not in the gltf crate's typed API; read from the JSON.
        let clearcoat = m.extension_value("KHR_materials_clearcoat");
        let number = |key: &str, default: f32| {
            clearcoat
                .and_then(|c| c.get(key))
                .and_then(|v| v.as_f64())
                .map_or(default, |v| v as f32)
        };
        let mut json_texture = |ctx: &mut Self, key: &str| -> Result<Option<FileTexture>> {
            let Some(t) = clearcoat.and_then(|c| c.get(key)) else {
                return Ok(None);
            };
            let index = t.get("index").and_then(|v| v.as_u64());
            let texture = index.and_then(|i| ctx.document.textures().nth(i as usize));
            let Some(texture) = texture else {
                return Err(ctx.err(format!(
                    "{what}: KHR_materials_clearcoat.{key} names no texture of the file"
                )));
            };
            let set = t.get("texCoord").and_then(|v| v.as_u64()).unwrap_or(0) as u32;
            sets.push(set);
            ctx.texture(&texture, set, Mat3::IDENTITY, &what).map(Some)
        };
        let clearcoat_map = json_texture(self, "clearcoatTexture")?;
        let clearcoat_roughness_map = json_texture(self, "clearcoatRoughnessTexture")?;
        let specular = m.specular();
        let strength = m.emissive_strength().unwrap_or(1.0);
        let params = PbrParams {
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            metallic_roughness_map,
            occlusion_map,
            emissive: m.emissive_factor().map(|e| e * strength),
            emissive_map,
            transmission: transmission
                .as_ref()
                .map_or(0.0, |t| t.transmission_factor()),
            transmission_map,
            clearcoat: number("clearcoatFactor", 0.0),
            clearcoat_map,
            clearcoat_roughness: number("clearcoatRoughnessFactor", 0.0),
            clearcoat_roughness_map,
            specular: specular.as_ref().map_or(1.0, |s| s.specular_factor()),
            specular_color: specular
                .as_ref()
                .map_or([1.0; 3], |s| s.specular_color_factor()),
            double_sided: m.double_sided(),
        };
        let uv_set = diffuse_map
            .as_ref()
            .map(|t| t.uv_set)
            .or(sets.first().copied())
            .unwrap_or(0);
        let alpha = match m.alpha_mode() {
            ::gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            ::gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
            ::gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        let fm = FileMaterial {
            name: m
                .name()
                .map_or_else(|| format!("material {i}"), str::to_string),
            diffuse: [r, g, b],
            opacity: a,
            ior: m.ior().unwrap_or(1.5),
            diffuse_map,
            alpha,
            normal_map,
            pbr: Some(Box::new(params)),
            ..Default::default()
        };
        Ok((fm, uv_set))
    }

    /// A texture's image (read once per file) and sampler.
    fn texture(
        &mut self,
        t: &::gltf::Texture,
        uv_set: u32,
        to_uv: Mat3,
        what: &str,
    ) -> Result<FileTexture> {
        use ::gltf::texture::{MagFilter, WrappingMode};
        let image = t.source();
        let index = match self.image_ids.get(&image.index()) {
            Some(&i) => i,
            None => {
                let file = self.image(&image, what)?;
                self.out.images.push(file);
                let i = self.out.images.len() as u32 - 1;
                self.image_ids.insert(image.index(), i);
                i
            }
        };
        let sampler = t.sampler();
        // One wrap mode for both axes: wrapS decides (files almost always set both alike).
        let wrap = match sampler.wrap_s() {
            WrappingMode::ClampToEdge => Wrap::Clamp,
            WrappingMode::MirroredRepeat => Wrap::Mirror,
            WrappingMode::Repeat => Wrap::Repeat,
        };
        // Magnification decides; minification filters (mipmaps) have no equivalent here.
        let filter = match sampler.mag_filter() {
            Some(MagFilter::Nearest) => Filter::Nearest,
            _ => Filter::Bilinear,
        };
        Ok(FileTexture {
            image: index,
            uv_set,
            wrap,
            filter,
            to_uv,
        })
    }

    fn image(&self, image: &::gltf::Image, what: &str) -> Result<FileImage> {
        let i = image.index();
        match image.source() {
            ::gltf::image::Source::View { view, .. } => {
                let bytes = self.buffers.get(view.buffer().index()).and_then(|b| {
                    let end = view.offset().checked_add(view.length())?;
                    b.get(view.offset()..end)
                });
                let bytes = bytes.ok_or_else(|| {
                    self.err(format!(
                        "{what}: image {i}: buffer view {} lies outside its buffer",
                        view.index()
                    ))
                })?;
                Ok(FileImage {
                    name: PathBuf::from(format!("{} (image {i})", self.path.display())),
                    bytes: Ok(Arc::new(bytes.to_vec())),
                })
            }
            ::gltf::image::Source::Uri { uri, .. } => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let (_, payload) = rest.split_once(";base64,").ok_or_else(|| {
                        self.err(format!("image {i}: only base64 data URIs are supported"))
                    })?;
                    let bytes = base64::engine::general_purpose::STANDARD
                        .decode(payload)
                        .map_err(|e| self.err(format!("image {i}: bad base64 data: {e}")))?;
                    return Ok(FileImage {
                        name: PathBuf::from(format!("{} (image {i})", self.path.display())),
                        bytes: Ok(Arc::new(bytes)),
                    });
                }
                if uri.contains("://") {
                    return Err(self.err(format!(
                        "image {i}: `{uri}` is not a local file; only relative paths and data URIs are supported"
                    )));
                }
                let uri = percent_decode(uri);
                Ok(FileImage {
                    name: (self.namer)(&uri),
                    bytes: (self.external)(&uri).map(Arc::new),
                })
            }
        }
    }

    /// A `KHR_lights_punctual` light at `world`: it shines along the node's -z. Intensities are
    /// taken as radiometric (candela as W/sr, lux as W/m^2): Appel's images have no exposure, so a
    /// constant factor such as 683 lm/W would only rescale them. `range` is ignored (the
    /// specification allows renderers to).
    fn light(&mut self, light: &::gltf::khr_lights_punctual::Light, world: Mat4) {
        match super::gltf_lights::placed_light(light, world) {
            Some(l) => self.out.lights.push(l),
            None => self.out.warnings.push(format!(
                "light {}: its node's transform, its colour or its intensity is degenerate; it is left out",
                light.index()
            )),
        }
    }

    fn camera(&mut self, camera: &::gltf::Camera, world: Mat4, node: &Node) {
        match file_camera(camera, world, node) {
            Ok(c) => self.out.cameras.push(c),
            Err(w) => self.out.warnings.push(w),
        }
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

    /// The primitive's triangles, and its tangents where it has them (see [`Self::tangents`]).
    fn primitive(
        &self,
        prim: &::gltf::Primitive,
        what: &str,
        uv_set: u32,
    ) -> Result<(TriangleMesh, Option<Vec<Vec4>>)> {
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
        let uvs = match prim.get(&::gltf::Semantic::TexCoords(uv_set)) {
            Some(a) if a.count() == nv => {
                self.check(
                    &a,
                    &[(vec2, F32), (vec2, U8), (vec2, U16)],
                    &format!("{what} TEXCOORD_{uv_set}"),
                )?;
                reader
                    .read_tex_coords(uv_set)
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
        let tangents = match &normals {
            Some(_) => self.tangents(prim, what, nv)?,
            // Without normals the specification asks for flat ones, and for the tangents to be
            // ignored: the flat frame has no use for them.
            None => None,
        };
        let mesh = TriangleMesh {
            positions,
            indices: flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
            normals,
            uvs,
        };
        // Without TANGENT, glTF asks for MikkTSpace ones; only normal-mapped primitives use
        // tangents, so the others keep none.
        let tangents = match tangents {
            None if prim.material().normal_texture().is_some() => mikktspace_tangents(&mesh),
            t => t,
        };
        Ok((mesh, tangents))
    }

    /// The primitive's `TANGENT` attribute, if it has one: VEC4 floats, one per vertex (the
    /// specification's only form without `KHR_mesh_quantization`). Another element type or
    /// count is an error naming the accessor, as are tangents that are not finite numbers.
    fn tangents(
        &self,
        prim: &::gltf::Primitive,
        what: &str,
        nv: usize,
    ) -> Result<Option<Vec<Vec4>>> {
        let Some(a) = prim.get(&::gltf::Semantic::Tangents) else {
            return Ok(None);
        };
        let what = format!("{what} TANGENT");
        self.check(&a, &[(Dimensions::Vec4, DataType::F32)], &what)?;
        if a.count() != nv {
            return Err(self.err(format!(
                "{what}: accessor {} has {} elements for {nv} vertices",
                a.index(),
                a.count()
            )));
        }
        let buffers = self.buffers;
        let reader = prim.reader(|b| buffers.get(b.index()).map(|v| v.as_slice()));
        let tangents: Vec<Vec4> = reader
            .read_tangents()
            .ok_or_else(|| self.err(format!("{what}: cannot read it")))?
            .map(Vec4::from)
            .collect();
        if let Some(i) = tangents.iter().position(|t| !t.is_finite()) {
            return Err(self.err(format!("{what}: tangent {i} is not a finite number")));
        }
        Ok(Some(tangents))
    }
}

/// A glTF camera placed by `node` at `world`: it looks along the node's -z with +y up (glTF 2.0
/// section 3.10.1), or a warning saying why it cannot be used (a degenerate transform).
pub fn file_camera(
    camera: &::gltf::Camera,
    world: Mat4,
    node: &Node,
) -> std::result::Result<FileCamera, String> {
    use ::gltf::camera::Projection;
    let eye = world.transform_point3(GVec3::ZERO);
    let forward = world.transform_vector3(-GVec3::Z).normalize_or_zero();
    let up = world.transform_vector3(GVec3::Y).normalize_or_zero();
    let name = camera
        .name()
        .or(node.name())
        .map_or_else(|| format!("camera {}", camera.index()), str::to_string);
    // A view direction lost to rounding (a huge eye) or along `up` (a skewed transform) has
    // no camera frame.
    if !eye.is_finite()
        || forward == GVec3::ZERO
        || up == GVec3::ZERO
        || eye + forward == eye
        || forward.cross(up).length_squared() < 1e-12
    {
        return Err(format!(
            "{name}: its node's transform is degenerate; the camera is left out"
        ));
    }
    let base = CameraDesc {
        eye: eye.into(),
        look_at: (eye + forward).into(),
        up: up.into(),
        ..CameraDesc::default()
    };
    let (camera, aspect) = match camera.projection() {
        Projection::Perspective(p) => (
            CameraDesc {
                fov: p.yfov().to_degrees().clamp(0.01, 179.0),
                near_clip: p.znear().max(0.0),
                ..base
            },
            p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0),
        ),
        Projection::Orthographic(o) => (
            CameraDesc {
                kind: CameraKind::Orthographic,
                half_width: Some(o.xmag().abs().max(1e-6)),
                ..base
            },
            (o.ymag() != 0.0).then(|| (o.xmag() / o.ymag()).abs()),
        ),
    };
    Ok(FileCamera {
        name,
        camera,
        aspect,
    })
}

/// `KHR_texture_transform`'s matrix, translation * rotation * scale acting on (u, v, 1). The
/// rotation is u' = cos u + sin v, v' = -sin u + cos v: counter-clockwise in uv space with v
/// pointing down, which is what the sample model TextureTransformTest and the implementations
/// agree on (the extension's GLSL listing has the opposite sign: KhronosGroup/glTF issue 1563).
pub fn texture_transform(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Mat3 {
    let (s, c) = rotation.sin_cos();
    let t = Mat3::from_cols_array_2d(&[
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [offset[0], offset[1], 1.0],
    ]);
    let r = Mat3::from_cols_array_2d(&[[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]);
    let sc = Mat3::from_diagonal(glam::Vec3::new(scale[0], scale[1], 1.0));
    t * r * sc
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
