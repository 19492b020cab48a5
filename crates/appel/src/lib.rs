//! Appel: a fast, correct CPU ray tracer.
//!
//! The crate is layered so that data flows one way (see `docs/architecture.md`), bottom to top:
//! `math`, `error` -> `geometry` -> `accel` -> `description` (the scene description and the values
//! readers and shading share) -> `io` (leaf readers: meshes, images, archives) -> `shading`,
//! `format` (scene formats) -> `scene` -> `render` -> `output`, `query`, `api`.
//! Nothing in a lower layer names anything of a higher one, and nothing here knows about the command line.

pub mod accel;
pub mod api;
pub mod description;
pub mod error;
pub mod format;
pub mod geometry;
pub mod io;
pub mod math;
pub mod output;
pub mod query;
pub mod render;
pub mod scene;
pub mod shading;

pub use error::{Error, Result};
