//! Mitsuba's `null`: no surface at all, only a boundary between media (an index-matched one).

use super::BsdfParams;
use crate::description::TextureDesc;
use serde::{Deserialize, Serialize};

/// The index-matched boundary of a medium: light passes straight through, unchanged.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct NullDesc {}

impl BsdfParams for NullDesc {
    const NAME: &'static str = "null";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        Vec::new()
    }
}
