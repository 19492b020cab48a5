//! BSDFs to `[materials.NAME]`, and texture-valued parameters to `TextureDesc`, with Mitsuba's
//! parameter names and defaults.

use super::super::document::{Object, Spectrum, TextureArg};
use super::super::spectrum::{pairs_to_rgb, SpectrumUse, UNIFORM_EMITTER_RGB};
use super::super::transform::to_rows;
use super::origin::origin_of;
use super::Converter;
use crate::description::origins::key_path;
use crate::description::{
    BlendDesc, BsdfParams, BumpMapDesc, CoatedConductorDesc, CoatedDiffuseDesc, ConductorDesc,
    DielectricDesc, DiffuseDesc, DistributionDesc, IorDesc, MaskDesc, MaterialDesc, NormalMapDesc,
    PhongDesc, PlasticDesc, PrincipledDesc, PrincipledThinDesc, RoughConductorDesc,
    RoughDielectricDesc, RoughPlasticDesc, TextureDesc, TextureFilter, TextureNode, TextureWrap,
    ThinDielectricDesc, TwoSidedDesc,
};
use crate::error::Result;
use std::rc::Rc;

/// Mitsuba's BSDF for shapes without one: diffuse, reflectance 0.5.
pub(super) fn mitsuba_default() -> MaterialDesc {
    MaterialDesc::Diffuse(DiffuseDesc {
        reflectance: TextureDesc::Value(0.5),
    })
}

impl Converter<'_> {
    /// The material name of a `<bsdf>`, converting it (and what it wraps) the first time.
    pub(super) fn material(&mut self, b: &Rc<Object>) -> Result<String> {
        if b.class != "bsdf" {
            return Err(b.error("expected a <bsdf>"));
        }
        let key = Rc::as_ptr(b);
        if let Some(name) = self.material_of.get(&key) {
            return Ok(name.clone());
        }
        let base = b.id.clone().unwrap_or_else(|| b.plugin.clone());
        let mut name = base.clone();
        let mut n = 1;
        while self.materials.contains_key(&name) || self.material_of.values().any(|v| *v == name) {
            name = format!("{base}_{n}");
            n += 1;
        }
        // Reserved before converting, so that what this BSDF wraps gets other names.
        self.material_of.insert(key, name.clone());
        let desc = self.bsdf(b)?;
        b.finish()?;
        self.materials.insert(name.clone(), desc);
        self.origins
            .record(key_path(&[&"materials", &name]), origin_of(b));
        Ok(name)
    }

    /// The nested (or referenced) BSDFs of a wrapper, converted.
    fn nested_bsdfs(&mut self, b: &Object) -> Result<Vec<String>> {
        let mut names = Vec::new();
        let children: Vec<_> = b.unnamed_children().collect();
        for child in children {
            let o = self.doc.target(child)?;
            if o.class == "bsdf" {
                b.take(child);
                names.push(self.material(&o)?);
            }
        }
        Ok(names)
    }

    fn bsdf(&mut self, b: &Object) -> Result<MaterialDesc> {
        Ok(match b.plugin.as_str() {
            "diffuse" => MaterialDesc::Diffuse(DiffuseDesc {
                reflectance: tex(self, b, "reflectance", 0.5)?,
            }),
            "conductor" => MaterialDesc::Conductor(ConductorDesc {
                material: b.string("material")?.map(str::to_string),
                eta: constant_color(self, b, "eta", SpectrumUse::Unbounded)?,
                k: constant_color(self, b, "k", SpectrumUse::Unbounded)?,
                specular_reflectance: tex(self, b, "specular_reflectance", 1.0)?,
            }),
            "roughconductor" => {
                let (distribution, alpha, alpha_u, alpha_v, sample_visible) = rough(self, b, true)?;
                MaterialDesc::RoughConductor(RoughConductorDesc {
                    material: b.string("material")?.map(str::to_string),
                    eta: constant_color(self, b, "eta", SpectrumUse::Unbounded)?,
                    k: constant_color(self, b, "k", SpectrumUse::Unbounded)?,
                    specular_reflectance: tex(self, b, "specular_reflectance", 1.0)?,
                    distribution,
                    alpha,
                    alpha_u,
                    alpha_v,
                    sample_visible,
                })
            }
            "dielectric" => MaterialDesc::Dielectric(DielectricDesc {
                int_ior: ior(b, "int_ior", "bk7")?,
                ext_ior: ior(b, "ext_ior", "air")?,
                specular_reflectance: tex(self, b, "specular_reflectance", 1.0)?,
                specular_transmittance: tex(self, b, "specular_transmittance", 1.0)?,
            }),
            // An index-matched boundary of media.
            "null" => MaterialDesc::Null(crate::description::NullDesc {}),
            "thindielectric" => MaterialDesc::ThinDielectric(ThinDielectricDesc {
                int_ior: ior(b, "int_ior", "bk7")?,
                ext_ior: ior(b, "ext_ior", "air")?,
                specular_reflectance: tex(self, b, "specular_reflectance", 1.0)?,
                specular_transmittance: tex(self, b, "specular_transmittance", 1.0)?,
            }),
            "roughdielectric" => {
                let (distribution, alpha, alpha_u, alpha_v, sample_visible) = rough(self, b, true)?;
                MaterialDesc::RoughDielectric(RoughDielectricDesc {
                    int_ior: ior(b, "int_ior", "bk7")?,
                    ext_ior: ior(b, "ext_ior", "air")?,
                    specular_reflectance: tex(self, b, "specular_reflectance", 1.0)?,
                    specular_transmittance: tex(self, b, "specular_transmittance", 1.0)?,
                    distribution,
                    alpha,
                    alpha_u,
                    alpha_v,
                    sample_visible,
                })
            }
            "plastic" => MaterialDesc::Plastic(PlasticDesc {
                int_ior: ior(b, "int_ior", "polypropylene")?,
                ext_ior: ior(b, "ext_ior", "air")?,
                diffuse_reflectance: tex(self, b, "diffuse_reflectance", 0.5)?,
                specular_reflectance: tex(self, b, "specular_reflectance", 1.0)?,
                nonlinear: b.bool_or("nonlinear", false)?,
            }),
            "roughplastic" => {
                // Mitsuba's rough plastic is isotropic: `alpha` only.
                let (distribution, alpha, _, _, sample_visible) = rough(self, b, false)?;
                MaterialDesc::RoughPlastic(RoughPlasticDesc {
                    int_ior: ior(b, "int_ior", "polypropylene")?,
                    ext_ior: ior(b, "ext_ior", "air")?,
                    diffuse_reflectance: tex(self, b, "diffuse_reflectance", 0.5)?,
                    specular_reflectance: tex(self, b, "specular_reflectance", 1.0)?,
                    nonlinear: b.bool_or("nonlinear", false)?,
                    distribution,
                    alpha,
                    alpha_u: None,
                    alpha_v: None,
                    sample_visible,
                })
            }
            "principled" => {
                if b.prop("eta").is_some() && b.prop("specular").is_some() {
                    let p = b.prop("specular").expect("present");
                    return Err(p.error("give either \"eta\" or \"specular\", not both"));
                }
                MaterialDesc::Principled(PrincipledDesc {
                    base_color: tex(self, b, "base_color", 0.5)?,
                    roughness: tex(self, b, "roughness", 0.5)?,
                    anisotropic: tex(self, b, "anisotropic", 0.0)?,
                    metallic: tex(self, b, "metallic", 0.0)?,
                    spec_trans: tex(self, b, "spec_trans", 0.0)?,
                    spec_tint: tex(self, b, "spec_tint", 0.0)?,
                    sheen: tex(self, b, "sheen", 0.0)?,
                    sheen_tint: tex(self, b, "sheen_tint", 0.0)?,
                    flatness: tex(self, b, "flatness", 0.0)?,
                    clearcoat: tex(self, b, "clearcoat", 0.0)?,
                    clearcoat_gloss: tex(self, b, "clearcoat_gloss", 0.0)?,
                    eta: b.float("eta")?.map(|v| v as f32),
                    specular: b.float("specular")?.map(|v| v as f32),
                    diffuse_reflectance_sampling_rate: b
                        .float_or("diffuse_reflectance_sampling_rate", 1.0)?
                        as f32,
                    main_specular_sampling_rate: b.float_or("main_specular_sampling_rate", 1.0)?
                        as f32,
                    clearcoat_sampling_rate: b.float_or("clearcoat_sampling_rate", 1.0)? as f32,
                })
            }
            "principledthin" => MaterialDesc::PrincipledThin(PrincipledThinDesc {
                base_color: tex(self, b, "base_color", 0.5)?,
                roughness: tex(self, b, "roughness", 0.5)?,
                anisotropic: tex(self, b, "anisotropic", 0.0)?,
                spec_trans: tex(self, b, "spec_trans", 0.0)?,
                spec_tint: tex(self, b, "spec_tint", 0.0)?,
                sheen: tex(self, b, "sheen", 0.0)?,
                sheen_tint: tex(self, b, "sheen_tint", 0.0)?,
                flatness: tex(self, b, "flatness", 0.0)?,
                diff_trans: tex(self, b, "diff_trans", 0.0)?,
                eta: tex(self, b, "eta", 1.5)?,
                specular_reflectance_sampling_rate: b
                    .float_or("specular_reflectance_sampling_rate", 1.0)?
                    as f32,
                specular_transmittance_sampling_rate: b
                    .float_or("specular_transmittance_sampling_rate", 1.0)?
                    as f32,
                diffuse_reflectance_sampling_rate: b
                    .float_or("diffuse_reflectance_sampling_rate", 1.0)?
                    as f32,
                diffuse_transmittance_sampling_rate: b
                    .float_or("diffuse_transmittance_sampling_rate", 1.0)?
                    as f32,
            }),
            // pbrt-v4's layered BSDFs, with the keys of Appel's scene format (Mitsuba has no
            // such plugin).
            "coateddiffuse" => MaterialDesc::CoatedDiffuse(CoatedDiffuseDesc {
                reflectance: tex(self, b, "reflectance", 0.5)?,
                alpha: tex(self, b, "alpha", 0.0)?,
                alpha_u: texture(self, b, "alpha_u", SpectrumUse::Reflectance)?,
                alpha_v: texture(self, b, "alpha_v", SpectrumUse::Reflectance)?,
                eta: b.float_or("eta", 1.5)? as f32,
                thickness: b.float_or("thickness", 0.01)? as f32,
                albedo: tex(self, b, "albedo", 0.0)?,
                g: b.float_or("g", 0.0)? as f32,
                maxdepth: layer_int(b, "maxdepth", 10)?,
                nsamples: layer_int(b, "nsamples", 1)?,
            }),
            "coatedconductor" => MaterialDesc::CoatedConductor(CoatedConductorDesc {
                interface_eta: b.float_or("interface_eta", 1.5)? as f32,
                interface_alpha: tex(self, b, "interface_alpha", 0.0)?,
                interface_alpha_u: texture(self, b, "interface_alpha_u", SpectrumUse::Reflectance)?,
                interface_alpha_v: texture(self, b, "interface_alpha_v", SpectrumUse::Reflectance)?,
                conductor_material: b.string("conductor_material")?.unwrap_or("Cu").to_string(),
                conductor_eta: constant_color(self, b, "conductor_eta", SpectrumUse::Unbounded)?,
                conductor_k: constant_color(self, b, "conductor_k", SpectrumUse::Unbounded)?,
                conductor_alpha: tex(self, b, "conductor_alpha", 0.0)?,
                conductor_alpha_u: texture(self, b, "conductor_alpha_u", SpectrumUse::Reflectance)?,
                conductor_alpha_v: texture(self, b, "conductor_alpha_v", SpectrumUse::Reflectance)?,
                thickness: b.float_or("thickness", 0.01)? as f32,
                albedo: tex(self, b, "albedo", 0.0)?,
                g: b.float_or("g", 0.0)? as f32,
                maxdepth: layer_int(b, "maxdepth", 10)?,
                nsamples: layer_int(b, "nsamples", 1)?,
            }),
            "twosided" => {
                let nested = self.nested_bsdfs(b)?;
                match nested.as_slice() {
                    [front] => MaterialDesc::TwoSided(TwoSidedDesc {
                        front: front.clone(),
                        back: None,
                    }),
                    [front, back] => MaterialDesc::TwoSided(TwoSidedDesc {
                        front: front.clone(),
                        back: Some(back.clone()),
                    }),
                    _ => return Err(b.error("expected one or two nested BSDFs")),
                }
            }
            "mask" => {
                let opacity = tex(self, b, "opacity", 0.5)?;
                let nested = self.nested_bsdfs(b)?;
                let [material] = nested.as_slice() else {
                    return Err(b.error("expected one nested BSDF"));
                };
                MaterialDesc::Mask(MaskDesc {
                    opacity,
                    material: material.clone(),
                })
            }
            "blendbsdf" => {
                let weight = tex(self, b, "weight", 0.5)?;
                let nested = self.nested_bsdfs(b)?;
                let [first, second] = nested.as_slice() else {
                    return Err(b.error("expected two nested BSDFs"));
                };
                MaterialDesc::Blend(BlendDesc {
                    weight,
                    materials: [first.clone(), second.clone()],
                })
            }
            "normalmap" => {
                let Some(normalmap) = texture(self, b, "normalmap", SpectrumUse::Unbounded)? else {
                    return Err(b.error("expected a \"normalmap\" texture"));
                };
                let nested = self.nested_bsdfs(b)?;
                let [material] = nested.as_slice() else {
                    return Err(b.error("expected one nested BSDF"));
                };
                MaterialDesc::NormalMap(NormalMapDesc {
                    normalmap,
                    material: material.clone(),
                    flip_invalid_normals: b.bool_or("flip_invalid_normals", true)?,
                    use_shadowing_function: b.bool_or("use_shadowing_function", true)?,
                })
            }
            "bumpmap" => {
                // Mitsuba takes the one texture child, whatever its name.
                let mut textures = Vec::new();
                for child in &b.children {
                    let o = self.doc.target(child)?;
                    if o.class == "texture" {
                        b.take(child);
                        textures.push(o);
                    }
                }
                let [t] = textures.as_slice() else {
                    return Err(b.error("expected exactly one nested texture (the height field)"));
                };
                let bumpmap = texture_object(self, t)?;
                let nested = self.nested_bsdfs(b)?;
                let [material] = nested.as_slice() else {
                    return Err(b.error("expected one nested BSDF"));
                };
                MaterialDesc::BumpMap(BumpMapDesc {
                    bumpmap,
                    scale: b.float_or("scale", 1.0)? as f32,
                    material: material.clone(),
                    flip_invalid_normals: b.bool_or("flip_invalid_normals", true)?,
                    use_shadowing_function: b.bool_or("use_shadowing_function", true)?,
                })
            }
            p => {
                // `phong` is Whitted's model, appel's own: Mitsuba's XML has no such plugin.
                let supported: Vec<&str> = MaterialDesc::BSDF_NAMES
                    .iter()
                    .filter(|n| **n != <PhongDesc as BsdfParams>::NAME)
                    .chain(MaterialDesc::WRAPPER_NAMES)
                    .copied()
                    .collect();
                return Err(b.error(format!(
                    "unsupported BSDF plugin \"{p}\" (supported: {})",
                    supported.join(", ")
                )));
            }
        })
    }
}

/// A layered BSDF's walk bound (`maxdepth`, `nsamples`); validation bounds it further.
fn layer_int(b: &Object, name: &str, default: u32) -> Result<u32> {
    Ok(b.int_in(name, 1..=u32::MAX as i64)?
        .map_or(default, |v| v as u32))
}

/// A reflectance-like texture parameter with Mitsuba's default.
fn tex(c: &Converter, b: &Object, name: &str, default: f64) -> Result<TextureDesc> {
    Ok(
        texture(c, b, name, SpectrumUse::Reflectance)?
            .unwrap_or(TextureDesc::Value(default as f32)),
    )
}

type Rough = (
    DistributionDesc,
    Option<TextureDesc>,
    Option<TextureDesc>,
    Option<TextureDesc>,
    bool,
);

/// `distribution`, `alpha` (or, where `anisotropic`, `alpha_u` and `alpha_v`), `sample_visible`.
fn rough(c: &Converter, b: &Object, anisotropic: bool) -> Result<Rough> {
    let distribution = match b.string("distribution")?.unwrap_or("beckmann") {
        "beckmann" => DistributionDesc::Beckmann,
        "ggx" => DistributionDesc::Ggx,
        d => {
            let p = b.prop("distribution").expect("read above");
            return Err(p.error(format!("unknown distribution \"{d}\" (beckmann or ggx)")));
        }
    };
    let alpha = texture(c, b, "alpha", SpectrumUse::Reflectance)?;
    let (mut alpha_u, mut alpha_v) = (None, None);
    if anisotropic {
        alpha_u = texture(c, b, "alpha_u", SpectrumUse::Reflectance)?;
        alpha_v = texture(c, b, "alpha_v", SpectrumUse::Reflectance)?;
        if alpha_u.is_some() != alpha_v.is_some() || (alpha.is_some() && alpha_u.is_some()) {
            return Err(b.error("give either alpha, or both alpha_u and alpha_v"));
        }
    }
    let sample_visible = b.bool_or("sample_visible", true)?;
    Ok((distribution, alpha, alpha_u, alpha_v, sample_visible))
}

/// An index of refraction: a number or one of Mitsuba's names, passed on as written.
fn ior(b: &Object, name: &str, default: &str) -> Result<IorDesc> {
    let Some(p) = b.prop(name) else {
        return Ok(IorDesc::Named(default.into()));
    };
    match &p.value {
        super::super::document::Value::String(s) => Ok(IorDesc::Named(s.clone())),
        _ => Ok(IorDesc::Value(b.float(name)?.expect("present") as f32)),
    }
}

/// A parameter where Mitsuba accepts a texture.
pub(super) fn texture(
    c: &Converter,
    o: &Object,
    name: &str,
    use_: SpectrumUse,
) -> Result<Option<TextureDesc>> {
    let Some(arg) = o.texture(c.doc, name)? else {
        return Ok(None);
    };
    Ok(Some(match arg {
        TextureArg::Float(v, _) => TextureDesc::Value(v as f32),
        TextureArg::Rgb(rgb, p) => {
            // Mitsuba refuses reflectances outside [0, 1] given in RGB.
            if use_ == SpectrumUse::Reflectance && rgb.iter().any(|v| !(0.0..=1.0).contains(v)) {
                return Err(p.error(format!(
                    "an RGB reflectance must lie in [0, 1], got {rgb:?}"
                )));
            }
            TextureDesc::Rgb(rgb.map(|v| v as f32))
        }
        TextureArg::Spectrum(Spectrum::Uniform(v), _) => match use_ {
            SpectrumUse::Emission => TextureDesc::Rgb(UNIFORM_EMITTER_RGB.map(|c| (c * v) as f32)),
            _ => TextureDesc::Value(*v as f32),
        },
        TextureArg::Spectrum(Spectrum::Pairs(pairs), _) => {
            TextureDesc::Rgb(pairs_to_rgb(pairs, use_).map(|v| v as f32))
        }
        TextureArg::Object(t, _) => texture_object(c, &t)?,
    }))
}

/// A `<texture>` object: Mitsuba's `rawconstant` (a value used as it is, with no colour
/// conversion) as a constant, other plugins as texture nodes.
fn texture_object(c: &Converter, t: &Object) -> Result<TextureDesc> {
    if t.class == "texture" && t.plugin == "rawconstant" {
        let value = match t.prop("value").map(|p| &p.value) {
            Some(super::super::document::Value::Vector(_)) => {
                TextureDesc::Rgb(t.vector("value")?.expect("present").map(|x| x as f32))
            }
            Some(_) => TextureDesc::Value(t.float("value")?.expect("present") as f32),
            None => TextureDesc::Value(1.0),
        };
        t.finish()?;
        return Ok(value);
    }
    Ok(TextureDesc::Texture(texture_node(c, t)?))
}

/// A colour that must be constant over the surface (indices, light colours).
pub(super) fn constant_color(
    c: &Converter,
    o: &Object,
    name: &str,
    use_: SpectrumUse,
) -> Result<Option<[f32; 3]>> {
    match texture(c, o, name, use_)? {
        None => Ok(None),
        Some(TextureDesc::Value(v)) => Ok(Some([v; 3])),
        Some(TextureDesc::Rgb(rgb)) => Ok(Some(rgb)),
        Some(TextureDesc::Texture(_)) => {
            let child = o.named_child(name).expect("a texture object");
            Err(child.loc.error(format!(
                "\"{name}\" of {} must be a constant (<float>, <rgb> or <spectrum>), not a texture",
                o.describe()
            )))
        }
    }
}

pub(super) fn texture_node(c: &Converter, t: &Object) -> Result<TextureNode> {
    if t.class != "texture" {
        return Err(t.error("expected a <texture>"));
    }
    let to_uv = t.transform("to_uv")?.map(|m| {
        // Mitsuba keeps the 2D part of the 4x4: the upper-left 2x2 and the translation.
        let r = to_rows(&m);
        [
            [r[0][0], r[0][1], r[0][3]],
            [r[1][0], r[1][1], r[1][3]],
            [0.0, 0.0, 1.0],
        ]
        .map(|row| row.map(|x| x as f32))
    });
    let node = match t.plugin.as_str() {
        "bitmap" => {
            let file = c.file(t, "filename")?;
            let filter = match t.string("filter_type")?.unwrap_or("bilinear") {
                "bilinear" => TextureFilter::Bilinear,
                "nearest" => TextureFilter::Nearest,
                f => {
                    let p = t.prop("filter_type").expect("read above");
                    return Err(
                        p.error(format!("unknown filter_type \"{f}\" (bilinear or nearest)"))
                    );
                }
            };
            let wrap = match t.string("wrap_mode")?.unwrap_or("repeat") {
                "repeat" => TextureWrap::Repeat,
                "mirror" => TextureWrap::Mirror,
                "clamp" => TextureWrap::Clamp,
                w => {
                    let p = t.prop("wrap_mode").expect("read above");
                    return Err(p.error(format!(
                        "unknown wrap_mode \"{w}\" (repeat, mirror or clamp)"
                    )));
                }
            };
            // Storage precision only (Mitsuba's half, single or the variant's precision): values
            // are kept in f32 here whatever it says.
            if let Some(format) = t.string("format")? {
                if !matches!(format, "auto" | "variant" | "fp16" | "fp32") {
                    let p = t.prop("format").expect("read above");
                    return Err(p.error(format!(
                        "unknown format \"{format}\" (auto, variant, fp16 or fp32)"
                    )));
                }
            }
            TextureNode::Bitmap {
                file,
                filter,
                wrap,
                raw: t.bool_or("raw", false)?,
                to_uv,
            }
        }
        "checkerboard" => {
            let color = |name: &str, default: f32| -> Result<[f32; 3]> {
                Ok(constant_color(c, t, name, SpectrumUse::Reflectance)?.unwrap_or([default; 3]))
            };
            TextureNode::Checkerboard {
                color0: color("color0", 0.4)?,
                color1: color("color1", 0.2)?,
                to_uv,
            }
        }
        "mesh_attribute" => {
            let Some(name) = t.string("name")? else {
                return Err(t.error("expected the attribute's \"name\""));
            };
            TextureNode::MeshAttribute { name: name.into() }
        }
        p => {
            return Err(t.error(format!(
                "unsupported texture plugin \"{p}\" (supported: bitmap, checkerboard, \
                 mesh_attribute, rawconstant)"
            )))
        }
    };
    t.finish()?;
    Ok(node)
}
