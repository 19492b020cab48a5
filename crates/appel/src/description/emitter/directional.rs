//! Mitsuba's `directional`: parallel light from infinitely far away.

use super::{unit, white, EmitterParams};
use crate::description::param_error::{non_negative, non_zero, ParamError};
use crate::description::Vec3f;
use serde::{Deserialize, Serialize};

/// Parallel light travelling along `direction`, with irradiance `color * intensity` on a surface
/// facing it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DirectionalDesc {
    pub direction: Vec3f,
    #[serde(default = "white")]
    pub color: Vec3f,
    #[serde(default = "unit")]
    pub intensity: f32,
}

impl EmitterParams for DirectionalDesc {
    const NAME: &'static str = "directional";

    fn check(&self) -> Result<(), ParamError> {
        non_zero("direction", &self.direction)?;
        non_negative("color", &self.color)?;
        non_negative("intensity", &[self.intensity])
    }
}
