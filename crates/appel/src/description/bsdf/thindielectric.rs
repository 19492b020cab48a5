//! Mitsuba's `thindielectric`: an infinitely thin dielectric sheet (window glass), with no
//! refraction and the inter-reflections inside the sheet summed.

use super::{air, bk7, one, BsdfParams};
use crate::description::{IorDesc, TextureDesc};
use serde::{Deserialize, Serialize};

/// An infinitely thin dielectric sheet; the keys of [`super::DielectricDesc`].
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ThinDielectricDesc {
    #[serde(default = "bk7")]
    pub int_ior: IorDesc,
    #[serde(default = "air")]
    pub ext_ior: IorDesc,
    #[serde(default = "one")]
    pub specular_reflectance: TextureDesc,
    #[serde(default = "one")]
    pub specular_transmittance: TextureDesc,
}

impl BsdfParams for ThinDielectricDesc {
    const NAME: &'static str = "thindielectric";

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
