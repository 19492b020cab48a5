//! Appel: a fast, correct CPU ray tracer.
//!
//! The crate is layered so that data flows one way (see `docs/architecture.md`):
//! input readers (`io`) -> `math` -> `geometry` -> `accel` -> `shading` -> `scene` -> `render`
//! -> `output`.
//! Nothing in a lower layer names anything of a higher one, and nothing here knows about the command line.

pub mod accel;
pub mod api;
pub mod error;
pub mod geometry;
pub mod io;
pub mod math;
pub mod output;
pub mod query;
pub mod render;
pub mod scene;
pub mod shading;

pub use error::{Error, Result};
