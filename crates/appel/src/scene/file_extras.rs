//! What a scene's mesh files brought besides triangles, kept with the scene for those who frame or
//! report it.

use crate::description::loaded_mesh::FileCamera;
use crate::description::LightDesc;
use crate::shading::texture::Texture;

/// What mesh files bring besides triangles and materials: emitting surfaces, lights, cameras and
/// warnings.
#[derive(Clone, Debug, Default)]
pub struct FileExtras {
    /// Top-level surfaces (by `Geometry::shapes` index) that emit, with their radiance.
    pub emission: Vec<(u32, Texture)>,
    pub lights: Vec<LightDesc>,
    pub cameras: Vec<FileCamera>,
    pub warnings: Vec<String>,
    /// Whether any file material maps onto a physically based material (the Monte Carlo
    /// integrators then show it as meant).
    pub physically_based: bool,
}
