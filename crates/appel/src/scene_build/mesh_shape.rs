//! `type = "mesh"` shapes: a mesh file, placed by its transform, with its own materials unless the
//! shape names one.

use super::file_materials::{self, is_physically_based, Images};
use super::{basic_meshes, AddShape, Entry, SceneBuilder};
use crate::description::loaded_mesh::FileMaterial;
use crate::description::{MeshShapeDesc, PhongDesc, TransformDesc};
use crate::error::{Error, Location, Result};
use crate::geometry::InstanceTransform;
use crate::io::load_mesh;
use crate::io::vertex_normals::angle_weighted;
use crate::scene::{Geometry, Instance, Prototype, ShapeKind};
use crate::shading::bsdf::PhongParams;
use crate::shading::material::Material;
use crate::shading::texture::Texture;
use std::path::Path;

/// A mesh file to load, and how.
pub struct MeshFile<'a> {
    pub path: &'a Path,
    pub transform: Option<&'a TransformDesc>,
    /// The scene material that replaces the file's own, when the scene names one.
    pub material: Option<u32>,
    /// Give parts without vertex normals smooth ones, computed from the transformed positions (as
    /// Mitsuba computes them after applying `to_world`).
    pub smooth_normals: bool,
}

impl AddShape for MeshShapeDesc {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        let first_new_shape = b.geometry.shapes.len();
        let path = b.base_dir.join(&self.file);
        b.add_mesh_file(
            None,
            MeshFile {
                path: &path,
                transform: self.transform.as_ref(),
                material: self.material.is_some().then_some(entry.material),
                smooth_normals: self.smooth_normals,
            },
        )?;
        b.steps.step(&format!("read {}", self.file))?;
        for shape in &b.geometry.shapes[first_new_shape..] {
            let ShapeKind::Mesh(k) = shape.kind else {
                continue;
            };
            let mesh = &mut b.geometry.meshes[k as usize];
            if self.face_normals {
                mesh.normals = None;
            }
            if self.flip_normals {
                basic_meshes::flip_normals(mesh);
            }
        }
        Ok(())
    }
}

impl SceneBuilder<'_> {
    /// Loads a mesh file, transforms it and adds one mesh shape per part, to `prototype` if given
    /// (a declared mesh), else to the scene's top level.
    pub(super) fn add_mesh_file(
        &mut self,
        prototype: Option<&mut Geometry>,
        file: MeshFile,
    ) -> Result<()> {
        let MeshFile {
            path,
            transform,
            material,
            smooth_normals,
        } = file;
        let geometry = match prototype {
            Some(g) => g,
            None => &mut self.geometry,
        };
        let materials = &mut self.materials;
        let extras = &mut self.from_files;
        let kind = self.prototype_accel;
        let options = &self.settings.accel_options;
        let mut loaded = load_mesh(path)?;
        if let Some(t) = transform {
            loaded.transform(t.matrix());
            let finite = loaded
                .parts
                .iter()
                .all(|p| p.mesh.positions.iter().all(|v| v.is_finite()))
                && loaded.placements.iter().all(|p| p.to_world.is_finite());
            if !finite {
                return Err(Error::input(
                    Location::file(path),
                    "the transform moves vertices beyond the range of f32",
                ));
            }
        }
        if smooth_normals {
            for part in loaded
                .parts
                .iter_mut()
                .chain(loaded.shared.iter_mut().flatten())
            {
                let mesh = &mut part.mesh;
                if mesh.normals.is_none() {
                    mesh.normals = Some(angle_weighted(&mesh.positions, &mesh.indices));
                }
            }
        }
        extras.warnings.extend(
            loaded
                .warnings
                .iter()
                .map(|w| format!("{}: {w}", path.display())),
        );
        extras.lights.append(&mut loaded.lights);
        extras.cameras.append(&mut loaded.cameras);
        // The scene index of each file material (the entry its triangles use), and its emission.
        let mut file_material: Vec<u32> = vec![];
        let mut emission: Vec<Option<Texture>> = vec![];
        if material.is_none() {
            let images = Images::decode(&loaded)?;
            for m in &loaded.materials {
                if is_physically_based(m) {
                    extras.physically_based = true;
                    let first = materials.len() as u32;
                    let built = file_materials::build(m, &images, first);
                    materials.extend(built.entries);
                    file_material.push(materials.len() as u32 - 1);
                    emission.push(built.emission);
                } else {
                    materials.push(material_from_file(m));
                    file_material.push(materials.len() as u32 - 1);
                    emission.push(None);
                }
            }
        }
        let part_material =
            |m: Option<u32>| material.unwrap_or_else(|| m.map_or(0, |m| file_material[m as usize]));
        let part_emission = |m: Option<u32>| match (material, m) {
            (None, Some(m)) => emission[m as usize].clone(),
            _ => None,
        };
        let mut first_prim = 0;
        // Attributes are read from files of one part (PLY), indexed by its vertices and triangles.
        let mut attributes = (loaded.parts.len() == 1).then_some(loaded.attributes);
        for part in loaded.parts {
            let id = part_material(part.material);
            let count = part.mesh.triangle_count() as u32;
            let emits = part_emission(part.material);
            let shape = geometry.push_mesh(part.mesh, id);
            if let Some(t) = part.tangents {
                geometry.set_mesh_tangents(geometry.meshes.len() as u32 - 1, t);
            }
            if let Some(e) = emits {
                extras.emission.push((shape, e));
            }
            if let Some(a) = attributes.take().filter(|a| !a.is_empty()) {
                geometry.set_mesh_attributes(geometry.meshes.len() as u32 - 1, a);
            }
            let source = &mut geometry.shapes[shape as usize].source;
            source.first_prim = first_prim;
            source.prim_table = part.file_triangles;
            first_prim += count;
        }
        // Meshes the file places several times: one prototype each, one instance per placement.
        let first_prototype = geometry.prototypes.len() as u32;
        for parts in loaded.shared {
            let mut g = Geometry::new(geometry.triangle_test);
            let mut first_prim = 0;
            for part in parts {
                if part_emission(part.material).is_some() {
                    extras.warnings.push(format!(
                        "{}: a mesh placed by several nodes has an emissive material; instanced \
                         surfaces cannot emit, so it does not",
                        path.display()
                    ));
                }
                let count = part.mesh.triangle_count() as u32;
                let shape = g.push_mesh(part.mesh, part_material(part.material));
                if let Some(t) = part.tangents {
                    g.set_mesh_tangents(g.meshes.len() as u32 - 1, t);
                }
                g.shapes[shape as usize].source.first_prim = first_prim;
                first_prim += count;
            }
            geometry.prototypes.push(Prototype::new(g, kind, options));
        }
        let mut instances = Vec::with_capacity(loaded.placements.len());
        for p in &loaded.placements {
            let Some(transform) = InstanceTransform::new(p.to_world) else {
                return Err(Error::input(
                    Location::file(path),
                    "a node placing a shared mesh has a transform that cannot be inverted",
                ));
            };
            let bounds = geometry.prototypes[(first_prototype + p.mesh) as usize].bounds;
            let world = transform.bounds_to_world(bounds);
            if !(world.min.is_finite() && world.max.is_finite()) {
                return Err(Error::input(
                    Location::file(path),
                    "a node moves a shared mesh beyond the range of f32",
                ));
            }
            instances.push(Instance {
                transform,
                prototype: first_prototype + p.mesh,
                source: 0,
                first_prim: p.first_triangle,
            });
        }
        if !instances.is_empty() {
            geometry.push_instances(0, instances);
        }
        Ok(())
    }
}

/// A file's material in Whitted's model, `phong` (see `docs/meshes.md`): `Kd` is the diffuse colour with
/// coefficient 1, the largest component of `Ks` the specular coefficient, `Ns` the Blinn exponent,
/// `1 - d` the transmission with `Ni` as its index of refraction.
pub fn material_from_file(m: &FileMaterial) -> Material {
    let clamp = |x: f32| if x.is_finite() { x.max(0.0) } else { 0.0 };
    let d = PhongDesc {
        color: m.diffuse.map(clamp),
        diffuse: 1.0,
        specular: clamp(m.specular.into_iter().fold(0.0, f32::max)),
        shininess: clamp(m.shininess).max(1.0),
        transmission: clamp(1.0 - m.opacity),
        ior: if m.ior.is_finite() && m.ior > 0.0 {
            m.ior
        } else {
            1.5
        },
        ..Default::default()
    };
    Material::Phong(PhongParams::from_desc(&d))
}
