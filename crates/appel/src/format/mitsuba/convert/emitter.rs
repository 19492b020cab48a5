//! Emitters that are not surfaces to `[[light]]`; surfaces' `area` emitters to a shape's
//! `emitter`. Colours inside an emitter follow Mitsuba's emission rules (no clamping to 1, no
//! D65 weighting of spectra).

use super::super::document::Object;
use super::super::spectrum::SpectrumUse;
use super::bsdf::{constant_color, texture};
use super::origin::origin_of;
use super::{columns, f32s, fov_axis, rows_f32, Converter};
use crate::description::origins::key_path;
use crate::description::{AreaEmitterDesc, LightDesc, TextureDesc, TransformDesc};
use crate::description::{
    ConstantDesc, DirectionalDesc, EnvMapDesc, PointDesc, ProjectorDesc, SpotDesc, SunSkyDesc,
};
use crate::error::Result;
use glam::DVec3;

impl Converter<'_> {
    pub(super) fn light(&mut self, e: &Object) -> Result<()> {
        let color = |name: &str| -> Result<[f32; 3]> {
            Ok(constant_color(self, e, name, SpectrumUse::Emission)?.unwrap_or([1.0; 3]))
        };
        let to_world = e.transform("to_world")?;
        let light = match e.plugin.as_str() {
            "point" => {
                let position = match (e.vector("position")?, to_world) {
                    (Some(_), Some(_)) => {
                        return Err(e.error("give position or to_world, not both"))
                    }
                    (Some(p), None) => DVec3::from(p),
                    (None, Some(m)) => columns(&m).0,
                    (None, None) => DVec3::ZERO,
                };
                LightDesc::Point(PointDesc {
                    position: f32s(position),
                    color: color("intensity")?,
                    intensity: 1.0,
                })
            }
            "spot" => {
                let (origin, _, y, z) = columns(&to_world.unwrap_or_default());
                let z = if to_world.is_some() { z } else { DVec3::Z };
                let cutoff = e.float_or("cutoff_angle", 20.0)?;
                LightDesc::Spot(SpotDesc {
                    position: f32s(origin),
                    look_at: f32s(origin + z.normalize()),
                    color: color("intensity")?,
                    intensity: 1.0,
                    cutoff_angle: cutoff as f32,
                    beam_width: e.float("beam_width")?.map(|b| b as f32),
                    texture: texture(self, e, "texture", SpectrumUse::Emission)?,
                    up: to_world.map(|_| f32s(y)),
                })
            }
            "projector" => {
                let m = to_world.unwrap_or_default();
                let (origin, _, y, z) = columns(&m);
                if e.prop("focal_length").is_some() {
                    let p = e.prop("focal_length").expect("present");
                    return Err(p.error("give the field of view as <float name=\"fov\">"));
                }
                let fov = e.float("fov")?;
                if let Some(f) = fov {
                    if !(f > 0.0 && f < 180.0) {
                        let p = e.prop("fov").expect("read above");
                        return Err(
                            p.error(format!("the field of view must be in (0, 180), got {f}"))
                        );
                    }
                }
                let fov_axis = match e.string("fov_axis")? {
                    None => None,
                    Some(a) => Some(fov_axis(a).ok_or_else(|| {
                        e.prop("fov_axis").expect("read above").error(format!(
                            "unknown fov_axis \"{a}\" (x, y, diagonal, smaller or larger)"
                        ))
                    })?),
                };
                LightDesc::Projector(ProjectorDesc {
                    position: f32s(origin),
                    look_at: f32s(origin + z.normalize()),
                    up: Some(f32s(y)),
                    irradiance: texture(self, e, "irradiance", SpectrumUse::Emission)?
                        .unwrap_or(TextureDesc::Value(1.0)),
                    scale: e.float_or("scale", 1.0)? as f32,
                    fov: fov.map(|f| f as f32),
                    fov_axis,
                })
            }
            "directional" => {
                let direction = match (e.vector("direction")?, to_world) {
                    (Some(_), Some(_)) => {
                        return Err(e.error("give direction or to_world, not both"))
                    }
                    (Some(d), None) => DVec3::from(d),
                    (None, Some(m)) => columns(&m).3,
                    (None, None) => DVec3::Z,
                };
                if direction.length() == 0.0 {
                    return Err(e.error("the direction is zero"));
                }
                LightDesc::Directional(DirectionalDesc {
                    direction: f32s(direction),
                    color: color("irradiance")?,
                    intensity: 1.0,
                })
            }
            "constant" => LightDesc::Constant(ConstantDesc {
                radiance: color("radiance")?,
            }),
            "envmap" => LightDesc::EnvMap(EnvMapDesc {
                file: self.file(e, "filename")?,
                scale: e.float_or("scale", 1.0)? as f32,
                transform: to_world.map(|m| TransformDesc {
                    matrix: Some(rows_f32(&m)),
                    ..TransformDesc::default()
                }),
            }),
            "sunsky" => {
                let sun_direction = e.vector("sun_direction")?;
                let float = |name: &str| e.float(name);
                let (latitude, longitude, timezone) =
                    (float("latitude")?, float("longitude")?, float("timezone")?);
                let (hour, minute, second) = (float("hour")?, float("minute")?, float("second")?);
                let (year, month, day) = (e.int("year")?, e.int("month")?, e.int("day")?);
                // Ranges and contradictions are the plugin's checks, which validation reports
                // at the property's line.
                let float_or =
                    |name: &str, default: f64| e.float_or(name, default).map(|v| v as f32);
                let (turbidity, sun_scale) =
                    (float_or("turbidity", 3.0)?, float_or("sun_scale", 1.0)?);
                let (sky_scale, sun_aperture) = (
                    float_or("sky_scale", 1.0)?,
                    float_or("sun_aperture", 0.5358)?,
                );
                let albedo =
                    constant_color(self, e, "albedo", SpectrumUse::Emission)?.unwrap_or([0.3; 3]);
                LightDesc::SunSky(SunSkyDesc {
                    sun_direction: sun_direction.map(|d| f32s(DVec3::from(d))),
                    latitude,
                    longitude,
                    timezone,
                    year,
                    month,
                    day,
                    hour,
                    minute,
                    second,
                    turbidity,
                    albedo,
                    sun_scale,
                    sky_scale,
                    sun_aperture,
                    complex_sun: e.bool_or("complex_sun", false)?,
                    transform: to_world.map(|m| TransformDesc {
                        matrix: Some(rows_f32(&m)),
                        ..TransformDesc::default()
                    }),
                })
            }
            "area" => return Err(e.error("an area emitter belongs inside a <shape>")),
            p => {
                return Err(e.error(format!(
                    "unsupported emitter plugin \"{p}\" (supported: {}; area on shapes)",
                    crate::description::light_names()
                )))
            }
        };
        e.finish()?;
        let index = self.lights.len();
        self.origins
            .record(key_path(&[&"light", &index]), origin_of(e));
        self.lights.push(light);
        Ok(())
    }

    /// A shape's nested `<emitter type="area">`.
    pub(super) fn area_emitter(&self, e: &Object) -> Result<AreaEmitterDesc> {
        if e.plugin != "area" {
            return Err(e.error(format!(
                "a shape carries only area emitters, not \"{}\"",
                e.plugin
            )));
        }
        let radiance =
            texture(self, e, "radiance", SpectrumUse::Emission)?.unwrap_or(TextureDesc::Value(1.0));
        e.finish()?;
        Ok(AreaEmitterDesc { radiance })
    }
}
