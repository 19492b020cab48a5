//! Mitsuba's `principledthin`: the Disney BSDF of a thin sheet (leaves, paper, fabric).

use super::{
    half, non_negative, one_and_a_half, one_f, zero, BsdfParams, ParamError,
};
use crate::description::{TextureDesc};
use serde::{Deserialize, Serialize};

/// Mitsuba's `principledthin`, key for key.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PrincipledThinDesc {
    #[serde(default = "half")]
    pub base_color: TextureDesc,
    #[serde(default = "half")]
    pub roughness: TextureDesc,
    #[serde(default = "zero")]
    pub anisotropic: TextureDesc,
    /// The share of specular (reflection and straight transmission) against diffuse scattering.
    #[serde(default = "zero")]
    pub spec_trans: TextureDesc,
    #[serde(default = "zero")]
    pub spec_tint: TextureDesc,
    #[serde(default = "zero")]
    pub sheen: TextureDesc,
    #[serde(default = "zero")]
    pub sheen_tint: TextureDesc,
    #[serde(default = "zero")]
    pub flatness: TextureDesc,
    /// Diffuse transmission, from 0 (none) to 2 (all of the diffuse part).
    #[serde(default = "zero")]
    pub diff_trans: TextureDesc,
    /// The sheet's IOR.
    #[serde(default = "one_and_a_half")]
    pub eta: TextureDesc,
    #[serde(default = "one_f")]
    pub specular_reflectance_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub specular_transmittance_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub diffuse_reflectance_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub diffuse_transmittance_sampling_rate: f32,
}

impl BsdfParams for PrincipledThinDesc {
    const NAME: &'static str = "principledthin";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        vec![
            ("base_color", &self.base_color),
            ("roughness", &self.roughness),
            ("anisotropic", &self.anisotropic),
            ("spec_trans", &self.spec_trans),
            ("spec_tint", &self.spec_tint),
            ("sheen", &self.sheen),
            ("sheen_tint", &self.sheen_tint),
            ("flatness", &self.flatness),
            ("diff_trans", &self.diff_trans),
            ("eta", &self.eta),
        ]
    }

    fn check(&self) -> Result<(), ParamError> {
        for (k, v) in [
            (
                "specular_reflectance_sampling_rate",
                self.specular_reflectance_sampling_rate,
            ),
            (
                "specular_transmittance_sampling_rate",
                self.specular_transmittance_sampling_rate,
            ),
            (
                "diffuse_reflectance_sampling_rate",
                self.diffuse_reflectance_sampling_rate,
            ),
            (
                "diffuse_transmittance_sampling_rate",
                self.diffuse_transmittance_sampling_rate,
            ),
        ] {
            non_negative(k, &[v])?;
        }
        Ok(())
    }
}
