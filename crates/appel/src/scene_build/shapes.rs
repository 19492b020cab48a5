//! The `[[shape]]` kinds made from their description alone (every kind but mesh files, which
//! `mesh_shape` adds): each becomes one surface of the scene.

use super::{basic_meshes, AddShape, Entry, SceneBuilder};
use crate::description::{
    BasicShapeDesc, CylinderDesc, ImplicitDesc, PlaneDesc, SdfGridDesc, SdfNormalsDesc, SphereDesc,
    TorusDesc, TriangleDesc, TriangleMeshDesc,
};
use crate::error::{Error, Location, Result};
use crate::geometry::{
    Cylinder, Implicit, ObjectTransform, Plane, SdfGrid, SdfNormals, Sphere, Torus, TriangleMesh,
};
use crate::math::{Aabb, Vec2};
use crate::scene::ShapeKind;

impl AddShape for SphereDesc {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        let sphere = Sphere::new(self.center.into(), self.radius);
        let id = b.geometry.push(ShapeKind::Sphere(sphere), entry.material);
        if let Some(rows) = self.mitsuba_uv {
            let rows = glam::Mat3::from_cols_array_2d(&rows).transpose();
            b.geometry.set_sphere_uv_frame(id, rows);
        }
        Ok(())
    }
}

impl AddShape for PlaneDesc {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        let plane = Plane::rectangle(
            self.point.into(),
            self.normal.into(),
            self.size.map(Vec2::from),
        );
        b.geometry.push(ShapeKind::Plane(plane), entry.material);
        Ok(())
    }
}

impl AddShape for TriangleDesc {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        let mesh = TriangleMesh {
            positions: self.vertices.iter().map(|&p| p.into()).collect(),
            indices: vec![[0, 1, 2]],
            normals: None,
            uvs: None,
        };
        b.geometry.push_mesh(mesh, entry.material);
        Ok(())
    }
}

impl AddShape for ImplicitDesc {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        let bounds = Aabb::new(self.bounds[0].into(), self.bounds[1].into());
        let implicit = Implicit::new(&self.f, bounds)
            .map_err(|e| Error::Invalid(format!("in the formula `{}`, {e}", self.f)))?;
        let transform = match &self.transform {
            Some(t) => Some(ObjectTransform::new(t.matrix()).ok_or_else(|| {
                Error::Invalid("the implicit surface's transform is not invertible".into())
            })?),
            None => None,
        };
        b.geometry
            .push_implicit(implicit, transform, entry.material);
        Ok(())
    }
}

impl AddShape for TorusDesc {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        let axis = self.axis.unwrap_or([0.0, 1.0, 0.0]);
        let torus = Torus::new(
            self.center.into(),
            self.major_radius,
            self.minor_radius,
            axis.into(),
        );
        b.geometry.push(ShapeKind::Torus(torus), entry.material);
        Ok(())
    }
}

impl AddShape for CylinderDesc {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        let cylinder = Cylinder::new(self.to_world(), self.flip_normals).ok_or_else(|| {
            Error::Invalid(format!(
                "shape[{}]: the cylinder's transform is not invertible",
                entry.index
            ))
        })?;
        b.geometry
            .push(ShapeKind::Cylinder(Box::new(cylinder)), entry.material);
        Ok(())
    }
}

impl AddShape for SdfGridDesc {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        let path = b.base_dir.join(&self.file);
        let grid = crate::io::grid_volume::read_grid_volume(&path)?;
        let at = |msg: String| Error::input(Location::file(&path), msg);
        if grid.channels != 1 {
            return Err(at(format!(
                "an SDF grid has one channel, this volume has {}",
                grid.channels
            )));
        }
        let normals = match self.normals {
            SdfNormalsDesc::Smooth => SdfNormals::Smooth,
            SdfNormalsDesc::Analytic => SdfNormals::Analytic,
        };
        let m = self
            .transform
            .as_ref()
            .map_or(glam::Mat4::IDENTITY, |t| t.matrix());
        let sdf = SdfGrid::new(grid.resolution, grid.data, m, normals).map_err(at)?;
        b.geometry
            .push(ShapeKind::SdfGrid(std::sync::Arc::new(sdf)), entry.material);
        Ok(())
    }
}

/// Mitsuba's rectangle, cube and disk: a unit mesh placed by the shape's transform.
pub struct Basic<'d> {
    unit: fn() -> TriangleMesh,
    desc: &'d BasicShapeDesc,
}

impl<'d> Basic<'d> {
    pub fn rectangle(desc: &'d BasicShapeDesc) -> Self {
        let unit = basic_meshes::rectangle;
        Self { unit, desc }
    }

    pub fn cube(desc: &'d BasicShapeDesc) -> Self {
        let unit = basic_meshes::cube;
        Self { unit, desc }
    }

    pub fn disk(desc: &'d BasicShapeDesc) -> Self {
        let unit = basic_meshes::disk;
        Self { unit, desc }
    }
}

impl AddShape for Basic<'_> {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        let m = self
            .desc
            .transform
            .as_ref()
            .map_or(glam::Mat4::IDENTITY, |t| t.matrix());
        let mut mesh = basic_meshes::transformed((self.unit)(), m);
        if self.desc.flip_normals {
            basic_meshes::flip_normals(&mut mesh);
        }
        b.geometry.push_mesh(mesh, entry.material);
        Ok(())
    }
}

impl AddShape for TriangleMeshDesc {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()> {
        b.geometry
            .push_mesh(basic_meshes::inline_mesh(self), entry.material);
        Ok(())
    }
}
