//! The file's cameras (glTF 2.0 section 3.10), in the order the scene's traversal meets their
//! nodes: the first is the scene's view, the others are there to be chosen.

use super::nodes::Placed;
use crate::description::loaded_mesh::FileCamera;
use std::path::Path;

/// Each camera node's camera in world space, mapped as the mesh reader maps them
/// ([`crate::io::gltf::file_camera`]: looking down the node's -z with +y up; perspective with
/// `yfov`, `aspectRatio` and `znear`, or orthographic with `xmag` as the half width). A camera
/// whose node's transform leaves no view direction is left out with a warning.
pub fn cameras(placed: &[Placed], path: &Path, warnings: &mut Vec<String>) -> Vec<FileCamera> {
    let mut out = vec![];
    for p in placed {
        let Some(camera) = p.node.camera() else {
            continue;
        };
        match crate::io::gltf::file_camera(&camera, p.world, &p.node) {
            Ok(c) => out.push(c),
            Err(w) => warnings.push(format!("{}: {w}", path.display())),
        }
    }
    out
}
