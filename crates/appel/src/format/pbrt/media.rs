//! `MakeNamedMedium` and `MediumInterface`: pbrt-v4's `homogeneous`, `uniformgrid` and `rgbgrid`
//! media as `[media.NAME]`, and the media the graphics state gives the shapes that follow and the
//! camera.
//!
//! pbrt-v4 writes a medium as `sigma_a` and `sigma_s` (spectra, default 1) times `scale`, with a
//! Henyey-Greenstein `g` (positive forward, as Mitsuba's and Appel's). A `uniformgrid` multiplies
//! the extinction by a grid of `density` values over the box `p0`-`p1` in the medium's space (its
//! samples at the cells' centres, interpolated trilinearly, pbrt-v4's `SampledGrid`), which
//! becomes a three-channel grid of `density (sigma_a + sigma_s)` in Appel's terms, with the albedo
//! `sigma_s / (sigma_a + sigma_s)`. An `rgbgrid` gives `sigma_a` and `sigma_s` as grids of RGB
//! values of their own over the same cells and box (either absent is 1 everywhere), both times
//! `scale`: a heterogeneous medium in its absorption and scattering form. Emission (`Le`) is an
//! error: Appel's media absorb and scatter only.

use super::convert::Converter;
use super::params::ParamType;
use super::parser::Directive;
use super::spectrum::{rgb_of, Use};
use crate::description::{
    ColorDesc, HeterogeneousDesc, HgDesc, HomogeneousDesc, IsotropicDesc, MediumDesc, PhaseDesc,
    TransformDesc, VolumeDesc, VolumeNode,
};
use crate::error::Result;
use glam::{DMat4, DVec3};

const MEDIA: &str = "homogeneous, uniformgrid, rgbgrid";

impl Converter {
    /// `MakeNamedMedium "name" "string type" ...`.
    pub(super) fn named_medium(&mut self, d: &Directive) -> Result<()> {
        let name = d.strings[0].clone();
        if name.is_empty() {
            return Err(d
                .loc
                .error("a medium needs a name (the empty name is vacuum)"));
        }
        let p = &d.params;
        let kind = p
            .string("type")?
            .ok_or_else(|| d.loc.error("MakeNamedMedium needs a \"string type\""))?
            .to_string();
        if let Some(q) = p.get("preset") {
            p.string("preset")?;
            return Err(q.error(
                "the measured media of pbrt's \"preset\" are not available: give sigma_a and \
                 sigma_s",
            ));
        }
        for emission in [
            "Le",
            "Lescale",
            "temperature",
            "temperaturescale",
            "temperatureoffset",
        ] {
            if let Some(q) = p.get(emission) {
                p.ignore(emission);
                return Err(q.error(format!(
                    "\"{emission}\": emitting media are not supported (Appel's media absorb and \
                     scatter)"
                )));
            }
        }
        let colour = |key: &str| -> Result<[f32; 3]> {
            match p.get(key) {
                Some(q) => {
                    let c = rgb_of(q, Use::Unbounded, &self.base_dir)?;
                    if c.iter().any(|x| !(x.is_finite() && *x >= 0.0)) {
                        return Err(q.error(format!("\"{key}\" must not be negative, got {c:?}")));
                    }
                    Ok(c)
                }
                None => Ok([1.0; 3]),
            }
        };
        let scale = p.float_or("scale", 1.0)?;
        if !(scale.is_finite() && scale >= 0.0) {
            let q = p.get("scale").expect("read above");
            return Err(q.error(format!("\"scale\" must not be negative, got {scale}")));
        }
        let g = p.float_or("g", 0.0)?;
        let phase = if g == 0.0 {
            PhaseDesc::Isotropic(IsotropicDesc {})
        } else {
            PhaseDesc::Hg(HgDesc { g: g as f32 })
        };
        let desc = match kind.as_str() {
            "homogeneous" => MediumDesc::Homogeneous(HomogeneousDesc {
                sigma_a: Some(ColorDesc::Rgb(colour("sigma_a")?)),
                sigma_s: Some(ColorDesc::Rgb(colour("sigma_s")?)),
                scale: scale as f32,
                phase,
                ..HomogeneousDesc::default()
            }),
            "uniformgrid" => {
                let (sigma_a, sigma_s) = (colour("sigma_a")?, colour("sigma_s")?);
                let (resolution, transform) = self.grid_space(d)?;
                let q = p
                    .get("density")
                    .ok_or_else(|| d.loc.error("a uniformgrid medium needs \"float density\""))?;
                let density = q.numbers().to_vec();
                p.ignore("density");
                let cells = resolution.iter().product::<usize>();
                if density.len() != cells {
                    return Err(q.error(format!(
                        "{} x {} x {} cells need {cells} densities, got {}",
                        resolution[0],
                        resolution[1],
                        resolution[2],
                        density.len()
                    )));
                }
                if let Some(bad) = density.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
                    return Err(q.error(format!("densities must not be negative, got {bad}")));
                }
                let sigma_t: [f32; 3] = std::array::from_fn(|k| sigma_a[k] + sigma_s[k]);
                let values = density
                    .iter()
                    .flat_map(|&v| sigma_t.map(|s| v as f32 * s))
                    .collect();
                let albedo: [f32; 3] = std::array::from_fn(|k| {
                    if sigma_t[k] > 0.0 {
                        sigma_s[k] / sigma_t[k]
                    } else {
                        0.0
                    }
                });
                MediumDesc::Heterogeneous(HeterogeneousDesc {
                    sigma_t: Some(Box::new(VolumeDesc::Volume(VolumeNode::Values {
                        resolution,
                        channels: 3,
                        values,
                        transform: Some(transform),
                    }))),
                    albedo: Some(Box::new(VolumeDesc::Rgb(albedo))),
                    scale: scale as f32,
                    phase,
                    ..HeterogeneousDesc::default()
                })
            }
            "rgbgrid" => {
                let (resolution, transform) = self.grid_space(d)?;
                let cells = resolution.iter().product::<usize>();
                // An absent grid is 1 everywhere (pbrt-v4's `RGBGridMedium`).
                let grid = |key: &str| -> Result<Box<VolumeDesc>> {
                    let Some(q) = p.array(key, ParamType::Rgb)? else {
                        return Ok(Box::new(VolumeDesc::Value(1.0)));
                    };
                    let v = q.numbers();
                    if v.len() != 3 * cells {
                        return Err(q.error(format!(
                            "{} x {} x {} cells need {cells} rgb values ({} numbers) for \
                             \"{key}\", got {} numbers",
                            resolution[0],
                            resolution[1],
                            resolution[2],
                            3 * cells,
                            v.len()
                        )));
                    }
                    if let Some(bad) = v.iter().find(|x| !(x.is_finite() && **x >= 0.0)) {
                        return Err(q.error(format!("\"{key}\" must not be negative, got {bad}")));
                    }
                    Ok(Box::new(VolumeDesc::Volume(VolumeNode::Values {
                        resolution,
                        channels: 3,
                        values: v.iter().map(|&x| x as f32).collect(),
                        transform: Some(transform.clone()),
                    })))
                };
                if p.get("sigma_a").is_none() && p.get("sigma_s").is_none() {
                    return Err(d.loc.error(
                        "an rgbgrid medium needs \"rgb sigma_a\" or \"rgb sigma_s\" (or both)",
                    ));
                }
                MediumDesc::Heterogeneous(HeterogeneousDesc {
                    sigma_a: Some(grid("sigma_a")?),
                    sigma_s: Some(grid("sigma_s")?),
                    scale: scale as f32,
                    phase,
                    ..HeterogeneousDesc::default()
                })
            }
            other => {
                let q = p.get("type").expect("read above");
                return Err(q.error(format!(
                    "unsupported medium \"{other}\" (supported: {MEDIA}; cloud and nanovdb are \
                     not)"
                )));
            }
        };
        if let Err(e) = desc.check() {
            return Err(d.loc.error(e.message));
        }
        self.media.insert(name, desc);
        Ok(())
    }

    /// A grid medium's cells (`nx`, `ny`, `nz`) and the transform of the unit cube onto its box
    /// `p0`-`p1` in the current space.
    fn grid_space(&self, d: &Directive) -> Result<([usize; 3], TransformDesc)> {
        if !self.in_world() {
            return Err(d
                .loc
                .error("define a grid medium after WorldBegin (its space is the world's)"));
        }
        let p = &d.params;
        let mut resolution = [1usize; 3];
        for (r, k) in resolution.iter_mut().zip(["nx", "ny", "nz"]) {
            let v = p.int(k)?.unwrap_or(1);
            if !(1..=4096).contains(&v) {
                let q = p.get(k).expect("a value out of range was given");
                return Err(q.error(format!("\"{k}\" must lie in 1..4096, got {v}")));
            }
            *r = v as usize;
        }
        let p0 = DVec3::from(p.point3("p0")?.unwrap_or([0.0; 3]));
        let p1 = DVec3::from(p.point3("p1")?.unwrap_or([1.0; 3]));
        if (p1 - p0).min_element() <= 0.0 {
            return Err(d.loc.error("the grid's box p0-p1 must have volume"));
        }
        let box_to_world = self.to_description(&self.attrs.ctm)
            * DMat4::from_translation(p0)
            * DMat4::from_scale(p1 - p0);
        let transform = TransformDesc {
            matrix: Some(
                box_to_world
                    .transpose()
                    .to_cols_array_2d()
                    .map(|r| r.map(|x| x as f32)),
            ),
            ..TransformDesc::default()
        };
        Ok((resolution, transform))
    }

    /// `MediumInterface "inside" "outside"` (one name: both): the media of the shapes that
    /// follow, and of the camera if it comes after.
    pub(super) fn medium_interface(&mut self, d: &Directive) -> Result<()> {
        let inside = d.strings[0].clone();
        let outside = d.strings.get(1).cloned().unwrap_or_else(|| inside.clone());
        let named = |n: String| -> Result<Option<String>> {
            if n.is_empty() {
                return Ok(None);
            }
            if !self.media.contains_key(&n) {
                return Err(d
                    .loc
                    .error(format!("no medium is named \"{n}\" (MakeNamedMedium)")));
            }
            Ok(Some(n))
        };
        self.attrs.medium_inside = named(inside)?;
        self.attrs.medium_outside = named(outside)?;
        Ok(())
    }
}
