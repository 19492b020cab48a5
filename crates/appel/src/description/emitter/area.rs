//! Mitsuba's `area`: a surface that emits.

use crate::description::TextureDesc;
use serde::{Deserialize, Serialize};

/// A shape's `emitter = { radiance = ... }`: the surface emits `radiance` from its front side
/// (where the normal points).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AreaEmitterDesc {
    pub radiance: TextureDesc,
}
