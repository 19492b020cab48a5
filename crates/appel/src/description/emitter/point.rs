//! Mitsuba's `point`: a light at a point, the same in every direction.

use super::{scale_point, unit, white, EmitterParams};
use crate::description::param_error::{finite, non_negative, ParamError};
use crate::description::Vec3f;
use serde::{Deserialize, Serialize};

/// Radiant intensity `color * intensity` (W/sr), falling off with the inverse square of the
/// distance.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PointDesc {
    pub position: Vec3f,
    #[serde(default = "white")]
    pub color: Vec3f,
    #[serde(default = "unit")]
    pub intensity: f32,
}

impl EmitterParams for PointDesc {
    const NAME: &'static str = "point";

    fn check(&self) -> Result<(), ParamError> {
        finite("position", &self.position)?;
        non_negative("color", &self.color)?;
        non_negative("intensity", &[self.intensity])
    }

    fn scale(&mut self, s: f32) {
        scale_point(&mut self.position, s);
        self.intensity *= s * s;
    }
}
