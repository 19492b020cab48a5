//! Mitsuba's `roughconductor`: a rough metal, a microfacet model (Walter et al. 2007) over the
//! conductor's Fresnel reflectance.

use super::conductor::check_metal;
use super::{one, rough_fields, BsdfParams, ParamError};
use crate::description::{TextureDesc, Vec3f};

rough_fields! {
    /// A rough metal; `material`, `eta` and `k` as for [`super::ConductorDesc`].
    pub struct RoughConductorDesc {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub material: Option<String>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub eta: Option<Vec3f>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub k: Option<Vec3f>,
        #[serde(default = "one")]
        pub specular_reflectance: TextureDesc,
    }
}

impl BsdfParams for RoughConductorDesc {
    const NAME: &'static str = "roughconductor";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        std::iter::once(Some(("specular_reflectance", &self.specular_reflectance)))
            .chain(self.rough_textures())
            .flatten()
            .collect()
    }

    fn check(&self) -> Result<(), ParamError> {
        check_metal(self.material.as_deref(), self.eta, self.k)
    }
}
