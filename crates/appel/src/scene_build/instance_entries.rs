//! From `[meshes.NAME]` and `[[instance]]` entries to prototypes and instances.

use super::mesh_shape::MeshFile;
use super::{basic_meshes, SceneBuilder};
use crate::error::{Error, Location, Result};
use crate::geometry::InstanceTransform;
use crate::io::placements::read_placements;
use crate::scene::{Geometry, Instance, Prototype};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

const TOO_FAR: &str = "the placement moves the mesh beyond the range of f32";

/// Whether the placed mesh's world bounds are finite (a huge scale or translation could overflow
/// them, and the structure's build and traversal need finite boxes).
fn fits(x: &InstanceTransform, bounds: crate::math::Aabb) -> bool {
    let b = x.bounds_to_world(bounds);
    b.min.is_finite() && b.max.is_finite()
}

impl SceneBuilder<'_> {
    /// Loads every declared mesh that an instance uses, builds its structure (of the scene's kind),
    /// and adds the instances (their `shapeid` continues the numbering of the `[[shape]]` entries).
    /// Returns the time spent building the prototypes' structures, which belongs to the build
    /// phase, not loading.
    pub(super) fn add_instances(&mut self) -> Result<Duration> {
        let d = self.d;
        let base_dir = self.base_dir;
        let mut prototype_of: BTreeMap<&str, u32> = BTreeMap::new();
        let mut loaded = vec![];
        // Mesh files of `[[shape]]`s may already have made prototypes (glTF nodes sharing a mesh).
        let base = self.geometry.prototypes.len() as u32;
        for entry in &d.instances {
            if prototype_of.contains_key(entry.mesh.as_str()) {
                continue;
            }
            let Some(m) = d.meshes.get(&entry.mesh) else {
                return Err(Error::Invalid(format!("unknown mesh `{}`", entry.mesh)));
            };
            let mut mesh_geometry = Geometry::new(self.geometry.triangle_test);
            let material = m.material.as_deref().map(|m| self.material_index(m));
            let emitting = self.from_files.emission.len();
            if m.file.is_empty() {
                // Written out in the scene; validation saw that each has a material.
                for t in &m.triangles {
                    let own = t.material.as_deref().map(|m| self.material_index(m));
                    let Some(mat) = own.or(material) else {
                        return Err(Error::Invalid(format!(
                            "mesh `{}`: a triangle mesh without a material",
                            entry.mesh
                        )));
                    };
                    mesh_geometry.push_mesh(basic_meshes::inline_mesh(t), mat);
                }
            } else {
                self.add_mesh_file(
                    Some(&mut mesh_geometry),
                    MeshFile {
                        path: &base_dir.join(&m.file),
                        transform: None,
                        material,
                        smooth_normals: m.smooth_normals,
                    },
                )?;
            }
            if !mesh_geometry.instances.is_empty() {
                return Err(Error::input(
                    Location::file(base_dir.join(&m.file)),
                    "this file places a mesh several times itself; instances of instances are not supported",
                ));
            }
            // Instanced surfaces cannot emit (their emission would be indexed by the prototype's
            // shapes, not the scene's).
            if self.from_files.emission.len() > emitting {
                self.from_files.emission.truncate(emitting);
                self.from_files.warnings.push(format!(
                    "{}: its emissive materials do not emit when the mesh is instanced",
                    m.file
                ));
            }
            let label = if m.file.is_empty() {
                &entry.mesh
            } else {
                &m.file
            };
            self.steps.step(&format!("read {label}"))?;
            loaded.push((label, mesh_geometry));
            prototype_of.insert(&entry.mesh, base + loaded.len() as u32 - 1);
        }
        // The prototypes' structures are independent: build them side by side (each also splits its
        // own large nodes in parallel).
        if !loaded.is_empty() {
            self.steps
                .begin(&format!("building {} mesh structures", loaded.len()));
        }
        let start = Instant::now();
        let (steps, kind, options) = (
            &self.steps,
            self.prototype_accel,
            &self.settings.accel_options,
        );
        let built: Result<Vec<Prototype>> = loaded
            .into_par_iter()
            .map(|(file, g)| {
                steps.check()?;
                let p = Prototype::new(g, kind, options);
                steps.step(&format!("built the structure of {file}"))?;
                Ok(p)
            })
            .collect();
        self.geometry.prototypes.extend(built?);
        let build = start.elapsed();
        for (k, entry) in d.instances.iter().enumerate() {
            let prototype = prototype_of[entry.mesh.as_str()];
            let bounds = self.geometry.prototypes[prototype as usize].bounds;
            let source = (d.shapes.len() + k) as u32;
            let instance = |transform| Instance {
                transform,
                prototype,
                source,
                first_prim: 0,
            };
            match &entry.placements {
                Some(file) => {
                    let path = base_dir.join(file);
                    let placements = read_placements(&path)?;
                    let mut instances = Vec::with_capacity(placements.len());
                    for p in placements {
                        let Some(x) = InstanceTransform::new(p.to_world) else {
                            return Err(Error::input(
                                Location::line(&path, p.line, None),
                                "the placement's matrix is not invertible",
                            ));
                        };
                        if !fits(&x, bounds) {
                            return Err(Error::input(Location::line(&path, p.line, None), TOO_FAR));
                        }
                        instances.push(instance(x));
                    }
                    self.geometry.push_instances(source, instances);
                }
                None => {
                    let m = entry
                        .transform
                        .as_ref()
                        .map_or(glam::Mat4::IDENTITY, |t| t.matrix());
                    let x = InstanceTransform::new(m).ok_or_else(|| {
                        Error::Invalid(format!("instance {k}'s transform is not invertible"))
                    })?;
                    if !fits(&x, bounds) {
                        return Err(Error::Invalid(format!("instance {k}: {TOO_FAR}")));
                    }
                    self.geometry.push_instances(source, [instance(x)]);
                }
            }
        }
        Ok(build)
    }
}
