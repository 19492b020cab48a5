//! Mitsuba's `principled`: Burley's Disney BSDF (diffuse with retro-reflection and sheen, a GGX
//! specular lobe blending dielectric, metallic and transmitting responses, a clearcoat).

use super::{half, non_negative, one_f, zero, BsdfParams, ParamError};
use crate::description::{TextureDesc};
use serde::{Deserialize, Serialize};

/// Mitsuba's `principled`, key for key: every weight is a texture in [0, 1] (Burley 2012).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PrincipledDesc {
    #[serde(default = "half")]
    pub base_color: TextureDesc,
    #[serde(default = "half")]
    pub roughness: TextureDesc,
    /// 0: isotropic; towards 1, stretched along the surface's u tangent.
    #[serde(default = "zero")]
    pub anisotropic: TextureDesc,
    #[serde(default = "zero")]
    pub metallic: TextureDesc,
    /// The share of the dielectric part that transmits (rough glass) instead of diffusing.
    #[serde(default = "zero")]
    pub spec_trans: TextureDesc,
    #[serde(default = "zero")]
    pub spec_tint: TextureDesc,
    #[serde(default = "zero")]
    pub sheen: TextureDesc,
    #[serde(default = "zero")]
    pub sheen_tint: TextureDesc,
    /// Blends the diffuse lobe towards Burley's fake subsurface term.
    #[serde(default = "zero")]
    pub flatness: TextureDesc,
    #[serde(default = "zero")]
    pub clearcoat: TextureDesc,
    #[serde(default = "zero")]
    pub clearcoat_gloss: TextureDesc,
    /// Relative IOR of the dielectric part (inside over outside); give this or `specular`, not
    /// both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<f32>,
    /// Reflectance at normal incidence as `0.08 specular` (0.5 by default: eta 1.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular: Option<f32>,
    #[serde(default = "one_f")]
    pub diffuse_reflectance_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub main_specular_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub clearcoat_sampling_rate: f32,
}

impl BsdfParams for PrincipledDesc {
    const NAME: &'static str = "principled";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        vec![
            ("base_color", &self.base_color),
            ("roughness", &self.roughness),
            ("anisotropic", &self.anisotropic),
            ("metallic", &self.metallic),
            ("spec_trans", &self.spec_trans),
            ("spec_tint", &self.spec_tint),
            ("sheen", &self.sheen),
            ("sheen_tint", &self.sheen_tint),
            ("flatness", &self.flatness),
            ("clearcoat", &self.clearcoat),
            ("clearcoat_gloss", &self.clearcoat_gloss),
        ]
    }

    fn check(&self) -> Result<(), ParamError> {
        if self.eta.is_some() && self.specular.is_some() {
            return Err(ParamError::new("eta", "give `eta` or `specular`, not both"));
        }
        if let Some(eta) = self.eta {
            if !(eta.is_finite() && eta > 0.0) {
                return Err(ParamError::new(
                    "eta",
                    format!("`eta` must be a positive number, got {eta}"),
                ));
            }
        }
        if let Some(s) = self.specular {
            // eta = 2 / (1 - sqrt(0.08 s)) - 1 is finite and at least 1 for s in [0, 12.5).
            if !(0.0..12.5).contains(&s) {
                return Err(ParamError::new(
                    "specular",
                    format!("`specular` must lie in [0, 12.5), got {s}"),
                ));
            }
        }
        for (k, v) in [
            (
                "diffuse_reflectance_sampling_rate",
                self.diffuse_reflectance_sampling_rate,
            ),
            ("main_specular_sampling_rate", self.main_specular_sampling_rate),
            ("clearcoat_sampling_rate", self.clearcoat_sampling_rate),
        ] {
            non_negative(k, &[v])?;
        }
        Ok(())
    }
}
