//! Files in and out: images, and triangle meshes (PLY, OBJ, glTF).

mod atomic;
pub mod gltf;
pub mod image;
pub mod mesh_file;
pub mod mitsuba;
pub mod obj;
pub mod placements;
pub mod ply;
mod ply_write;
pub mod points;

pub use ply_write::write_ply;

pub use atomic::write_atomically;
pub use mesh_file::{is_mesh_file, load_mesh, FileMaterial, LoadedMesh, MeshPart, SharedPlacement};
