//! pbrt-v4's `coateddiffuse`: a Lambertian base under a dielectric coating, with an optional
//! scattering medium between them, evaluated by a random walk between the two interfaces (Guo et
//! al. 2018, "Position-free Monte Carlo simulation for arbitrary layered BSDFs"; Pharr, Jakob
//! and Humphreys, "Physically Based Rendering", 4th ed., section 14.3).

use super::{half, zero, BsdfParams, ParamError};
use crate::description::{TextureDesc};
use serde::{Deserialize, Serialize};

/// A diffuse base under a dielectric coating; pbrt-v4's parameters and defaults. The coating's
/// roughness is a Trowbridge-Reitz (GGX) alpha (pbrt's `roughness` after `remaproughness`); 0,
/// the default, is a smooth coating.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CoatedDiffuseDesc {
    /// The base's Lambertian reflectance.
    #[serde(default = "half")]
    pub reflectance: TextureDesc,
    /// The coating's roughness, or `alpha_u` and `alpha_v` for an anisotropic one.
    #[serde(default = "zero")]
    pub alpha: TextureDesc,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_u: Option<TextureDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_v: Option<TextureDesc>,
    /// The coating's index of refraction over the outside's.
    #[serde(default = "layer::eta")]
    pub eta: f32,
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

/// The medium between the interfaces and the random walk through it, shared by the coated
/// BSDFs (pbrt-v4's `LayeredBxDF` parameters; see the keys of [`CoatedDiffuseDesc`]).
#[derive(Clone, Debug, PartialEq)]
pub struct LayerDesc {
    pub thickness: f32,
    pub albedo: TextureDesc,
    pub g: f32,
    pub maxdepth: u32,
    pub nsamples: u32,
}

pub(crate) mod layer {
    pub fn eta() -> f32 {
        1.5
    }
    pub fn thickness() -> f32 {
        0.01
    }
    pub fn maxdepth() -> u32 {
        10
    }
    pub fn nsamples() -> u32 {
        1
    }
}

/// The most random walks a layered BSDF may average per evaluation, and their longest depth:
/// each evaluation costs up to their product in interface samples.
pub const MAX_LAYER_SAMPLES: u32 = 256;
pub const MAX_LAYER_DEPTH: u32 = 1024;

impl LayerDesc {
    pub(crate) fn check(&self) -> Result<(), ParamError> {
        if !(self.thickness.is_finite() && self.thickness > 0.0) {
            return Err(ParamError::new(
                "thickness",
                format!("`thickness` must be a positive number, got {}", self.thickness),
            ));
        }
        if !(self.g > -1.0 && self.g < 1.0) {
            return Err(ParamError::new(
                "g",
                format!("`g` must lie in (-1, 1), got {}", self.g),
            ));
        }
        if !(1..=MAX_LAYER_DEPTH).contains(&self.maxdepth) {
            return Err(ParamError::new(
                "maxdepth",
                format!("`maxdepth` must lie in [1, {MAX_LAYER_DEPTH}], got {}", self.maxdepth),
            ));
        }
        if !(1..=MAX_LAYER_SAMPLES).contains(&self.nsamples) {
            return Err(ParamError::new(
                "nsamples",
                format!(
                    "`nsamples` must lie in [1, {MAX_LAYER_SAMPLES}], got {}",
                    self.nsamples
                ),
            ));
        }
        // A scattering albedo above 1 would create light.
        let too_bright = match &self.albedo {
            TextureDesc::Value(v) => *v > 1.0,
            TextureDesc::Rgb(c) => c.iter().any(|v| *v > 1.0),
            TextureDesc::Texture(_) => false,
        };
        if too_bright {
            return Err(ParamError::new("albedo", "`albedo` must not exceed 1"));
        }
        Ok(())
    }
}

/// The coating's index: a positive number.
pub(crate) fn check_eta(key: &'static str, eta: f32) -> Result<(), ParamError> {
    if eta.is_finite() && eta > 0.0 {
        Ok(())
    } else {
        Err(ParamError::new(
            key,
            format!("`{key}` must be a positive number, got {eta}"),
        ))
    }
}

/// `alpha_u` and `alpha_v` come together.
pub(crate) fn check_alphas(
    u: (&'static str, &Option<TextureDesc>),
    v: (&'static str, &Option<TextureDesc>),
) -> Result<(), ParamError> {
    if u.1.is_some() != v.1.is_some() {
        let missing = if u.1.is_none() { u.0 } else { v.0 };
        return Err(ParamError::new(
            missing,
            format!("give both `{}` and `{}`, or neither", u.0, v.0),
        ));
    }
    Ok(())
}

impl CoatedDiffuseDesc {
    /// The coating's roughness along u and v.
    pub fn alphas(&self) -> (TextureDesc, TextureDesc) {
        alphas(&self.alpha, &self.alpha_u, &self.alpha_v)
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

impl BsdfParams for CoatedDiffuseDesc {
    const NAME: &'static str = "coateddiffuse";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        [
            Some(("reflectance", &self.reflectance)),
            Some(("alpha", &self.alpha)),
            self.alpha_u.as_ref().map(|t| ("alpha_u", t)),
            self.alpha_v.as_ref().map(|t| ("alpha_v", t)),
            Some(("albedo", &self.albedo)),
        ]
        .into_iter()
        .flatten()
        .collect()
    }

    fn check(&self) -> Result<(), ParamError> {
        check_eta("eta", self.eta)?;
        check_alphas(("alpha_u", &self.alpha_u), ("alpha_v", &self.alpha_v))?;
        self.layer().check()
    }
}

/// `alpha_u` and `alpha_v` where given, else `alpha` for both.
pub(crate) fn alphas(
    alpha: &TextureDesc,
    u: &Option<TextureDesc>,
    v: &Option<TextureDesc>,
) -> (TextureDesc, TextureDesc) {
    (
        u.clone().unwrap_or_else(|| alpha.clone()),
        v.clone().unwrap_or_else(|| alpha.clone()),
    )
}
