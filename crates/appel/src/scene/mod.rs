//! From a scene description to a scene ready to render: geometry, acceleration structure, materials,
//! lights and camera.

mod basic_meshes;
pub mod builtin;
mod camera;
mod emitters;
mod file_materials;
mod frame;
mod geometry;
mod instance;
mod instance_entries;
mod memory;
mod mesh_shape;
mod progress;
mod queries;
mod sequence;
mod shading_materials;
mod textures;

use crate::description::animation;
use crate::description::{self, Description, ShapeDesc};
pub use camera::Camera;
pub use emitters::{SceneEmitters, NO_EMITTER};
pub use frame::{frame_model, model_description, view_model};
pub use geometry::{
    Geometry, PrimRef, PrimRefs, SceneHit, Shape, ShapeKind, ShapeSource, NO_INSTANCE,
};
pub use instance::{Instance, Prototype};
pub use memory::{estimate_memory, MemoryEstimate};
pub use mesh_shape::FileExtras;
pub use progress::{LoadStep, SceneOptions};
pub use sequence::{FrameUpdate, Sequence, REBUILD_FACTOR};

use crate::accel::{Accel, AccelKind, AccelOptions, AccelStats};
use crate::error::{Error, Location, Result};
use crate::geometry::{
    Cylinder, Implicit, ObjectTransform, Plane, SdfGrid, SdfNormals, Sphere, Torus, TriangleMesh,
    TriangleTest,
};
use crate::math::{Vec2, Vec3};
use std::path::Path;
use std::time::{Duration, Instant};

/// Which integrator renders the scene.
pub use crate::description::IntegratorName as IntegratorKind;

#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub integrator: IntegratorKind,
    pub max_depth: i32,
    pub rr_depth: u32,
    pub hide_emitters: bool,
    pub spp: u32,
    pub sampler: description::SamplerName,
    pub seed: u64,
    pub filter: description::FilterDesc,
    pub accel: AccelKind,
    /// `[render.NAME]` of each structure.
    pub accel_options: AccelOptions,
    /// `[render.NAME]` of each integrator.
    pub integrator_params: description::IntegratorParams,
}

/// How long building the scene took, phase by phase.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneTimings {
    /// Reading files and creating the geometry.
    pub load: Duration,
    /// Building the acceleration structure.
    pub build: Duration,
}

/// A scene ready to render.
#[derive(Clone, Debug)]
pub struct Scene {
    pub camera: Camera,
    pub settings: RenderSettings,
    pub geometry: Geometry,
    pub accel: Accel,
    /// The materials of every integrator, by the index each surface carries (see
    /// [`crate::shading::material::Material`]).
    pub shading_materials: Vec<crate::shading::material::Material>,
    /// Whether any material is a mask (cut-outs), which rays must then step through.
    pub has_masks: bool,
    /// The lights of every integrator: every `[[light]]` and emitting surface.
    pub emitters: SceneEmitters,
    /// What `whitted` and `raycast` show where a ray leaves the scene.
    pub background: Vec3,
    /// The ambient light of `whitted` and `raycast`, weighted by each material's `ambient`.
    pub ambient: Vec3,
    pub timings: SceneTimings,
    /// What the scene's mesh files brought besides triangles (materials, emitting surfaces, lights,
    /// cameras, warnings).
    pub from_files: FileExtras,
}

impl Scene {
    /// Builds a scene from a validated description. `base_dir` resolves relative file names.
    pub fn new(d: &Description, base_dir: &Path) -> Result<Scene> {
        Self::new_with(d, base_dir, SceneOptions::default())
    }

    /// [`Self::new`], reporting each file read and structure built, and stopping when cancelled.
    pub fn new_with(d: &Description, base_dir: &Path, options: SceneOptions) -> Result<Scene> {
        // An animated description renders as its first frame (`Sequence` for the others).
        let first_frame;
        let d = if animation::is_animated(d) {
            first_frame = animation::at_frame(d, 0);
            &first_frame
        } else {
            d
        };
        let load_start = Instant::now();
        let used_meshes = d
            .meshes
            .keys()
            .filter(|name| d.instances.iter().any(|i| &i.mesh == *name))
            .count() as u64;
        let mesh_shapes = d
            .shapes
            .iter()
            .filter(|s| matches!(s, ShapeDesc::Mesh(_)))
            .count() as u64;
        let steps = progress::Steps::new(options, mesh_shapes + 2 * used_meshes + 1);
        let skip_top_level = options.skip_top_level;
        let settings = RenderSettings {
            integrator: d.render.integrator,
            max_depth: d.render.max_depth,
            rr_depth: d.render.rr_depth,
            hide_emitters: d.render.hide_emitters,
            spp: d.render.spp,
            sampler: d.render.image_integrator().sampler(d.render.sampler),
            seed: d.render.seed,
            filter: d.render.filter,
            accel: AccelKind::from_name(&d.render.accel).ok_or_else(|| {
                Error::Invalid(format!(
                    "unknown acceleration structure `{}`",
                    d.render.accel
                ))
            })?,
            accel_options: d.render.accel_options(),
            integrator_params: d.render.integrator_params(),
        };
        // What the declared meshes' structures are built as.
        let build_settings = RenderSettings {
            accel: if options.skip_structures {
                AccelKind::Brute
            } else {
                settings.accel
            },
            ..settings.clone()
        };
        // Validation has rejected other names.
        let triangle_test = TriangleTest::from_name(&d.render.triangle).unwrap_or_default();
        // Material 0 is the default grey diffuse of shapes that name none.
        let names: Vec<&String> = d.materials.keys().collect();
        let mut textures = textures::TextureCache::new(base_dir);
        let mut materials = shading_materials::build(d, &mut textures)?;
        let mut geometry = Geometry::new(triangle_test);
        let mut from_files = FileExtras::default();
        for (index, s) in d.shapes.iter().enumerate() {
            let first_new_shape = geometry.shapes.len();
            let first_new_instance = geometry.instances.len();
            let material = s
                .material()
                .and_then(|m| names.iter().position(|n| *n == m))
                .map_or(0, |i| i as u32 + 1);
            match s {
                ShapeDesc::Sphere(s) => {
                    let id = geometry.push(
                        ShapeKind::Sphere(Sphere::new(s.center.into(), s.radius)),
                        material,
                    );
                    if let Some(rows) = s.mitsuba_uv {
                        let rows = glam::Mat3::from_cols_array_2d(&rows).transpose();
                        geometry.set_sphere_uv_frame(id, rows);
                    }
                }
                ShapeDesc::Plane(p) => {
                    let plane =
                        Plane::rectangle(p.point.into(), p.normal.into(), p.size.map(Vec2::from));
                    geometry.push(ShapeKind::Plane(plane), material);
                }
                ShapeDesc::Triangle(t) => {
                    let mesh = TriangleMesh {
                        positions: t.vertices.iter().map(|&p| p.into()).collect(),
                        indices: vec![[0, 1, 2]],
                        normals: None,
                        uvs: None,
                    };
                    geometry.push_mesh(mesh, material);
                }
                ShapeDesc::Implicit(i) => {
                    let bounds = crate::math::Aabb::new(i.bounds[0].into(), i.bounds[1].into());
                    let implicit = Implicit::new(&i.f, bounds)
                        .map_err(|e| Error::Invalid(format!("in the formula `{}`, {e}", i.f)))?;
                    let transform = match &i.transform {
                        Some(t) => Some(ObjectTransform::new(t.matrix()).ok_or_else(|| {
                            Error::Invalid(
                                "the implicit surface's transform is not invertible".into(),
                            )
                        })?),
                        None => None,
                    };
                    geometry.push_implicit(implicit, transform, material);
                }
                ShapeDesc::Torus(t) => {
                    let axis = t.axis.unwrap_or([0.0, 1.0, 0.0]);
                    let torus =
                        Torus::new(t.center.into(), t.major_radius, t.minor_radius, axis.into());
                    geometry.push(ShapeKind::Torus(torus), material);
                }
                ShapeDesc::Cylinder(c) => {
                    let cylinder =
                        Cylinder::new(c.to_world(), c.flip_normals).ok_or_else(|| {
                            Error::Invalid(format!(
                                "shape[{index}]: the cylinder's transform is not invertible"
                            ))
                        })?;
                    geometry.push(ShapeKind::Cylinder(Box::new(cylinder)), material);
                }
                ShapeDesc::SdfGrid(g) => {
                    let path = base_dir.join(&g.file);
                    let grid = crate::io::grid_volume::read_grid_volume(&path)?;
                    let at = |msg: String| Error::input(Location::file(&path), msg);
                    if grid.channels != 1 {
                        return Err(at(format!(
                            "an SDF grid has one channel, this volume has {}",
                            grid.channels
                        )));
                    }
                    let normals = match g.normals {
                        description::SdfNormalsDesc::Smooth => SdfNormals::Smooth,
                        description::SdfNormalsDesc::Analytic => SdfNormals::Analytic,
                    };
                    let m = g
                        .transform
                        .as_ref()
                        .map_or(glam::Mat4::IDENTITY, |t| t.matrix());
                    let sdf = SdfGrid::new(grid.resolution, grid.data, m, normals).map_err(at)?;
                    geometry.push(ShapeKind::SdfGrid(std::sync::Arc::new(sdf)), material);
                }
                ShapeDesc::Rectangle(b) | ShapeDesc::Cube(b) | ShapeDesc::Disk(b) => {
                    let mesh = match s {
                        ShapeDesc::Rectangle(_) => basic_meshes::rectangle(),
                        ShapeDesc::Cube(_) => basic_meshes::cube(),
                        _ => basic_meshes::disk(),
                    };
                    let m = b
                        .transform
                        .as_ref()
                        .map_or(glam::Mat4::IDENTITY, |t| t.matrix());
                    let mut mesh = basic_meshes::transformed(mesh, m);
                    if b.flip_normals {
                        basic_meshes::flip_normals(&mut mesh);
                    }
                    geometry.push_mesh(mesh, material);
                }
                ShapeDesc::TriangleMesh(t) => {
                    geometry.push_mesh(basic_meshes::inline_mesh(t), material);
                }
                ShapeDesc::Mesh(m) => {
                    mesh_shape::add_mesh_file(
                        &mut geometry,
                        &mut materials,
                        &mut from_files,
                        &base_dir.join(&m.file),
                        m.transform.as_ref(),
                        m.material.is_some().then_some(material),
                        m.smooth_normals,
                        build_settings.accel,
                        &settings.accel_options,
                    )?;
                    steps.step(&format!("read {}", m.file))?;
                    for shape in &geometry.shapes[first_new_shape..] {
                        let ShapeKind::Mesh(k) = shape.kind else {
                            continue;
                        };
                        let mesh = &mut geometry.meshes[k as usize];
                        if m.face_normals {
                            mesh.normals = None;
                        }
                        if m.flip_normals {
                            basic_meshes::flip_normals(mesh);
                        }
                    }
                }
            }
            // A mesh file may have become several surfaces: all report this `[[shape]]`.
            for shape in &mut geometry.shapes[first_new_shape..] {
                shape.source.shape = index as u32;
            }
            for instance in &mut geometry.instances[first_new_instance..] {
                instance.source = index as u32;
            }
        }
        let prototype_build = instance_entries::add_instances(
            d,
            base_dir,
            &build_settings,
            &mut geometry,
            &mut materials,
            &mut from_files,
            |m| {
                names
                    .iter()
                    .position(|n| *n == m)
                    .map_or(0, |i| i as u32 + 1)
            },
            &steps,
        )?;
        let load = load_start.elapsed() - prototype_build;
        steps.begin(&format!(
            "building the top-level structure ({} primitives)",
            geometry.prims.len()
        ));
        let build_start = Instant::now();
        let top_level = if skip_top_level || options.skip_structures {
            AccelKind::Brute
        } else {
            settings.accel
        };
        let accel = Accel::build_with(top_level, &geometry, &settings.accel_options);
        let build = build_start.elapsed() + prototype_build;
        let emitters = SceneEmitters::build(d, &geometry, &from_files.emission, &mut textures)?;
        let has_masks = materials.iter().any(|m| m.has_mask());
        steps.step("built the top-level structure")?;
        Ok(Scene {
            camera: Camera::new(&d.camera),
            settings,
            geometry,
            accel,
            shading_materials: materials,
            emitters,
            has_masks,
            background: d.environment.background.into(),
            ambient: d.environment.ambient.into(),
            timings: SceneTimings { load, build },
            from_files,
        })
    }

    /// Replaces the camera, lights and environment with those of `d` (geometry and settings stay):
    /// used to frame a bare mesh file once its bounds are known.
    pub fn set_view(&mut self, d: &Description) -> Result<()> {
        self.camera = Camera::new(&d.camera);
        self.emitters = SceneEmitters::build(
            d,
            &self.geometry,
            &self.from_files.emission,
            &mut textures::TextureCache::new(Path::new(".")),
        )?;
        self.background = d.environment.background.into();
        self.ambient = d.environment.ambient.into();
        Ok(())
    }

    pub fn accel_stats(&self) -> AccelStats {
        let mut s = self.accel.stats();
        s.build_time = self.timings.build;
        s
    }
}
