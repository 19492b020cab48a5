//! pbrt-v4's `coatedconductor`: a metal under a dielectric coating, with an optional scattering
//! medium between them, evaluated by the same random walk as [`super::CoatedDiffuseDesc`] (Guo
//! et al. 2018; pbrt-v4 book, section 14.3).

use super::coateddiffuse::{alphas, check_alphas, check_eta, layer, LayerDesc};
use super::conductor::check_metal;
use super::{zero, BsdfParams, ParamError};
use crate::description::{TextureDesc, Vec3f};
use serde::{Deserialize, Serialize};

/// A conductor under a dielectric coating; pbrt-v4's parameters (`interface.X` and
/// `conductor.X` as `interface_X` and `conductor_X`) and defaults. Roughnesses are
/// Trowbridge-Reitz (GGX) alphas; 0, the default, is smooth.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CoatedConductorDesc {
    /// The coating's index of refraction over the outside's.
    #[serde(default = "layer::eta")]
    pub interface_eta: f32,
    #[serde(default = "zero")]
    pub interface_alpha: TextureDesc,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interface_alpha_u: Option<TextureDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interface_alpha_v: Option<TextureDesc>,
    /// One of Mitsuba's named metals, as for `conductor` (pbrt's default is copper, `"Cu"`);
    /// ignored where `conductor_eta` and `conductor_k` are given.
    #[serde(default = "copper")]
    pub conductor_material: String,
    /// The metal's complex index (relative to vacuum: the coating's index divides it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_eta: Option<Vec3f>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_k: Option<Vec3f>,
    #[serde(default = "zero")]
    pub conductor_alpha: TextureDesc,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_alpha_u: Option<TextureDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conductor_alpha_v: Option<TextureDesc>,
    /// The medium's thickness, in units of its mean free path (its extinction is 1).
    #[serde(default = "layer::thickness")]
    pub thickness: f32,
    /// The medium's single-scattering albedo; 0 (the default) is a clear, non-scattering layer.
    #[serde(default = "zero")]
    pub albedo: TextureDesc,
    /// The Henyey-Greenstein asymmetry of the medium's phase function, in (-1, 1).
    #[serde(default)]
    pub g: f32,
    /// The longest random walk, in scattering events.
    #[serde(default = "layer::maxdepth")]
    pub maxdepth: u32,
    /// Random walks averaged per evaluation.
    #[serde(default = "layer::nsamples")]
    pub nsamples: u32,
}

fn copper() -> String {
    "Cu".into()
}

impl CoatedConductorDesc {
    /// The coating's roughness along u and v.
    pub fn interface_alphas(&self) -> (TextureDesc, TextureDesc) {
        alphas(
            &self.interface_alpha,
            &self.interface_alpha_u,
            &self.interface_alpha_v,
        )
    }

    /// The metal's roughness along u and v.
    pub fn conductor_alphas(&self) -> (TextureDesc, TextureDesc) {
        alphas(
            &self.conductor_alpha,
            &self.conductor_alpha_u,
            &self.conductor_alpha_v,
        )
    }

    /// The layer between the interfaces.
    pub fn layer(&self) -> LayerDesc {
        LayerDesc {
            thickness: self.thickness,
            albedo: self.albedo.clone(),
            g: self.g,
            maxdepth: self.maxdepth,
            nsamples: self.nsamples,
        }
    }
}

impl BsdfParams for CoatedConductorDesc {
    const NAME: &'static str = "coatedconductor";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        [
            Some(("interface_alpha", &self.interface_alpha)),
            self.interface_alpha_u
                .as_ref()
                .map(|t| ("interface_alpha_u", t)),
            self.interface_alpha_v
                .as_ref()
                .map(|t| ("interface_alpha_v", t)),
            Some(("conductor_alpha", &self.conductor_alpha)),
            self.conductor_alpha_u
                .as_ref()
                .map(|t| ("conductor_alpha_u", t)),
            self.conductor_alpha_v
                .as_ref()
                .map(|t| ("conductor_alpha_v", t)),
            Some(("albedo", &self.albedo)),
        ]
        .into_iter()
        .flatten()
        .collect()
    }

    fn check(&self) -> Result<(), ParamError> {
        check_eta("interface_eta", self.interface_eta)?;
        check_alphas(
            ("interface_alpha_u", &self.interface_alpha_u),
            ("interface_alpha_v", &self.interface_alpha_v),
        )?;
        check_alphas(
            ("conductor_alpha_u", &self.conductor_alpha_u),
            ("conductor_alpha_v", &self.conductor_alpha_v),
        )?;
        check_metal(
            Some(&self.conductor_material),
            self.conductor_eta,
            self.conductor_k,
        )
        .map_err(|e| ParamError {
            key: match e.key {
                "eta" => "conductor_eta",
                "k" => "conductor_k",
                _ => "conductor_material",
            },
            ..e
        })?;
        self.layer().check()
    }
}
