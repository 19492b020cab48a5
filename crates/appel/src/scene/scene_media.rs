//! The scene's participating media: the list of media, the two media each surface separates
//! (indices into the list, 8 bytes per surface), and the camera's medium. A surface with a
//! medium on either side is a transition: a ray crossing it enters the exterior medium when it
//! leaves along the outward normal and the interior one otherwise (no medium is vacuum), as in
//! Mitsuba 3. Other surfaces leave the ray's medium as it was.

use super::{SceneHit, NO_INSTANCE};
use crate::math::Vec3;
use crate::shading::medium::Medium;

/// No medium: vacuum.
pub const NO_MEDIUM: u32 = u32::MAX;

/// The media on the two sides of a surface, by index into [`SceneMedia::media`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MediumInterface {
    /// Behind the outward normal.
    pub interior: u32,
    /// On the side of the outward normal.
    pub exterior: u32,
}

impl MediumInterface {
    pub const NONE: MediumInterface = MediumInterface {
        interior: NO_MEDIUM,
        exterior: NO_MEDIUM,
    };

    /// Whether crossing the surface changes the medium.
    #[inline]
    pub fn is_transition(&self) -> bool {
        *self != Self::NONE
    }

    /// The medium a ray leaving the surface along `dir` is in (`n` the outward normal).
    #[inline]
    pub fn target(&self, dir: Vec3, n: Vec3) -> u32 {
        if dir.dot(n) > 0.0 {
            self.exterior
        } else {
            self.interior
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct SceneMedia {
    pub media: Vec<Medium>,
    /// By `Geometry::shapes` index.
    pub of_shape: Vec<MediumInterface>,
    /// The camera's medium, or [`NO_MEDIUM`].
    pub camera: u32,
}

impl SceneMedia {
    /// Whether the scene has any medium at all.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.media.is_empty()
    }

    /// The medium `index`, or `None` for vacuum.
    #[inline]
    pub fn get(&self, index: u32) -> Option<&Medium> {
        self.media.get(index as usize)
    }

    /// The media the surface hit separates (instanced surfaces bound none).
    #[inline]
    pub fn interface(&self, hit: &SceneHit) -> MediumInterface {
        if hit.instance != NO_INSTANCE {
            return MediumInterface::NONE;
        }
        self.of_shape
            .get(hit.shape as usize)
            .copied()
            .unwrap_or(MediumInterface::NONE)
    }
}
