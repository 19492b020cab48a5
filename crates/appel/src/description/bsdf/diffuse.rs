//! Mitsuba's `diffuse`: Lambertian reflection.

use super::{half, BsdfParams};
use crate::description::{TextureDesc};
use serde::{Deserialize, Serialize};

/// Lambertian reflection.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DiffuseDesc {
    #[serde(default = "half")]
    pub reflectance: TextureDesc,
}

impl BsdfParams for DiffuseDesc {
    const NAME: &'static str = "diffuse";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        vec![("reflectance", &self.reflectance)]
    }
}
