//! Mitsuba's `spot`: a point light restricted to a cone, optionally projecting an image.

use super::{check_aim, scale_point, unit, white, EmitterParams};
use crate::description::param_error::{non_negative, ParamError};
use crate::description::{TextureDesc, Vec3f};
use serde::{Deserialize, Serialize};

/// A point light restricted to a cone around `position -> look_at`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpotDesc {
    pub position: Vec3f,
    pub look_at: Vec3f,
    #[serde(default = "white")]
    pub color: Vec3f,
    #[serde(default = "unit")]
    pub intensity: f32,
    /// Half-angle of the cone in degrees, outside of which no light leaves (20 by default).
    #[serde(default = "default_cutoff")]
    pub cutoff_angle: f32,
    /// Half-angle in degrees of the inner cone of full intensity (3/4 of the cutoff by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beam_width: Option<f32>,
    /// Which way is up in the projected `texture`: the light's local y axis is the part of `up`
    /// perpendicular to the axis (as Mitsuba's `lookat` builds it). By default +y, or +x when the
    /// axis is nearly vertical.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<Vec3f>,
    /// An image projected through the cone, multiplying the intensity: uv (0.5, 0.5) on the axis,
    /// 0 and 1 where the cone's cutoff meets the image plane (Mitsuba's `texture`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<TextureDesc>,
}

fn default_cutoff() -> f32 {
    20.0
}

impl SpotDesc {
    /// The half-angle of full intensity: `beam_width`, or Mitsuba's 3/4 of the cutoff.
    pub fn beam_width(&self) -> f32 {
        self.beam_width.unwrap_or(0.75 * self.cutoff_angle)
    }
}

impl EmitterParams for SpotDesc {
    const NAME: &'static str = "spot";

    fn check(&self) -> Result<(), ParamError> {
        check_aim(&self.position, &self.look_at)?;
        non_negative("color", &self.color)?;
        non_negative("intensity", &[self.intensity])?;
        let cutoff = self.cutoff_angle;
        if !(cutoff > 0.0 && cutoff <= 90.0) {
            return Err(ParamError::new(
                "cutoff_angle",
                format!("`cutoff_angle` must lie in (0, 90] degrees, got {cutoff}"),
            ));
        }
        if let Some(b) = self.beam_width {
            if !(b > 0.0 && b <= cutoff) {
                return Err(ParamError::new(
                    "beam_width",
                    format!("`beam_width` must lie in (0, cutoff_angle], got {b}"),
                ));
            }
        }
        Ok(())
    }

    fn scale(&mut self, s: f32) {
        scale_point(&mut self.position, s);
        scale_point(&mut self.look_at, s);
        self.intensity *= s * s;
    }
}
