//! Mitsuba's `roughdielectric`: a rough interface between two indices of refraction (Walter et
//! al. 2007).

use super::{air, bk7, one, rough_fields, BsdfParams};
use crate::description::{IorDesc, TextureDesc};

rough_fields! {
    /// A rough dielectric interface.
    pub struct RoughDielectricDesc {
        #[serde(default = "bk7")]
        pub int_ior: IorDesc,
        #[serde(default = "air")]
        pub ext_ior: IorDesc,
        #[serde(default = "one")]
        pub specular_reflectance: TextureDesc,
        #[serde(default = "one")]
        pub specular_transmittance: TextureDesc,
    }
}

impl BsdfParams for RoughDielectricDesc {
    const NAME: &'static str = "roughdielectric";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        [
            Some(("specular_reflectance", &self.specular_reflectance)),
            Some(("specular_transmittance", &self.specular_transmittance)),
        ]
        .into_iter()
        .chain(self.rough_textures())
        .flatten()
        .collect()
    }

    fn iors(&self) -> Vec<(&'static str, &IorDesc)> {
        vec![("int_ior", &self.int_ior), ("ext_ior", &self.ext_ior)]
    }
}
