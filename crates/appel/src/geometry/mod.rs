//! Ray-surface intersection for each kind of surface, and the local surface description at a hit.
//!
//! Every intersector returns the smallest `t` in `(0, t_max)` (a cheap [`PrimHit`]); the full
//! [`SurfaceInteraction`] is computed once, for the final hit only.

mod cylinder;
mod file_tangent;
pub mod implicit;
mod instance_transform;
mod mesh;
mod overlap;
mod plane;
pub mod poly;
pub mod procedural;
mod sdf_grid;
mod sphere;
mod torus;
mod transform;
pub mod triangle;

pub use cylinder::Cylinder;
pub use file_tangent::FileTangent;
pub use implicit::Implicit;
pub use instance_transform::InstanceTransform;
pub use mesh::TriangleMesh;
pub use overlap::triangle_box_overlap;
pub use plane::Plane;
pub use sdf_grid::{SdfGrid, SdfNormals};
pub use sphere::{Sphere, SphereBlock};
pub use torus::Torus;
pub use transform::ObjectTransform;
pub use triangle::TriangleTest;

use crate::math::{Vec2, Vec3};

/// What traversal carries around: the ray parameter and two surface coordinates (barycentrics for a
/// triangle), enough to compute the full interaction later.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimHit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
    /// The primitive hit inside a nested structure (a mesh instance's own triangles); 0 for a plain
    /// surface.
    pub sub: u32,
}

impl PrimHit {
    /// What an any-hit (shadow ray) test reports for a hit: only that there is one, before `t_max`.
    #[inline]
    pub fn any_hit(t_max: f32) -> Self {
        Self {
            t: t_max,
            u: 0.0,
            v: 0.0,
            sub: 0,
        }
    }
}

/// The local geometry at a hit point.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction {
    /// The hit point, refined onto the surface where the surface allows it.
    pub p: Vec3,
    /// A conservative bound on the absolute rounding error of each coordinate of `p`.
    pub p_error: Vec3,
    /// Unit geometric normal, pointing to the outside of the surface (for triangles: by winding).
    pub n: Vec3,
    /// Unit shading normal (interpolated vertex normal where a mesh has them), same side as `n`.
    pub ns: Vec3,
    /// Surface coordinates used by textures.
    pub uv: Vec2,
    /// The surface's derivative along `u` (not normalized; zero where a surface has no
    /// parametrization). The shading frame's tangent follows it (unless the file gives
    /// `tangent`), as Mitsuba 3's
    /// `SurfaceInteraction::initialize_sh_frame` does, so anisotropic BSDFs and normal maps are
    /// oriented by the texture coordinates.
    pub dpdu: Vec3,
    /// The derivative along `v` (zero where `dpdu` is), which bump maps need.
    pub dpdv: Vec3,
    /// The tangent frame a mesh file gives at the point (glTF's `TANGENT`), which then orients
    /// the shading frame instead of `dpdu`; `None` elsewhere.
    pub tangent: Option<FileTangent>,
}

impl SurfaceInteraction {
    /// The direction the shading frame's tangent follows: the file's tangent where it gives one,
    /// else dp/du.
    #[inline]
    pub fn shading_tangent(&self) -> Vec3 {
        self.tangent.map_or(self.dpdu, |t| t.dir)
    }

    /// The side of `ns × s` tangent-space y (a normal map's green channel) runs on: the file's
    /// handedness where it gives tangents, else +1 (the bitangent `ns × dp/du`).
    #[inline]
    pub fn bitangent_sign(&self) -> f32 {
        self.tangent.map_or(1.0, |t| t.sign)
    }
}
