//! Mitsuba's `envmap`: an image of the surroundings.

use super::{unit, EmitterParams};
use crate::description::param_error::{non_negative, ParamError};
use crate::description::TransformDesc;
use serde::{Deserialize, Serialize};

/// A latitude-longitude environment map (EXR or HDR) around the scene.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EnvMapDesc {
    pub file: String,
    #[serde(default = "unit")]
    pub scale: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
}

impl EmitterParams for EnvMapDesc {
    const NAME: &'static str = "envmap";

    fn check(&self) -> Result<(), ParamError> {
        if self.file.is_empty() {
            return Err(ParamError::new("file", "`file` must name an image file"));
        }
        non_negative("scale", &[self.scale])
    }

    fn transform(&self) -> Option<&TransformDesc> {
        self.transform.as_ref()
    }
}
