//! `<medium>`, `<phase>` and `<volume>` to `[media.NAME]`: Mitsuba 3's `homogeneous` and
//! `heterogeneous` media with their nested phase function (isotropic when none), their
//! coefficients as constants or volumes (`constvolume`, `gridvolume`), and the media shapes
//! bound (`<ref name="interior">`, `exterior`) and sensors sit in.

use super::super::document::{Object, TextureArg};
use super::super::spectrum::SpectrumUse;
use super::bsdf::constant_color;
use super::origin::origin_of;
use super::{rows_f32, Converter};
use crate::description::origins::key_path;
use crate::description::{
    BlendPhaseDesc, ColorDesc, HeterogeneousDesc, HgDesc, HomogeneousDesc, IsotropicDesc,
    MediumDesc, PhaseDesc, RayleighDesc, TransformDesc, VolumeDesc, VolumeFilter, VolumeNode,
};
use crate::error::Result;
use glam::DMat4;
use std::rc::Rc;

const MEDIA: &str = "homogeneous, heterogeneous";
const PHASES: &str = "isotropic, hg, rayleigh, blendphase";
const VOLUMES: &str = "constvolume, gridvolume";

impl Converter<'_> {
    /// The `[media.NAME]` of a `<medium>`, converted once however many objects name it.
    pub(super) fn medium(&mut self, m: &Rc<Object>) -> Result<String> {
        if m.class != "medium" {
            return Err(m.error("expected a <medium>"));
        }
        if let Some(name) = self.medium_of.get(&Rc::as_ptr(m)) {
            return Ok(name.clone());
        }
        let mut name =
            m.id.clone()
                .unwrap_or_else(|| format!("medium_{}", self.media.len()));
        while self.media.contains_key(&name) {
            name.push('_');
        }
        let desc = self.medium_desc(m)?;
        self.origins
            .record(key_path(&[&"media", &name]), origin_of(m));
        self.media.insert(name.clone(), desc);
        self.medium_of.insert(Rc::as_ptr(m), name.clone());
        Ok(name)
    }

    /// A shape's `interior` and `exterior` media.
    pub(super) fn shape_media(&mut self, s: &Object) -> Result<(Option<String>, Option<String>)> {
        let mut sides = [None, None];
        for (side, key) in sides.iter_mut().zip(["interior", "exterior"]) {
            if let Some(child) = s.named_child(key) {
                let m = self.doc.target(child)?;
                *side = Some(self.medium(&m)?);
            }
        }
        for child in &s.children {
            let o = self.doc.target(child)?;
            let named_side = matches!(child.name.as_deref(), Some("interior" | "exterior"));
            if o.class == "medium" && !named_side {
                return Err(child.loc.error(
                    "a shape's medium is named \"interior\" or \"exterior\" (as in Mitsuba)",
                ));
            }
        }
        let [interior, exterior] = sides;
        Ok((interior, exterior))
    }

    /// The medium a sensor sits in: its one `<medium>` child, whatever its name.
    pub(super) fn sensor_medium(&mut self, s: &Object) -> Result<Option<String>> {
        let mut found = None;
        for child in &s.children {
            let o = self.doc.target(child)?;
            if o.class != "medium" {
                continue;
            }
            if found.is_some() {
                return Err(child.loc.error("a sensor sits in one medium"));
            }
            s.take(child);
            found = Some(self.medium(&o)?);
        }
        Ok(found)
    }

    fn medium_desc(&mut self, m: &Object) -> Result<MediumDesc> {
        let phase = self.medium_phase(m)?;
        // Appel always samples emitters from inside media, as Mitsuba's default does.
        if !m.bool_or("sample_emitters", true)? {
            let p = m.prop("sample_emitters").expect("read above");
            return Err(p.error("Appel always samples emitters from media (the value true)"));
        }
        // An optimisation hint in Mitsuba (RGB extinction tracked per channel or not): the
        // estimate's expectation is the same either way.
        m.bool("has_spectral_extinction")?;
        let scale = m.float_or("scale", 1.0)? as f32;
        let d = match m.plugin.as_str() {
            "homogeneous" => {
                let sigma_t = match self.volume_arg(m, "sigma_t", SpectrumUse::Unbounded)? {
                    None => None,
                    Some(v) => Some(match v.constant() {
                        Some(c) => ColorDesc::Rgb(c),
                        None => {
                            let c = m.named_child("sigma_t").expect("a volume object");
                            return Err(c.loc.error(
                                "a homogeneous medium's sigma_t is one constant (use a \
                                 heterogeneous medium for a grid)",
                            ));
                        }
                    }),
                };
                let colour = |name: &str| -> Result<Option<ColorDesc>> {
                    Ok(constant_color(self, m, name, SpectrumUse::Unbounded)?.map(ColorDesc::Rgb))
                };
                let (sigma_a, sigma_s) = (colour("sigma_a")?, colour("sigma_s")?);
                MediumDesc::Homogeneous(HomogeneousDesc {
                    sigma_t,
                    albedo: self.volume_arg(m, "albedo", SpectrumUse::Reflectance)?,
                    sigma_a,
                    sigma_s,
                    scale,
                    phase,
                })
            }
            "heterogeneous" => MediumDesc::Heterogeneous(HeterogeneousDesc {
                sigma_t: self
                    .volume_arg(m, "sigma_t", SpectrumUse::Unbounded)?
                    .map(Box::new),
                albedo: self
                    .volume_arg(m, "albedo", SpectrumUse::Reflectance)?
                    .map(Box::new),
                scale,
                phase,
                ..HeterogeneousDesc::default()
            }),
            p => {
                return Err(m.error(format!(
                    "unsupported medium plugin \"{p}\" (supported: {MEDIA})"
                )))
            }
        };
        if let Err(e) = d.check() {
            return Err(match m.prop(e.key) {
                Some(p) => p.error(e.message),
                None => m.error(e.message),
            });
        }
        m.finish()?;
        Ok(d)
    }

    /// The medium's nested phase function (any name), isotropic without one.
    fn medium_phase(&mut self, m: &Object) -> Result<PhaseDesc> {
        let mut phase = None;
        for child in &m.children {
            let o = self.doc.target(child)?;
            if o.class != "phase" {
                continue;
            }
            if phase.is_some() {
                return Err(child.loc.error("a medium has one phase function"));
            }
            m.take(child);
            phase = Some(phase_desc(&o)?);
        }
        Ok(phase.unwrap_or_default())
    }

    /// A coefficient given as a constant or as a `<volume>`.
    fn volume_arg(&self, m: &Object, name: &str, use_: SpectrumUse) -> Result<Option<VolumeDesc>> {
        if let Some(TextureArg::Object(v, child)) = m.texture(self.doc, name)? {
            if v.class != "volume" {
                return Err(child.loc.error(format!(
                    "\"{name}\" of {} is a constant or a <volume>, not a <{}>",
                    m.describe(),
                    v.class
                )));
            }
            return Ok(Some(VolumeDesc::Volume(self.volume_node(&v)?)));
        }
        Ok(constant_color(self, m, name, use_)?.map(|c| {
            if c[0] == c[1] && c[1] == c[2] {
                VolumeDesc::Value(c[0])
            } else {
                VolumeDesc::Rgb(c)
            }
        }))
    }

    fn volume_node(&self, v: &Object) -> Result<VolumeNode> {
        let to_world = v.transform("to_world")?;
        let transform = to_world
            .filter(|m| *m != DMat4::IDENTITY)
            .map(|m| TransformDesc {
                matrix: Some(rows_f32(&m)),
                ..TransformDesc::default()
            });
        let node = match v.plugin.as_str() {
            "constvolume" => {
                let value =
                    constant_color(self, v, "value", SpectrumUse::Unbounded)?.unwrap_or([0.75; 3]);
                VolumeNode::ConstVolume {
                    value: ColorDesc::Rgb(value),
                    transform,
                }
            }
            "gridvolume" | "grid" => {
                let filter = match v.string("filter_type")?.unwrap_or("trilinear") {
                    "trilinear" => VolumeFilter::Trilinear,
                    "nearest" => VolumeFilter::Nearest,
                    f => {
                        let p = v.prop("filter_type").expect("read above");
                        return Err(p.error(format!(
                            "unknown filter_type \"{f}\" (trilinear or nearest)"
                        )));
                    }
                };
                if let Some(w) = v.string("wrap_mode")? {
                    if w != "clamp" {
                        let p = v.prop("wrap_mode").expect("read above");
                        return Err(p.error("Appel's grid volumes clamp (wrap_mode clamp)"));
                    }
                }
                if v.bool_or("use_grid_bbox", false)? {
                    let p = v.prop("use_grid_bbox").expect("read above");
                    return Err(p.error(
                        "place the grid with to_world: the file's bounding box is not read",
                    ));
                }
                // Mitsuba's acceleration of lookups and raw RGB storage change nothing in RGB.
                v.bool("accel")?;
                v.bool("raw")?;
                VolumeNode::GridVolume {
                    file: self.file(v, "filename")?,
                    transform,
                    filter,
                }
            }
            p => {
                return Err(v.error(format!(
                    "unsupported volume plugin \"{p}\" (supported: {VOLUMES})"
                )))
            }
        };
        v.finish()?;
        Ok(node)
    }
}

fn phase_desc(p: &Object) -> Result<PhaseDesc> {
    let d = match p.plugin.as_str() {
        "isotropic" => PhaseDesc::Isotropic(IsotropicDesc {}),
        "hg" => PhaseDesc::Hg(HgDesc {
            g: p.float_or("g", 0.8)? as f32,
        }),
        "rayleigh" => PhaseDesc::Rayleigh(RayleighDesc {}),
        "blendphase" => {
            let mut phases = Vec::new();
            for child in &p.children {
                let Some(o) = (match &child.target {
                    super::super::document::Target::Object(o) => Some(o.clone()),
                    super::super::document::Target::Ref(_) => None,
                }) else {
                    return Err(child
                        .loc
                        .error("nest the <phase> rather than referencing it"));
                };
                if o.class == "phase" {
                    p.take(child);
                    phases.push(phase_desc(&o)?);
                }
            }
            let [a, b]: [PhaseDesc; 2] = phases
                .try_into()
                .map_err(|_| p.error("a blendphase blends exactly two <phase> functions"))?;
            PhaseDesc::BlendPhase(BlendPhaseDesc {
                weight: p.float_or("weight", 0.5)? as f32,
                phases: Box::new([a, b]),
            })
        }
        other => {
            return Err(p.error(format!(
                "unsupported phase plugin \"{other}\" (supported: {PHASES})"
            )))
        }
    };
    if let Err(e) = d.check() {
        return Err(match p.prop(e.key) {
            Some(prop) => prop.error(e.message),
            None => p.error(e.message),
        });
    }
    p.finish()?;
    Ok(d)
}
