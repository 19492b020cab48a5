//! Mitsuba's `projector`: a pinhole projecting an image.

use super::{check_aim, scale_point, unit, EmitterParams};
use crate::description::param_error::{non_negative, ParamError};
use crate::description::{FovAxis, TextureDesc, Vec3f};
use serde::{Deserialize, Serialize};

/// The reciprocal of a perspective camera at `position` looking at `look_at`. `irradiance` is
/// what a plane facing it at unit distance receives, divided by π and `scale` (Mitsuba's
/// convention); the field of view `fov` degrees spans `fov_axis` of the image (by default
/// Mitsuba's 50 mm lens: 46.8° across the diagonal).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ProjectorDesc {
    pub position: Vec3f,
    pub look_at: Vec3f,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<Vec3f>,
    #[serde(default = "unit_texture")]
    pub irradiance: TextureDesc,
    #[serde(default = "unit")]
    pub scale: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov: Option<f32>,
    /// `x` unless given, as Mitsuba's projector (Appel's cameras default to `y`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov_axis: Option<FovAxis>,
}

fn unit_texture() -> TextureDesc {
    TextureDesc::Value(1.0)
}

impl ProjectorDesc {
    /// The field of view in degrees and the axis it spans: as given (across `x` unless said
    /// otherwise), or Mitsuba's default lens, 50 mm on 36 x 24 mm film, across the diagonal.
    pub fn field_of_view(&self) -> (f32, FovAxis) {
        match self.fov {
            Some(f) => (f, self.fov_axis.unwrap_or(FovAxis::X)),
            None => (
                2.0 * (36f32.hypot(24.0) / 100.0).atan().to_degrees(),
                FovAxis::Diagonal,
            ),
        }
    }
}

impl EmitterParams for ProjectorDesc {
    const NAME: &'static str = "projector";

    fn check(&self) -> Result<(), ParamError> {
        check_aim(&self.position, &self.look_at)?;
        non_negative("scale", &[self.scale])?;
        if let Some(f) = self.fov {
            if !(f > 0.0 && f < 180.0) {
                return Err(ParamError::new(
                    "fov",
                    format!("`fov` must lie in (0, 180) degrees, got {f}"),
                ));
            }
        }
        Ok(())
    }

    fn scale(&mut self, s: f32) {
        scale_point(&mut self.position, s);
        scale_point(&mut self.look_at, s);
        self.scale *= s * s;
    }
}
