//! Mitsuba's `conductor`: a smooth metal, a mirror weighted by the complex Fresnel reflectance.

use super::{one, BsdfParams, ParamError};
use crate::description::{TextureDesc, Vec3f};
use crate::description::spectra;
use serde::{Deserialize, Serialize};

/// A smooth metal: a mirror weighted by the complex Fresnel reflectance.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ConductorDesc {
    /// One of Mitsuba's named metals (`"Au"`, `"Cu"`, ...; `"none"`: a perfect mirror). Ignored
    /// where `eta` and `k` are given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Real part of the complex index of refraction, per RGB channel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<Vec3f>,
    /// Imaginary part (absorption coefficient).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<Vec3f>,
    #[serde(default = "one")]
    pub specular_reflectance: TextureDesc,
}

impl BsdfParams for ConductorDesc {
    const NAME: &'static str = "conductor";

    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        vec![("specular_reflectance", &self.specular_reflectance)]
    }

    fn check(&self) -> Result<(), ParamError> {
        check_metal(self.material.as_deref(), self.eta, self.k)
    }
}

/// A metal's index: `eta` and `k` given, or taken from a metal Appel knows (the conductors'
/// shared check; `material`, `eta` and `k` are the keys).
pub(crate) fn check_metal(
    material: Option<&str>,
    eta: Option<Vec3f>,
    k: Option<Vec3f>,
) -> Result<(), ParamError> {
    if let Some(eta) = eta {
        if eta.iter().any(|x| !x.is_finite()) {
            return Err(ParamError::new("eta", format!("`eta` must be finite, got {eta:?}")));
        }
    }
    if let Some(k) = k {
        super::non_negative("k", &k)?;
    }
    if eta.is_some() && k.is_some() {
        return Ok(());
    }
    let name = material.unwrap_or(spectra::NO_CONDUCTOR);
    if spectra::conductor(name).is_none() {
        return Err(ParamError::new(
            "material",
            format!(
                "unknown conductor `{name}`, expected one of: {}",
                spectra::CONDUCTOR_NAMES.join(", ")
            ),
        ));
    }
    Ok(())
}
