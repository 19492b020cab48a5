//! `appel gen`: large reproducible scenes for measuring Appel at scale (issue 5). Everything comes
//! from one seed through [`SplitMix64`](appel::geometry::procedural::SplitMix64) and integer-hashed
//! noise, so the same seed gives the same bytes on every machine.
//!
//! - `ecosystem`: a terrain and a forest of instanced plants, one scene file, binary PLY meshes and
//!   text placement lists;
//! - `city`: buildings with recessed windows, one binary PLY mesh, no instancing.

mod builder;
pub mod city;
pub mod cloth;
mod ecosystem;
mod noise;
pub mod plants;
pub mod terrain;

pub use builder::MeshBuilder;
pub use cloth::cloth_scene;
pub use ecosystem::{ecosystem, species_list, Species};

use appel::error::{Error, Result};
use std::path::Path;

/// What a generator is asked for.
#[derive(Clone, Copy, Debug)]
pub struct GenOptions {
    pub seed: u64,
    /// Multiplies the number of plant placements (ecosystem only).
    pub density: f64,
    /// Multiplies every mesh's triangle budget: 1 gives the full-size scenes, small values quick
    /// test scenes of the same structure.
    pub detail: f64,
}

impl Default for GenOptions {
    fn default() -> Self {
        Self {
            seed: 1,
            density: 1.0,
            detail: 1.0,
        }
    }
}

/// What a generator wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GenReport {
    /// The scene file, then every other file, relative to the output folder.
    pub files: Vec<String>,
    /// Triangles stored in the mesh files.
    pub unique_triangles: u64,
    /// Triangles as rendered: each placement counts its mesh once more.
    pub instanced_triangles: u64,
    pub instances: u64,
}

/// The city: one binary PLY of at least `10^7 * detail` triangles and a scene file around it;
/// `step` as for [`ecosystem`].
pub fn city_scene(
    dir: &Path,
    options: &GenOptions,
    step: &dyn Fn(&str) -> Result<()>,
) -> Result<GenReport> {
    let target = (1e7 * options.detail).max(1000.0) as usize;
    step(&format!("building a city of at least {target} triangles"))?;
    let (mesh, extent) = city::city(target, options.seed);
    let mesh = mesh.into_mesh();
    let triangles = mesh.triangle_count() as u64;
    step(&format!("writing city.ply ({triangles} triangles)"))?;
    appel::output::write_ply(&dir.join("city.ply"), &[(0, &mesh)])?;
    drop(mesh);
    let e = extent;
    let scene = format!(
        r#"# `appel gen city --seed {seed}`: {triangles} triangles in one mesh, no instancing.
[camera]
eye = [{ex}, {ey}, {ez}]
look_at = [0.0, 90.0, 0.0]
fov = 50.0
width = 1920
height = 1080

[render]
integrator = "whitted"
max_depth = 3

[environment]
background = [0.55, 0.7, 0.9]
ambient = [0.45, 0.5, 0.6]

[materials.concrete]
color = [0.78, 0.74, 0.68]
ambient = 0.35
diffuse = 0.75
specular = 0.15
shininess = 40.0

[materials.street]
color = [0.25, 0.25, 0.27]
ambient = 0.3
reflection = 0.15

[[shape]]
type = "mesh"
file = "city.ply"
material = "concrete"

[[shape]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = [{size}, {size}]
material = "street"

[[light]]
type = "directional"
direction = [-0.55, -0.45, -0.7]
intensity = 1.1
"#,
        seed = options.seed,
        ex = 0.8 * e,
        ey = 0.4 * e,
        ez = 1.05 * e,
        size = 2.2 * e,
    );
    step("writing city.toml")?;
    appel::output::write_atomically(&dir.join("city.toml"), |out| {
        use std::io::Write;
        out.write_all(scene.as_bytes())
            .map_err(|e| Error::io(dir.join("city.toml"), e))
    })?;
    Ok(GenReport {
        files: vec!["city.toml".into(), "city.ply".into()],
        unique_triangles: triangles,
        instanced_triangles: triangles,
        instances: 0,
    })
}
