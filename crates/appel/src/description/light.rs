//! `[[light]]`: emitters that are not surfaces (surfaces emit through a shape's `emitter` key).

use super::{TransformDesc, Vec3f};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum LightDesc {
    /// Radiant intensity `color * intensity` (W/sr), falling off with the inverse square of the
    /// distance.
    Point {
        position: Vec3f,
        #[serde(default = "white")]
        color: Vec3f,
        #[serde(default = "unit")]
        intensity: f32,
    },
    /// Parallel light travelling along `direction`, with irradiance `color * intensity` on a
    /// surface facing it.
    Directional {
        direction: Vec3f,
        #[serde(default = "white")]
        color: Vec3f,
        #[serde(default = "unit")]
        intensity: f32,
    },
    /// A point light restricted to a cone around `position -> look_at` (Mitsuba's `spot`).
    Spot {
        position: Vec3f,
        look_at: Vec3f,
        #[serde(default = "white")]
        color: Vec3f,
        #[serde(default = "unit")]
        intensity: f32,
        /// Half-angle of the cone in degrees, outside of which no light leaves (20 by default).
        #[serde(default = "default_cutoff")]
        cutoff_angle: f32,
        /// Half-angle in degrees of the inner cone of full intensity (3/4 of the cutoff by default).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        beam_width: Option<f32>,
        /// Which way is up in the projected `texture`: the light's local y axis is the part of
        /// `up` perpendicular to the axis (as Mitsuba's `lookat` builds it). By default +y, or +x
        /// when the axis is nearly vertical.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        up: Option<Vec3f>,
        /// An image projected through the cone, multiplying the intensity: uv (0.5, 0.5) on the
        /// axis, 0 and 1 where the cone's cutoff meets the image plane (Mitsuba's `texture`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        texture: Option<super::TextureDesc>,
    },
    /// A pinhole projecting an image (Mitsuba's `projector`): the reciprocal of a perspective
    /// camera at `position` looking at `look_at`. `irradiance` is what a plane facing it at unit
    /// distance receives, divided by π and `scale` (Mitsuba's convention); the field of view
    /// `fov` degrees spans `fov_axis` of the image (by default Mitsuba's 50 mm lens: 46.8° across
    /// the diagonal).
    Projector {
        position: Vec3f,
        look_at: Vec3f,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        up: Option<Vec3f>,
        #[serde(default = "unit_texture")]
        irradiance: super::TextureDesc,
        #[serde(default = "unit")]
        scale: f32,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        fov: Option<f32>,
        /// `x` unless given, as Mitsuba's projector (Appel's cameras default to `y`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        fov_axis: Option<super::FovAxis>,
    },
    /// Light of radiance `radiance` arriving from every direction (Mitsuba's `constant`).
    Constant {
        #[serde(default = "white")]
        radiance: Vec3f,
    },
    /// A latitude-longitude environment map (EXR or HDR) around the scene (Mitsuba's `envmap`).
    Envmap {
        file: String,
        #[serde(default = "unit")]
        scale: f32,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        transform: Option<TransformDesc>,
    },
    /// Sky and sun of Hosek and Wilkie's model around the scene (Mitsuba's `sunsky`), in a frame
    /// whose +z is the zenith and +x north, turned into the scene by `transform`. The sun stands
    /// along `sun_direction` (world space), or where it is seen from `latitude`/`longitude`
    /// (degrees) at the local time `year`-`month`-`day` `hour`:`minute`:`second` in `timezone`
    /// (hours ahead of UTC); without either, at Mitsuba's default place and time (Tokyo,
    /// 2010-07-10 15:00, UTC+9).
    Sunsky {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        sun_direction: Option<Vec3f>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        latitude: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        longitude: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        timezone: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        year: Option<i64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        month: Option<i64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        day: Option<i64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        hour: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        minute: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        second: Option<f64>,
        /// Atmospheric turbidity in [1, 10] (3: a clear temperate sky).
        #[serde(default = "default_turbidity")]
        turbidity: f32,
        /// Ground albedo in [0, 1] per channel.
        #[serde(default = "default_albedo")]
        albedo: Vec3f,
        #[serde(default = "unit")]
        sun_scale: f32,
        #[serde(default = "unit")]
        sky_scale: f32,
        /// The sun's angular diameter in degrees, in (0, 180); its irradiance stays the same.
        #[serde(default = "default_sun_aperture")]
        sun_aperture: f32,
        /// The limb-darkened solar disk instead of a uniform one.
        #[serde(default)]
        complex_sun: bool,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        transform: Option<TransformDesc>,
    },
}

impl LightDesc {
    /// The point lights' positions, scaled by `s` with their intensity by `s^2` so that the
    /// inverse-square falloff leaves the image unchanged (for [`super::Description::scaled`]).
    pub fn scale(&mut self, s: f32) {
        let sc = |v: &mut Vec3f| *v = v.map(|x| x * s);
        match self {
            LightDesc::Point {
                position,
                intensity,
                ..
            } => {
                sc(position);
                *intensity *= s * s;
            }
            LightDesc::Spot {
                position,
                look_at,
                intensity,
                ..
            } => {
                sc(position);
                sc(look_at);
                *intensity *= s * s;
            }
            LightDesc::Projector {
                position,
                look_at,
                scale,
                ..
            } => {
                sc(position);
                sc(look_at);
                *scale *= s * s;
            }
            LightDesc::Directional { .. }
            | LightDesc::Constant { .. }
            | LightDesc::Envmap { .. }
            | LightDesc::Sunsky { .. } => {}
        }
    }
}

/// A shape's `emitter = { radiance = ... }`: the surface emits `radiance` from its front side
/// (where the normal points), as Mitsuba's `area` emitter.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AreaEmitterDesc {
    pub radiance: super::TextureDesc,
}

fn white() -> Vec3f {
    [1.0; 3]
}
fn unit_texture() -> super::TextureDesc {
    super::TextureDesc::Value(1.0)
}
fn unit() -> f32 {
    1.0
}
fn default_cutoff() -> f32 {
    20.0
}
fn default_turbidity() -> f32 {
    3.0
}
fn default_albedo() -> Vec3f {
    [0.3; 3]
}
/// The real sun's angular diameter in degrees, as Mitsuba's `sunsky` takes it.
fn default_sun_aperture() -> f32 {
    0.5358
}
