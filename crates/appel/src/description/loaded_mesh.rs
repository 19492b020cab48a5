//! Meshes as files give them, the common result of the mesh readers (`io`) and the input of the
//! scene and its shading: triangles grouped by material, the file's materials, images, lights,
//! cameras and named attributes.

use super::texture_lookup::{Filter, Wrap};
use super::{CameraDesc, LightDesc};
use super::{DirectionalDesc, PointDesc, SpotDesc};
use crate::geometry::TriangleMesh;
use crate::math::{Aabb, Vec3};
use glam::{Mat3, Mat4, Vec4};
use std::path::PathBuf;
use std::sync::Arc;

/// A material as a mesh file states it, before it is mapped onto Appel's materials (see
/// `docs/meshes.md`): OBJ's MTL (`Kd Ks Ns Ni d` and their maps), or glTF's metallic-roughness
/// material with its extensions.
#[derive(Clone, Debug, PartialEq)]
pub struct FileMaterial {
    pub name: String,
    /// Diffuse colour (MTL `Kd`, glTF `baseColorFactor` rgb), linear RGB.
    pub diffuse: [f32; 3],
    /// Specular colour (MTL `Ks`).
    pub specular: [f32; 3],
    /// Phong exponent (MTL `Ns`).
    pub shininess: f32,
    /// Index of refraction (MTL `Ni`, glTF `KHR_materials_ior`).
    pub ior: f32,
    /// Opacity (MTL `d`, glTF base colour alpha); 1 is opaque.
    pub opacity: f32,
    /// Multiplies `diffuse` (MTL `map_Kd`, glTF `baseColorTexture`, whose alpha multiplies
    /// `opacity`).
    pub diffuse_map: Option<FileTexture>,
    /// MTL `map_Ks`, multiplying `specular`.
    pub specular_map: Option<FileTexture>,
    /// MTL `map_Ns`: a grey image scaling `shininess`.
    pub shininess_map: Option<FileTexture>,
    /// MTL `map_d`: opacity from the image's alpha channel if it has one, else its grey value.
    pub opacity_map: Option<FileTexture>,
    /// How opacity is used: MTL files blend (any `d < 1` or `map_d`), glTF says.
    pub alpha: AlphaMode,
    /// Tangent-space normal map (glTF `normalTexture`, MTL `norm`), with its strength. Read so
    /// that it can be applied by a normal-mapping material; not applied here.
    pub normal_map: Option<(FileTexture, f32)>,
    /// Height map (MTL `bump` / `map_bump`, with `-bm` strength). Read, not applied.
    pub bump_map: Option<(FileTexture, f32)>,
    /// glTF's physically based parameters; `None` for MTL materials.
    pub pbr: Option<Box<PbrParams>>,
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
            diffuse_map: None,
            specular_map: None,
            shininess_map: None,
            opacity_map: None,
            alpha: AlphaMode::Opaque,
            normal_map: None,
            bump_map: None,
            pbr: None,
        }
    }
}

/// glTF's `alphaMode`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored.
    #[default]
    Opaque,
    /// The surface is there where alpha >= the cutoff, absent elsewhere.
    Mask(f32),
    /// Alpha is the surface's coverage.
    Blend,
}

/// glTF 2.0's metallic-roughness material and the `KHR_materials_*` extensions Appel reads; factors
/// multiply their textures as the specification says.
#[derive(Clone, Debug, PartialEq)]
pub struct PbrParams {
    pub metallic: f32,
    pub roughness: f32,
    /// Roughness in G, metalness in B (linear).
    pub metallic_roughness_map: Option<FileTexture>,
    /// Ambient occlusion in R: read, not used (a path tracer computes occlusion itself).
    pub occlusion_map: Option<FileTexture>,
    /// `emissiveFactor` times `KHR_materials_emissive_strength`.
    pub emissive: [f32; 3],
    pub emissive_map: Option<FileTexture>,
    /// `KHR_materials_transmission` (R of its texture).
    pub transmission: f32,
    pub transmission_map: Option<FileTexture>,
    /// `KHR_materials_clearcoat`: its factor (R of its texture) and roughness (G of its texture).
    pub clearcoat: f32,
    pub clearcoat_map: Option<FileTexture>,
    pub clearcoat_roughness: f32,
    pub clearcoat_roughness_map: Option<FileTexture>,
    /// `KHR_materials_specular`: `specularFactor` and `specularColorFactor` (their textures are
    /// read, not used).
    pub specular: f32,
    pub specular_color: [f32; 3],
    pub double_sided: bool,
}

impl Default for PbrParams {
    fn default() -> Self {
        Self {
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_map: None,
            occlusion_map: None,
            emissive: [0.0; 3],
            emissive_map: None,
            transmission: 0.0,
            transmission_map: None,
            clearcoat: 0.0,
            clearcoat_map: None,
            clearcoat_roughness: 0.0,
            clearcoat_roughness_map: None,
            specular: 1.0,
            specular_color: [1.0; 3],
            double_sided: false,
        }
    }
}

/// A texture of a mesh file's material: one of the file's images and how it is looked up.
#[derive(Clone, Debug, PartialEq)]
pub struct FileTexture {
    /// Index into [`LoadedMesh::images`].
    pub image: u32,
    /// The texture coordinate set (glTF `TEXCOORD_n`; 0 for OBJ).
    pub uv_set: u32,
    pub wrap: Wrap,
    pub filter: Filter,
    /// Applied to (u, v, 1) before the lookup (`KHR_texture_transform`, MTL `-o`/`-s`).
    pub to_uv: Mat3,
}

/// An image a mesh file refers to: its name, and its bytes or why they could not be read.
#[derive(Clone, Debug, PartialEq)]
pub struct FileImage {
    pub name: PathBuf,
    pub bytes: std::result::Result<Arc<Vec<u8>>, String>,
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
    /// Per-vertex tangents the file gives (glTF `TANGENT`): xyz the tangent, w (+1 or -1) the
    /// handedness of the bitangent `cross(normal, tangent) * w`; one per position.
    pub tangents: Option<Vec<Vec4>>,
}

impl MeshPart {
    /// Applies an affine transform to the part's mesh (see [`transform_mesh`]) and its tangents:
    /// these are surface directions, carried by the linear part itself, and a mirroring transform
    /// turns their handedness around (`cross(Ma, Mb) = det(M) M^-T (a x b)`).
    pub fn transform(&mut self, m: Mat4) {
        transform_mesh(&mut self.mesh, m);
        if m == Mat4::IDENTITY {
            return;
        }
        if let Some(ts) = &mut self.tangents {
            let linear = Mat3::from_mat4(m);
            let flip = if linear.determinant() < 0.0 {
                -1.0
            } else {
                1.0
            };
            for t in ts {
                let dir = (linear * t.truncate()).normalize_or_zero();
                *t = dir.extend(flip * t.w);
            }
        }
    }
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
    /// The images the materials' textures read.
    pub images: Vec<FileImage>,
    /// The file's lights (glTF `KHR_lights_punctual`), in world space.
    pub lights: Vec<LightDesc>,
    /// The file's cameras (glTF), in world space, in node order.
    pub cameras: Vec<FileCamera>,
    /// Problems that do not stop the file from rendering (a texture that cannot be found).
    pub warnings: Vec<String>,
    /// Named per-vertex and per-triangle values (PLY's extra properties) of a file read as one
    /// part; textures read them by name (Mitsuba's `mesh_attribute`).
    pub attributes: Vec<MeshAttribute>,
}

/// A camera placed by a mesh file: where it is and what it sees. `aspect` is the width over the
/// height the file asks for, if any.
#[derive(Clone, Debug, PartialEq)]
pub struct FileCamera {
    pub name: String,
    pub camera: CameraDesc,
    pub aspect: Option<f32>,
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
                part.transform(p.to_world);
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
            part.transform(m);
        }
        for p in &mut self.placements {
            p.to_world = m * p.to_world;
        }
        for l in &mut self.lights {
            transform_light(l, m);
        }
        for c in &mut self.cameras {
            let cam = &mut c.camera;
            let eye = m.transform_point3(cam.eye.into());
            let look = m.transform_point3(cam.look_at.into());
            cam.up = m
                .transform_vector3(cam.up.into())
                .normalize_or_zero()
                .into();
            cam.eye = eye.into();
            cam.look_at = look.into();
        }
    }
}

/// One warning for the images that could not be read: the materials using them render with their
/// factors alone.
pub(crate) fn unreadable_images(images: &[FileImage]) -> Vec<String> {
    let bad: Vec<&String> = images
        .iter()
        .filter_map(|i| i.bytes.as_ref().err())
        .collect();
    match bad.as_slice() {
        [] => vec![],
        [one] => vec![format!(
            "texture {one}; the materials using it render without it"
        )],
        [first, rest @ ..] => vec![format!(
            "{} textures cannot be read (the first: {first}); the materials using them render without them",
            rest.len() + 1
        )],
    }
}

/// Moves a light placed by a file along with the file's transform.
pub(crate) fn transform_light(l: &mut LightDesc, m: Mat4) {
    let p = |v: &mut [f32; 3]| *v = m.transform_point3((*v).into()).into();
    match l {
        LightDesc::Point(PointDesc { position, .. }) => p(position),
        LightDesc::Spot(SpotDesc {
            position, look_at, ..
        }) => {
            p(position);
            p(look_at);
        }
        LightDesc::Directional(DirectionalDesc { direction, .. }) => {
            *direction = m
                .transform_vector3((*direction).into())
                .normalize_or_zero()
                .into()
        }
        _ => {}
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

/// Positions must be finite: a NaN or infinite vertex would poison bounds and the acceleration
/// structure. Returns the index of the first bad one.
pub(crate) fn first_non_finite(positions: &[Vec3]) -> Option<usize> {
    positions.iter().position(|p| !p.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

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
