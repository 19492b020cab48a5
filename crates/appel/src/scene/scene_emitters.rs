//! The scene's emitters, which every integrator reads: `[[light]]` entries and the surfaces with
//! an `emitter`, the power-based choice among them, and which surface emits as which emitter.

use crate::shading::emitter::{Emitter, LightPicker};

/// [`SceneEmitters::of_shape`] of a surface that does not emit.
pub const NO_EMITTER: u32 = u32::MAX;

#[derive(Clone, Debug)]
pub struct SceneEmitters {
    pub emitters: Vec<Emitter>,
    /// Chooses an emitter for next-event estimation in proportion to its power.
    pub picker: LightPicker,
    /// The emitter of each top-level surface (by `Geometry::shapes` index), or [`NO_EMITTER`].
    pub of_shape: Vec<u32>,
    /// The infinite emitters (environment), which rays leaving the scene see.
    pub infinite: Vec<u32>,
    /// The delta emitters (points, spots, projectors, directional lights), in order: the lights
    /// of `whitted` and `raycast`, which shade from every one with a shadow ray.
    pub delta: Vec<u32>,
    /// The scene's bounding sphere (centre, radius), through which an infinite light's rays
    /// enter in light tracing.
    pub sphere: (crate::math::Vec3, f32),
}
