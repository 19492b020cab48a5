//! From a scene description to a scene ready to render: a [`SceneBuilder`] owns what building needs
//! (the geometry so far, the materials, what mesh files bring besides triangles, the texture cache,
//! progress and the settings) and adds each `[[shape]]` through the [`AddShape`] of its kind, then
//! the declared meshes and their instances, then builds the structures, emitters and materials.
//!
//! `Scene::new` and `Scene::new_with` are written here rather than in `scene/`, so that the runtime
//! scene names nothing of how it is built.

mod basic_meshes;
mod emitters;
mod file_materials;
mod frame;
mod instance_entries;
mod media;
mod memory;
mod mesh_shape;
mod progress;
mod sequence;
mod shading_materials;
mod shapes;
mod textures;

pub use frame::{frame_model, model_description, view_model};
pub use memory::{estimate_memory, MemoryEstimate};
pub use progress::{LoadStep, SceneOptions};
pub use sequence::{FrameUpdate, Sequence, REBUILD_FACTOR};

use crate::accel::{Accel, AccelKind};
use crate::description::animation;
use crate::description::{Description, ShapeDesc};
use crate::error::{Error, Result};
use crate::geometry::TriangleTest;
use crate::scene::{
    Camera, FileExtras, Geometry, RenderSettings, Scene, SceneEmitters, SceneTimings,
};
use crate::shading::material::Material;
use progress::Steps;
use std::path::Path;
use std::time::Instant;
use textures::TextureCache;

impl Scene {
    /// Builds a scene from a validated description. `base_dir` resolves relative file names.
    pub fn new(d: &Description, base_dir: &Path) -> Result<Scene> {
        Self::new_with(d, base_dir, SceneOptions::default())
    }

    /// [`Self::new`], reporting each file read and structure built, and stopping when cancelled.
    pub fn new_with(d: &Description, base_dir: &Path, options: SceneOptions) -> Result<Scene> {
        // An animated description renders as its first frame (`Sequence` for the others).
        if animation::is_animated(d) {
            let first_frame = animation::at_frame(d, 0);
            return SceneBuilder::new(&first_frame, base_dir, options)?.build();
        }
        SceneBuilder::new(d, base_dir, options)?.build()
    }

    /// Replaces the camera, lights and environment with those of `d` (geometry and settings stay):
    /// used to frame a bare mesh file once its bounds are known.
    pub fn set_view(&mut self, d: &Description) -> Result<()> {
        self.camera = Camera::new(&d.camera);
        self.emitters = SceneEmitters::build(
            d,
            &self.geometry,
            &self.from_files.emission,
            &mut TextureCache::new(Path::new(".")),
        )?;
        self.background = d.environment.background.into();
        self.ambient = d.environment.ambient.into();
        Ok(())
    }
}

/// The `[[shape]]` being added: its place in the description and the index of its material.
#[derive(Clone, Copy, Debug)]
pub struct Entry {
    pub index: usize,
    pub material: u32,
}

/// One kind of `[[shape]]`: how its description becomes surfaces of the scene being built.
pub trait AddShape {
    fn add(&self, b: &mut SceneBuilder, entry: Entry) -> Result<()>;
}

/// A scene being built from its description.
pub struct SceneBuilder<'a> {
    d: &'a Description,
    base_dir: &'a Path,
    /// The scene's settings, as it will render.
    settings: RenderSettings,
    /// What the declared meshes' and mesh files' own structures are built as.
    prototype_accel: AccelKind,
    options: SceneOptions<'a>,
    steps: Steps<'a>,
    geometry: Geometry,
    /// The materials of every integrator: material 0 is the default grey `phong` of shapes that
    /// name none, then the described ones, then mesh files' as they are read.
    materials: Vec<Material>,
    from_files: FileExtras,
    textures: TextureCache<'a>,
}

impl<'a> SceneBuilder<'a> {
    /// A builder of `d` (a single frame: see [`animation::at_frame`]), with its settings read and
    /// its described materials made, and no geometry yet.
    pub fn new(d: &'a Description, base_dir: &'a Path, options: SceneOptions<'a>) -> Result<Self> {
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
        let steps = Steps::new(options, mesh_shapes + 2 * used_meshes + 1);
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
        let prototype_accel = if options.skip_structures {
            AccelKind::Brute
        } else {
            settings.accel
        };
        // Validation has rejected other names.
        let triangle_test = TriangleTest::from_name(&d.render.triangle).unwrap_or_default();
        let mut textures = TextureCache::new(base_dir);
        let materials = shading_materials::build(d, &mut textures)?;
        Ok(Self {
            d,
            base_dir,
            settings,
            prototype_accel,
            options,
            steps,
            geometry: Geometry::new(triangle_test),
            materials,
            from_files: FileExtras::default(),
            textures,
        })
    }

    /// The scene: every shape, the declared meshes and their instances, the structures, emitters
    /// and materials.
    pub fn build(mut self) -> Result<Scene> {
        let load_start = Instant::now();
        let d = self.d;
        for (index, s) in d.shapes.iter().enumerate() {
            self.add_shape(index, s)?;
        }
        let prototype_build = self.add_instances()?;
        let load = load_start.elapsed() - prototype_build;
        self.steps.begin(&format!(
            "building the top-level structure ({} primitives)",
            self.geometry.prims.len()
        ));
        let build_start = Instant::now();
        let top_level = if self.options.skip_top_level || self.options.skip_structures {
            AccelKind::Brute
        } else {
            self.settings.accel
        };
        let accel = Accel::build_with(top_level, &self.geometry, &self.settings.accel_options);
        let build = build_start.elapsed() + prototype_build;
        let emitters = SceneEmitters::build(
            d,
            &self.geometry,
            &self.from_files.emission,
            &mut self.textures,
        )?;
        let media = media::build(d, &self.geometry, self.base_dir)?;
        let has_masks = self.materials.iter().any(|m| m.has_mask());
        self.steps.step("built the top-level structure")?;
        Ok(Scene {
            camera: Camera::new(&d.camera),
            settings: self.settings,
            geometry: self.geometry,
            accel,
            shading_materials: self.materials,
            emitters,
            media,
            has_masks,
            background: d.environment.background.into(),
            ambient: d.environment.ambient.into(),
            timings: SceneTimings { load, build },
            from_files: self.from_files,
        })
    }

    /// Adds `[[shape]]` number `index`: the surfaces it becomes all report it as their source.
    fn add_shape(&mut self, index: usize, s: &ShapeDesc) -> Result<()> {
        let first_new_shape = self.geometry.shapes.len();
        let first_new_instance = self.geometry.instances.len();
        let entry = Entry {
            index,
            material: s.material().map_or(0, |m| self.material_index(m)),
        };
        match s {
            ShapeDesc::Sphere(s) => s.add(self, entry),
            ShapeDesc::Plane(p) => p.add(self, entry),
            ShapeDesc::Triangle(t) => t.add(self, entry),
            ShapeDesc::Implicit(i) => i.add(self, entry),
            ShapeDesc::Torus(t) => t.add(self, entry),
            ShapeDesc::Cylinder(c) => c.add(self, entry),
            ShapeDesc::SdfGrid(g) => g.add(self, entry),
            ShapeDesc::Rectangle(b) => shapes::Basic::rectangle(b).add(self, entry),
            ShapeDesc::Cube(b) => shapes::Basic::cube(b).add(self, entry),
            ShapeDesc::Disk(b) => shapes::Basic::disk(b).add(self, entry),
            ShapeDesc::TriangleMesh(t) => t.add(self, entry),
            ShapeDesc::Mesh(m) => m.add(self, entry),
        }?;
        // A mesh file may have become several surfaces: all report this `[[shape]]`.
        for shape in &mut self.geometry.shapes[first_new_shape..] {
            shape.source.shape = index as u32;
        }
        for instance in &mut self.geometry.instances[first_new_instance..] {
            instance.source = index as u32;
        }
        Ok(())
    }

    /// The index of the described material `name` in the scene's list (0, the default, for a name
    /// the description does not have).
    fn material_index(&self, name: &str) -> u32 {
        self.d
            .materials
            .keys()
            .position(|n| n == name)
            .map_or(0, |i| i as u32 + 1)
    }
}
