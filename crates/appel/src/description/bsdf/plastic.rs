//! Mitsuba's `plastic`: a diffuse base under a smooth dielectric coating.

use super::{air, half, one, polypropylene, BsdfParams};
use crate::description::{IorDesc, TextureDesc};
use serde::{Deserialize, Serialize};

/// A diffuse base under a smooth dielectric coating.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PlasticDesc {
    /// Mitsuba's default is polypropylene (1.49).
    #[serde(default = "polypropylene")]
    pub int_ior: IorDesc,
    #[serde(default = "air")]
    pub ext_ior: IorDesc,
    #[serde(default = "half")]
    pub diffuse_reflectance: TextureDesc,
    #[serde(default = "one")]
    pub specular_reflectance: TextureDesc,
    /// Account for the colour shift of light scattered several times under the coating.
    #[serde(default)]
    pub nonlinear: bool,
}

impl BsdfParams for PlasticDesc {
    const NAME: &'static str = "plastic";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        vec![
            ("diffuse_reflectance", &self.diffuse_reflectance),
            ("specular_reflectance", &self.specular_reflectance),
        ]
    }

    fn iors(&self) -> Vec<(&'static str, &IorDesc)> {
        vec![("int_ior", &self.int_ior), ("ext_ior", &self.ext_ior)]
    }
}
