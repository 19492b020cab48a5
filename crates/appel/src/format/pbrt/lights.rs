//! pbrt's lights: `point`, `spot`, `distant` and `infinite` (a constant, or an equal-area
//! octahedral image) as `[[light]]`
//! entries, and `AreaLightSource "diffuse"` as the emitter of the shapes that follow it.
//! Intensities follow pbrt-v4: an emission spectrum is normalised to one nit (an `rgb` value is
//! taken as it is), then multiplied by `scale`; `power`, where given, sets the total power.

use super::convert::{AreaLight, Converter};
use super::params::{ParamSet, ParamType};
use super::parser::Directive;
use super::shapes::rows;
use super::spectrum::{rgb_of, Use};
use crate::description::LightDesc;
use crate::description::{
    ConstantDesc, DirectionalDesc, EqualAreaEnvMapDesc, PointDesc, SpotDesc, TransformDesc,
};
use crate::error::Result;
use glam::DVec3;
use std::f64::consts::PI;

impl Converter {
    /// The colour of an emission parameter (white by default: pbrt's default is the colour
    /// space's illuminant, one nit), times `scale`.
    fn emission(&self, p: &ParamSet, name: &str) -> Result<[f64; 3]> {
        let rgb = match p.any_of(
            name,
            &[ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody],
        )? {
            Some(q) => rgb_of(q, Use::Illuminant, &self.base_dir)?,
            None => [1.0; 3],
        };
        let scale = p.float_or("scale", 1.0)?;
        Ok(rgb.map(|c| c as f64 * scale))
    }

    pub(super) fn light(&mut self, d: &Directive) -> Result<()> {
        let p = &d.params;
        let m = self.to_description(&self.attrs.ctm);
        let point = |name: &str, default: DVec3| -> Result<DVec3> {
            Ok(p.point3(name)?.map_or(default, DVec3::from_array))
        };
        let power = p.float("power")?.filter(|v| *v > 0.0);
        let f32s = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
        let light = match d.strings[0].as_str() {
            "point" => {
                let mut i = self.emission(p, "I")?;
                if let Some(phi) = power {
                    i = i.map(|c| c * phi / (4.0 * PI));
                }
                let (color, intensity) = color_and_scale(i);
                LightDesc::Point(PointDesc {
                    position: f32s(m.transform_point3(point("from", DVec3::ZERO)?)),
                    color,
                    intensity,
                })
            }
            "spot" => {
                let cone = p.float_or("coneangle", 30.0)?;
                let delta = p.float_or("conedelta", 5.0)?;
                if !(cone > 0.0 && cone <= 90.0 && (0.0..=cone).contains(&delta)) {
                    return Err(d.loc.error(format!(
                        "a spot's coneangle must be in (0, 90] and its conedelta in [0, \
                         coneangle], got {cone} and {delta}"
                    )));
                }
                let mut i = self.emission(p, "I")?;
                if let Some(phi) = power {
                    // pbrt-v4: the power of a spot with a smooth falloff between the two cones.
                    let (c_end, c_start) =
                        (cone.to_radians().cos(), (cone - delta).to_radians().cos());
                    i = i.map(|c| c * phi / (2.0 * PI * (1.0 - 0.5 * (c_start + c_end))));
                }
                let (color, intensity) = color_and_scale(i);
                let from = point("from", DVec3::ZERO)?;
                let to = point("to", DVec3::Z)?;
                if from == to {
                    return Err(d.loc.error("a spot's \"from\" and \"to\" coincide"));
                }
                LightDesc::Spot(SpotDesc {
                    position: f32s(m.transform_point3(from)),
                    look_at: f32s(m.transform_point3(to)),
                    color,
                    intensity,
                    cutoff_angle: cone as f32,
                    beam_width: Some((cone - delta) as f32),
                    up: None,
                    texture: None,
                })
            }
            "distant" => {
                if power.is_some() {
                    return Err(d.loc.error(
                        "a distant light's \"power\" depends on the scene's extent, which Appel \
                         does not compute: give \"scale\"",
                    ));
                }
                let l = self.emission(p, "L")?;
                let (color, intensity) = color_and_scale(l);
                let from = point("from", DVec3::ZERO)?;
                let to = point("to", DVec3::Z)?;
                let dir = m.transform_vector3(to - from);
                if dir.length_squared() == 0.0 {
                    return Err(d
                        .loc
                        .error("a distant light's \"from\" and \"to\" coincide"));
                }
                LightDesc::Directional(DirectionalDesc {
                    direction: f32s(dir.normalize()),
                    color,
                    intensity,
                })
            }
            "infinite" => {
                if let Some(q) = p.get("portal") {
                    return Err(q.error("portals are not supported"));
                }
                if power.is_some() || p.get("illuminance").is_some() {
                    return Err(d.loc.error(
                        "an infinite light's \"power\"/\"illuminance\" is not supported: give \
                         \"scale\"",
                    ));
                }
                match p.string("filename")?.map(|f| f.to_string()) {
                    Some(q) => {
                        let at = &p.get("filename").expect("read").loc;
                        let path = self.base_dir.join(&q);
                        if !path.is_file() {
                            return Err(at.error(format!(
                                "the environment image \"{q}\" is missing (looked for {})",
                                path.display()
                            )));
                        }
                        // pbrt-v4 lights the scene with the image as it is, times `scale` (an
                        // RGB illuminant spectrum of the image's colour space, which is its RGB
                        // again), in the light's frame: the CTM, mirrored as the world is.
                        LightDesc::EqualAreaEnvMap(EqualAreaEnvMapDesc {
                            file: path.to_string_lossy().into_owned(),
                            scale: p.float_or("scale", 1.0)? as f32,
                            transform: Some(TransformDesc {
                                matrix: Some(rows(&m)),
                                ..TransformDesc::default()
                            }),
                        })
                    }
                    None => LightDesc::Constant(ConstantDesc {
                        radiance: self.emission(p, "L")?.map(|c| c as f32),
                    }),
                }
            }
            other => {
                return Err(d.loc.error(format!(
                    "unsupported light \"{other}\" (supported: point, spot, distant, infinite; \
                     AreaLightSource \"diffuse\")"
                )))
            }
        };
        if self.object.is_some() {
            return Err(d.loc.error("a LightSource inside an object definition"));
        }
        self.lights.push(light);
        Ok(())
    }

    pub(super) fn area_light(&mut self, d: &Directive) -> Result<()> {
        if d.strings[0] != "diffuse" {
            return Err(d.loc.error(format!(
                "unsupported area light \"{}\" (supported: diffuse)",
                d.strings[0]
            )));
        }
        let p = &d.params;
        if let Some(q) = p.get("filename") {
            return Err(q.error("an image-textured area light is not supported"));
        }
        if let Some(q) = p.get("power") {
            return Err(q.error(
                "an area light's \"power\" is not supported (it needs the shape's area): give \
                 \"scale\"",
            ));
        }
        if p.bool_or("twosided", false)? {
            let at = &p.get("twosided").expect("read").loc;
            return Err(at.error(
                "two-sided area lights are not supported: Appel's emitters light the front side",
            ));
        }
        let l = self.emission(p, "L")?;
        self.attrs.area_light = Some(AreaLight {
            radiance: l.map(|c| c as f32),
            loc: d.loc.clone(),
        });
        Ok(())
    }
}

/// A colour and a scalar intensity whose product is `c`: the colour's largest channel is 1.
fn color_and_scale(c: [f64; 3]) -> ([f32; 3], f32) {
    let m = c.iter().cloned().fold(0.0, f64::max);
    if m <= 0.0 {
        return ([0.0; 3], 0.0);
    }
    (c.map(|x| (x / m) as f32), m as f32)
}
