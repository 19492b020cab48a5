//! Leaf input readers: triangle meshes (PLY, OBJ, glTF, Mitsuba's serialized), images, archives, grid
//! volumes, placement and point lists. Scene files are read by `format`; writers are in
//! `output`.

pub mod assets;
pub mod bitmap_read;
pub mod gltf;
pub mod gltf_lights;
pub mod grid_volume;
pub mod json_path;
pub mod mesh_file;
pub mod mikktspace_tangents;
pub mod obj;
pub mod pfm;
pub mod placements;
pub mod ply;
pub mod points;
pub mod serialized;
pub mod text;
pub mod vertex_normals;

pub use mesh_file::{is_mesh_file, load_mesh, mesh_source_exists};
