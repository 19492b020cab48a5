//! Mitsuba's `constant`: the same light from every direction.

use super::{white, EmitterParams};
use crate::description::param_error::{non_negative, ParamError};
use crate::description::Vec3f;
use serde::{Deserialize, Serialize};

/// Light of radiance `radiance` arriving from every direction.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ConstantDesc {
    #[serde(default = "white")]
    pub radiance: Vec3f,
}

impl EmitterParams for ConstantDesc {
    const NAME: &'static str = "constant";

    fn check(&self) -> Result<(), ParamError> {
        non_negative("radiance", &self.radiance)
    }
}
