//! Files in and out: images now, mesh formats with the geometry work.

mod atomic;
pub mod image;
mod ply_write;

pub use ply_write::write_ply;

pub use atomic::write_atomically;
