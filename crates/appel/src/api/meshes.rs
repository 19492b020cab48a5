//! Scenes built from meshes given as arrays, placed where they are or by transforms.

use super::load::{apply_overrides, Override};
use super::SceneHandle;
use crate::accel::{Accel, AccelKind};
use crate::error::{Error, Result};
use crate::geometry::{InstanceTransform, TriangleMesh};
use crate::scene::{Geometry, Instance, Prototype, Scene};
use crate::scene_build::frame_model;
use glam::Mat4;
use std::path::Path;

/// A mesh's arrays, checked by the caller: indices in range, positions finite.
pub type MeshArrays = TriangleMesh;

/// Mesh `mesh` placed by `to_world`.
#[derive(Clone, Copy, Debug)]
pub struct Placement {
    pub mesh: usize,
    pub to_world: Mat4,
}

impl SceneHandle {
    /// A scene of `meshes`. Without `placements`, mesh `i` is shape `i`, where its vertices are;
    /// with them, placement `i` is shape `i` and instance `i`, of a prototype per mesh with its
    /// own structure (a mesh placed many times is stored once). The camera looks at the bounds
    /// unless `camera` overrides say otherwise; `accel` names the structure.
    pub fn from_meshes(
        meshes: Vec<MeshArrays>,
        placements: Option<Vec<Placement>>,
        camera: &[Override],
        accel: &str,
    ) -> Result<SceneHandle> {
        let kind = AccelKind::from_name(accel).ok_or_else(|| {
            Error::Invalid(format!(
                "accel: unknown structure `{accel}`, expected one of: {}",
                AccelKind::NAMES.join(", ")
            ))
        })?;
        let mut d = crate::scene_build::model_description("");
        d.shapes.clear();
        d.render.accel = accel.to_string();
        let mut scene = Scene::new(&d, Path::new("."))?;
        let options = scene.settings.accel_options;
        let mut geometry = Geometry::new(crate::geometry::TriangleTest::Watertight);
        match placements {
            None => {
                for m in meshes {
                    geometry.push_mesh(m, 0);
                }
            }
            Some(placements) => {
                let mut prototypes: Vec<Prototype> = meshes
                    .into_iter()
                    .map(|m| {
                        let mut g = Geometry::new(crate::geometry::TriangleTest::Watertight);
                        g.push_mesh(m, 0);
                        Prototype::new(g, kind, &options)
                    })
                    .collect();
                geometry.prototypes.append(&mut prototypes);
                for (i, p) in placements.iter().enumerate() {
                    if p.mesh >= geometry.prototypes.len() {
                        return Err(Error::Invalid(format!(
                            "transforms[{i}]: no mesh {}",
                            p.mesh
                        )));
                    }
                    let transform = InstanceTransform::new(p.to_world).ok_or_else(|| {
                        Error::Invalid(format!("transforms[{i}] is not invertible"))
                    })?;
                    let instance = Instance {
                        transform,
                        prototype: p.mesh as u32,
                        source: i as u32,
                        first_prim: 0,
                    };
                    geometry.push_instances(i as u32, [instance]);
                }
            }
        }
        scene.accel = Accel::build_with(kind, &geometry, &options);
        scene.geometry = geometry;
        let mut framed = frame_model(&d, scene.geometry.bounds());
        apply_overrides(&mut framed, camera)?;
        scene.set_view(&framed)?;
        Ok(SceneHandle::new(scene, framed.camera))
    }
}
