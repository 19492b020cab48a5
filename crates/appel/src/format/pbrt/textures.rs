//! pbrt's textures and texture-valued parameters onto Appel's: constants, `imagemap` (as a
//! bitmap), `checkerboard` of two constants, and `scale` and `mix` where they reduce to one of
//! these. Anything else is an error at the `Texture` directive.

use super::convert::Converter;
use super::params::{Param, ParamSet, ParamType};
use super::parser::Directive;
use super::spectrum::{rgb_of, Use};
use crate::description::{TextureDesc, TextureFilter, TextureNode, TextureWrap};
use crate::error::Result;

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Float,
    Spectrum,
}

impl Converter {
    /// A spectrum-valued material parameter: a constant colour, or a named spectrum texture.
    pub(super) fn spectrum_tex(
        &self,
        p: &ParamSet,
        name: &str,
        default: f32,
    ) -> Result<TextureDesc> {
        Ok(self
            .tex_param(p, name, Kind::Spectrum)?
            .unwrap_or(TextureDesc::Value(default)))
    }

    /// A float-valued material parameter: a number, or a named float texture.
    pub(super) fn float_tex(&self, p: &ParamSet, name: &str, default: f32) -> Result<TextureDesc> {
        Ok(self
            .tex_param(p, name, Kind::Float)?
            .unwrap_or(TextureDesc::Value(default)))
    }

    fn tex_param(&self, p: &ParamSet, name: &str, kind: Kind) -> Result<Option<TextureDesc>> {
        let types: &[ParamType] = match kind {
            Kind::Float => &[ParamType::Float, ParamType::Texture],
            Kind::Spectrum => &[
                ParamType::Rgb,
                ParamType::Spectrum,
                ParamType::Blackbody,
                ParamType::Float,
                ParamType::Texture,
            ],
        };
        let Some(q) = p.any_of(name, types)? else {
            return Ok(None);
        };
        Ok(Some(self.texture_value(q, kind)?))
    }

    fn texture_value(&self, q: &Param, kind: Kind) -> Result<TextureDesc> {
        match q.ty {
            ParamType::Float => {
                let v = q.numbers();
                if v.len() != 1 {
                    return Err(q.error(format!("\"float {}\" takes one number", q.name)));
                }
                Ok(TextureDesc::Value(v[0] as f32))
            }
            ParamType::Texture => {
                let [t] = q.strings() else {
                    return Err(q.error("a texture parameter names one texture"));
                };
                let table = match kind {
                    Kind::Float => &self.float_textures,
                    Kind::Spectrum => &self.spectrum_textures,
                };
                table.get(t).cloned().ok_or_else(|| {
                    q.error(format!(
                        "no {} texture named \"{t}\" has been declared",
                        match kind {
                            Kind::Float => "float",
                            Kind::Spectrum => "spectrum",
                        }
                    ))
                })
            }
            _ => Ok(TextureDesc::Rgb(rgb_of(q, Use::Albedo, &self.base_dir)?)),
        }
    }

    /// `Texture "name" "float"|"spectrum" "class" ...`.
    pub(super) fn texture(&mut self, d: &Directive) -> Result<()> {
        let (name, ty, class) = (&d.strings[0], &d.strings[1], &d.strings[2]);
        let kind = match ty.as_str() {
            "float" => Kind::Float,
            "spectrum" | "color" => Kind::Spectrum,
            other => {
                return Err(d.loc.error(format!(
                    "a texture is \"float\" or \"spectrum\", not \"{other}\""
                )))
            }
        };
        let p = &d.params;
        let default = |v: f32| TextureDesc::Value(v);
        let t = match class.as_str() {
            "constant" => self.tex_param(p, "value", kind)?.unwrap_or(default(1.0)),
            "imagemap" => self.imagemap(d)?,
            "checkerboard" => {
                if p.int("dimension")?.unwrap_or(2) != 2 {
                    return Err(d.loc.error("3D checkerboards are not supported"));
                }
                let t1 = self.tex_param(p, "tex1", kind)?.unwrap_or(default(1.0));
                let t2 = self.tex_param(p, "tex2", kind)?.unwrap_or(default(0.0));
                let (Some(c1), Some(c2)) = (constant(&t1), constant(&t2)) else {
                    return Err(d.loc.error(
                        "a checkerboard of textures is not supported: give tex1 and tex2 as \
                         constants",
                    ));
                };
                let to_uv = self.uv_mapping(d, CHECKER)?;
                // pbrt paints tex1 where floor(s) + floor(t) is even. Appel's checkerboard
                // (Mitsuba's) alternates at halves: with (s, t) / 2 as its uv, its `color0`
                // squares are pbrt's tex1 squares for colours, and (as Mitsuba's float query
                // picks the other squares) its `color1` squares for floats.
                let (color0, color1) = match kind {
                    Kind::Spectrum => (c1, c2),
                    Kind::Float => (c2, c1),
                };
                TextureDesc::Texture(TextureNode::Checkerboard {
                    color0,
                    color1,
                    to_uv: Some(to_uv),
                })
            }
            "scale" => {
                let t = self.tex_param(p, "tex", kind)?.unwrap_or(default(1.0));
                let s = self
                    .tex_param(p, "scale", Kind::Float)?
                    .unwrap_or(default(1.0));
                match (constant(&t), constant(&s)) {
                    (_, Some(s)) if s == [1.0; 3] => t,
                    (Some(t1), _) if t1 == [1.0; 3] => s,
                    (Some(a), Some(b)) => rgb(std::array::from_fn(|i| a[i] * b[i])),
                    (None, Some(s)) => scaled(&t, s).ok_or_else(|| {
                        d.loc.error(
                            "a scaled image texture is not supported (Appel's bitmaps have no \
                             scale); scale the image itself",
                        )
                    })?,
                    (_, None) => return Err(d.loc.error("a scale by a texture is not supported")),
                }
            }
            "mix" => {
                let t1 = self.tex_param(p, "tex1", kind)?.unwrap_or(default(0.0));
                let t2 = self.tex_param(p, "tex2", kind)?.unwrap_or(default(1.0));
                let amount = self
                    .tex_param(p, "amount", Kind::Float)?
                    .unwrap_or(default(0.5));
                let Some(a) = constant(&amount).map(|a| a[0]) else {
                    return Err(d.loc.error("a mix by a varying amount is not supported"));
                };
                match (constant(&t1), constant(&t2)) {
                    _ if a == 0.0 => t1,
                    _ if a == 1.0 => t2,
                    (Some(x), Some(y)) => rgb(std::array::from_fn(|i| (1.0 - a) * x[i] + a * y[i])),
                    _ => {
                        return Err(d
                            .loc
                            .error("a mix of textures is not supported unless both are constants"))
                    }
                }
            }
            other => {
                return Err(d.loc.error(format!(
                    "unsupported texture \"{other}\" (supported: constant, imagemap, \
                     checkerboard, scale, mix)"
                )))
            }
        };
        let table = match kind {
            Kind::Float => &mut self.float_textures,
            Kind::Spectrum => &mut self.spectrum_textures,
        };
        table.insert(name.clone(), t);
        Ok(())
    }

    fn imagemap(&mut self, d: &Directive) -> Result<TextureDesc> {
        let p = &d.params;
        let file = p
            .string("filename")?
            .ok_or_else(|| d.loc.error("an imagemap needs \"string filename\""))?;
        let path = self.base_dir.join(file);
        if !path.is_file() {
            return Err(d.loc.error(format!(
                "the image \"{file}\" is missing (looked for {})",
                path.display()
            )));
        }
        let filter = match p.string("filter")?.unwrap_or("bilinear") {
            "point" => TextureFilter::Nearest,
            // pbrt's MIP-mapped filters sample the same image; Appel reads its finest level.
            "bilinear" | "trilinear" | "ewa" | "EWA" => TextureFilter::Bilinear,
            other => {
                return Err(d.loc.error(format!(
                    "unknown imagemap filter \"{other}\" (point, bilinear, trilinear, ewa)"
                )))
            }
        };
        let wrap = match p.string("wrap")?.unwrap_or("repeat") {
            "repeat" => TextureWrap::Repeat,
            "clamp" => TextureWrap::Clamp,
            other => {
                return Err(d.loc.error(format!(
                    "imagemap wrap \"{other}\" is not supported (repeat, clamp)"
                )))
            }
        };
        let raw = match p.string("encoding")? {
            None | Some("sRGB") => false,
            Some("linear") => true,
            Some(other) => {
                return Err(d.loc.error(format!(
                    "imagemap encoding \"{other}\" is not supported (sRGB, linear)"
                )))
            }
        };
        if p.float_or("scale", 1.0)? != 1.0 {
            return Err(d.loc.error(
                "an imagemap \"scale\" other than 1 is not supported; scale the image itself",
            ));
        }
        if p.bool_or("invert", false)? {
            return Err(d.loc.error("an inverted imagemap is not supported"));
        }
        p.ignore("maxanisotropy");
        let to_uv = self.uv_mapping(d, IMAGE)?;
        Ok(TextureDesc::Texture(TextureNode::Bitmap {
            file: path.to_string_lossy().into_owned(),
            filter,
            wrap,
            raw,
            to_uv: Some(to_uv),
        }))
    }

    /// pbrt's `uv` mapping `(s, t) = (su u + du, sv v + dv)`, then what the texture does with
    /// (s, t), as the 3x3 matrix on (u, v, 1) that Appel's textures apply first.
    fn uv_mapping(&self, d: &Directive, then: [[f64; 3]; 2]) -> Result<[[f32; 3]; 3]> {
        let p = &d.params;
        if let Some(m) = p.string("mapping")? {
            if m != "uv" {
                return Err(d.loc.error(format!(
                    "texture mapping \"{m}\" is not supported (uv only)"
                )));
            }
        }
        let su = p.float_or("uscale", 1.0)?;
        let sv = p.float_or("vscale", 1.0)?;
        let du = p.float_or("udelta", 0.0)?;
        let dv = p.float_or("vdelta", 0.0)?;
        let [[a, b, c], [e, f, g]] = then;
        // (x, y) = then * (s, t, 1) with s = su u + du, t = sv v + dv.
        Ok([
            [
                (a * su) as f32,
                (b * sv) as f32,
                (a * du + b * dv + c) as f32,
            ],
            [
                (e * su) as f32,
                (f * sv) as f32,
                (e * du + f * dv + g) as f32,
            ],
            [0.0, 0.0, 1.0],
        ])
    }
}

/// Checkerboard: Appel's squares are half as large as pbrt's.
const CHECKER: [[f64; 3]; 2] = [[0.5, 0.0, 0.0], [0.0, 0.5, 0.0]];
/// Images: pbrt looks up (s, 1 - t) with the first row at the top; Appel's uv (0, 0) is the
/// top-left corner.
const IMAGE: [[f64; 3]; 2] = [[1.0, 0.0, 0.0], [0.0, -1.0, 1.0]];

fn constant(t: &TextureDesc) -> Option<[f32; 3]> {
    match t {
        TextureDesc::Value(v) => Some([*v; 3]),
        TextureDesc::Rgb(c) => Some(*c),
        TextureDesc::Texture(_) => None,
    }
}

fn rgb(c: [f32; 3]) -> TextureDesc {
    if c[0] == c[1] && c[1] == c[2] {
        TextureDesc::Value(c[0])
    } else {
        TextureDesc::Rgb(c)
    }
}

/// A checkerboard of constants scaled by a constant.
fn scaled(t: &TextureDesc, s: [f32; 3]) -> Option<TextureDesc> {
    match t {
        TextureDesc::Texture(TextureNode::Checkerboard {
            color0,
            color1,
            to_uv,
        }) => Some(TextureDesc::Texture(TextureNode::Checkerboard {
            color0: std::array::from_fn(|i| color0[i] * s[i]),
            color1: std::array::from_fn(|i| color1[i] * s[i]),
            to_uv: *to_uv,
        })),
        _ => None,
    }
}
