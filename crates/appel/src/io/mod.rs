//! Files in and out: images now, mesh formats with the geometry work.

mod atomic;
pub mod image;

pub use atomic::write_atomically;
