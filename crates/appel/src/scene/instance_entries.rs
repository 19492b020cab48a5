//! From `[meshes.NAME]` and `[[instance]]` entries to prototypes and instances.

use super::instance::{Instance, Prototype};
use super::mesh_shape::{add_mesh_file, FileExtras};
use super::progress::Steps;
use super::{Geometry, RenderSettings};
use crate::description::Description;
use crate::error::{Error, Location, Result};
use crate::geometry::InstanceTransform;
use crate::io::placements::read_placements;
use crate::shading::material::Material;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant};

const TOO_FAR: &str = "the placement moves the mesh beyond the range of f32";

/// Whether the placed mesh's world bounds are finite (a huge scale or translation could overflow
/// them, and the structure's build and traversal need finite boxes).
fn fits(x: &InstanceTransform, bounds: crate::math::Aabb) -> bool {
    let b = x.bounds_to_world(bounds);
    b.min.is_finite() && b.max.is_finite()
}

/// Loads every declared mesh that an instance uses, builds its structure (of the scene's kind), and adds the instances
/// (their `shapeid` continues the numbering of the `[[shape]]` entries). Returns the time spent
/// building the prototypes' structures, which belongs to the build phase, not loading.
#[allow(clippy::too_many_arguments)]
pub(super) fn add_instances(
    d: &Description,
    base_dir: &Path,
    settings: &RenderSettings,
    geometry: &mut Geometry,
    materials: &mut Vec<Material>,
    extras: &mut FileExtras,
    material_index: impl Fn(&str) -> u32,
    steps: &Steps,
) -> Result<Duration> {
    let mut prototype_of: BTreeMap<&str, u32> = BTreeMap::new();
    let mut loaded = vec![];
    // Mesh files of `[[shape]]`s may already have made prototypes (glTF nodes sharing a mesh).
    let base = geometry.prototypes.len() as u32;
    for entry in &d.instances {
        if prototype_of.contains_key(entry.mesh.as_str()) {
            continue;
        }
        let Some(m) = d.meshes.get(&entry.mesh) else {
            return Err(Error::Invalid(format!("unknown mesh `{}`", entry.mesh)));
        };
        let mut mesh_geometry = Geometry::new(geometry.triangle_test);
        let material = m.material.as_deref().map(&material_index);
        let emitting = extras.emission.len();
        if m.file.is_empty() {
            // Written out in the scene; validation saw that each has a material.
            for t in &m.triangles {
                let own = t.material.as_deref().map(&material_index);
                let Some(mat) = own.or(material) else {
                    return Err(Error::Invalid(format!(
                        "mesh `{}`: a triangle mesh without a material",
                        entry.mesh
                    )));
                };
                mesh_geometry.push_mesh(super::basic_meshes::inline_mesh(t), mat);
            }
        } else {
            add_mesh_file(
                &mut mesh_geometry,
                materials,
                extras,
                &base_dir.join(&m.file),
                None,
                material,
                m.smooth_normals,
                settings.accel,
                &settings.accel_options,
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
        if extras.emission.len() > emitting {
            extras.emission.truncate(emitting);
            extras.warnings.push(format!(
                "{}: its emissive materials do not emit when the mesh is instanced",
                m.file
            ));
        }
        let label = if m.file.is_empty() {
            &entry.mesh
        } else {
            &m.file
        };
        steps.step(&format!("read {label}"))?;
        loaded.push((label, mesh_geometry));
        prototype_of.insert(&entry.mesh, base + loaded.len() as u32 - 1);
    }
    // The prototypes' structures are independent: build them side by side (each also splits its
    // own large nodes in parallel).
    if !loaded.is_empty() {
        steps.begin(&format!("building {} mesh structures", loaded.len()));
    }
    let start = Instant::now();
    let built: Result<Vec<Prototype>> = loaded
        .into_par_iter()
        .map(|(file, g)| {
            steps.check()?;
            let p = Prototype::new(g, settings.accel, &settings.accel_options);
            steps.step(&format!("built the structure of {file}"))?;
            Ok(p)
        })
        .collect();
    geometry.prototypes.extend(built?);
    let build = start.elapsed();
    for (k, entry) in d.instances.iter().enumerate() {
        let prototype = prototype_of[entry.mesh.as_str()];
        let bounds = geometry.prototypes[prototype as usize].bounds;
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
                geometry.push_instances(source, instances);
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
                geometry.push_instances(source, [instance(x)]);
            }
        }
    }
    Ok(build)
}
