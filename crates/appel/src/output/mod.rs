//! Output writers: images (PNG, EXR with AOVs) and binary PLY meshes, each written atomically
//! (whole or not at all).

mod atomic;
pub mod heatmap;
pub mod image;
mod ply_write;

pub use atomic::write_atomically;
pub use ply_write::write_ply;
