//! What the scene's meshes span, from the file's JSON alone: every `POSITION` accessor must state
//! its `min` and `max` (glTF 2.0 section 3.7.2.1), so the box of each placed primitive is its
//! accessor's box through its node's transform, and no buffer needs to be read to frame the
//! scene.

use super::nodes::Placed;
use crate::math::{Aabb, Vec3};
use ::gltf::mesh::Mode;
use ::gltf::Semantic;

/// What the meshes of the scene bring to its view.
pub struct MeshExtent {
    /// The world box of the placed triangle primitives, or `None` where a `POSITION` accessor
    /// does not state its bounds (the file is then read whole to find them).
    pub bounds: Option<Aabb>,
    /// Whether a primitive has a material: glTF's materials are metallic-roughness ones, which the
    /// mesh reader maps onto physically based materials.
    pub physically_based: bool,
}

/// The box and materials of the primitives the mesh reader renders (triangle mode only).
pub fn mesh_extent(placed: &[Placed]) -> MeshExtent {
    let mut bounds = Some(Aabb::EMPTY);
    let mut physically_based = false;
    for p in placed {
        let Some(mesh) = p.node.mesh() else { continue };
        for prim in mesh.primitives().filter(|q| q.mode() == Mode::Triangles) {
            physically_based |= prim.material().index().is_some();
            let corners = prim
                .get(&Semantic::Positions)
                .and_then(|a| Some((vec3(a.min()?)?, vec3(a.max()?)?)));
            bounds = match (bounds, corners) {
                (Some(b), Some((lo, hi))) => Some((0..8).fold(b, |b, i| {
                    let corner = Vec3::new(
                        if i & 1 == 0 { lo.x } else { hi.x },
                        if i & 2 == 0 { lo.y } else { hi.y },
                        if i & 4 == 0 { lo.z } else { hi.z },
                    );
                    b.include(p.world.transform_point3(corner))
                })),
                _ => None,
            };
        }
    }
    MeshExtent {
        bounds,
        physically_based,
    }
}

/// Three finite numbers.
fn vec3(v: ::gltf::json::Value) -> Option<Vec3> {
    let a = v.as_array()?;
    let x = |i: usize| {
        a.get(i)?
            .as_f64()
            .map(|x| x as f32)
            .filter(|x| x.is_finite())
    };
    (a.len() == 3).then_some(())?;
    Some(Vec3::new(x(0)?, x(1)?, x(2)?))
}
