//! Mitsuba's `roughplastic`: a diffuse base under a rough dielectric coating.

use super::{
    air, half, one, polypropylene, rough_fields, BsdfParams, ParamError,
    DEFAULT_ALPHA,
};
use crate::description::{IorDesc, TextureDesc};

rough_fields! {
    /// A diffuse base under a rough dielectric coating. Isotropic: `alpha_v` is not read.
    pub struct RoughPlasticDesc {
        #[serde(default = "polypropylene")]
        pub int_ior: IorDesc,
        #[serde(default = "air")]
        pub ext_ior: IorDesc,
        #[serde(default = "half")]
        pub diffuse_reflectance: TextureDesc,
        #[serde(default = "one")]
        pub specular_reflectance: TextureDesc,
        #[serde(default)]
        pub nonlinear: bool,
    }
}

impl RoughPlasticDesc {
    /// The coating's roughness, which must be a number: its albedo is precomputed at load for one
    /// roughness, as Mitsuba does.
    pub fn constant_alpha(&self) -> Result<f32, ParamError> {
        for (k, a) in [("alpha", &self.alpha), ("alpha_u", &self.alpha_u)] {
            if matches!(a, Some(TextureDesc::Rgb(_) | TextureDesc::Texture(_))) {
                return Err(ParamError::new(
                    k,
                    format!(
                        "a rough plastic's `{k}` must be a number: its coating's albedo is \
                         precomputed for one roughness"
                    ),
                ));
            }
        }
        Ok(match self.alpha.as_ref().or(self.alpha_u.as_ref()) {
            Some(TextureDesc::Value(a)) => *a,
            _ => DEFAULT_ALPHA,
        })
    }
}

impl BsdfParams for RoughPlasticDesc {
    const NAME: &'static str = "roughplastic";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        [
            Some(("diffuse_reflectance", &self.diffuse_reflectance)),
            Some(("specular_reflectance", &self.specular_reflectance)),
        ]
        .into_iter()
        .chain(self.rough_textures())
        .flatten()
        .collect()
    }

    fn iors(&self) -> Vec<(&'static str, &IorDesc)> {
        vec![("int_ior", &self.int_ior), ("ext_ior", &self.ext_ior)]
    }

    fn check(&self) -> Result<(), ParamError> {
        self.constant_alpha().map(|_| ())
    }
}
