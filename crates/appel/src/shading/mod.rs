//! What surfaces and lights do to light, independent of how the image is rendered: BSDFs in their
//! local shading frame, textures, emitters, and Mitsuba's named optical constants. The scene
//! builds them from its description; the integrators in `render` evaluate and sample them.

pub mod bsdf;
#[cfg(test)]
pub(crate) mod chi2;
pub mod emitter;
pub mod frame;
pub mod material;
pub mod medium;
pub mod perturb;
pub use crate::description::spectra;
pub mod texture;
