//! pbrt-v4's image `infinite` light: an equal-area octahedral image of the surroundings.

use super::{unit, EmitterParams};
use crate::description::param_error::{non_negative, ParamError};
use crate::description::TransformDesc;
use serde::{Deserialize, Serialize};

/// A square environment image (EXR, HDR, PFM, PNG) in the equal-area octahedral mapping pbrt-v4
/// stores them in: +z of the light's frame is the image's centre, -z its corners.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EqualAreaEnvMapDesc {
    pub file: String,
    #[serde(default = "unit")]
    pub scale: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
}

impl EmitterParams for EqualAreaEnvMapDesc {
    const NAME: &'static str = "equalareaenvmap";

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
