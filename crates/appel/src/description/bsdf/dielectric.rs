//! Mitsuba's `dielectric`: a smooth interface between two indices of refraction.

use super::{air, bk7, one, BsdfParams};
use crate::description::{IorDesc, TextureDesc};
use serde::{Deserialize, Serialize};

/// A smooth interface between two indices of refraction.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DielectricDesc {
    /// Inside (the side opposite the normal); Mitsuba's default is BK7 glass.
    #[serde(default = "bk7")]
    pub int_ior: IorDesc,
    #[serde(default = "air")]
    pub ext_ior: IorDesc,
    #[serde(default = "one")]
    pub specular_reflectance: TextureDesc,
    #[serde(default = "one")]
    pub specular_transmittance: TextureDesc,
}

impl BsdfParams for DielectricDesc {
    const NAME: &'static str = "dielectric";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        vec![
            ("specular_reflectance", &self.specular_reflectance),
            ("specular_transmittance", &self.specular_transmittance),
        ]
    }

    fn iors(&self) -> Vec<(&'static str, &IorDesc)> {
        vec![("int_ior", &self.int_ior), ("ext_ior", &self.ext_ior)]
    }
}
