//! pbrt-v4's materials onto Appel's BSDFs (Mitsuba's models). pbrt's BSDFs scatter on both sides
//! of a surface, Mitsuba's opaque ones on the front only: every opaque material is wrapped in
//! `twosided`. docs/pbrt.md says how each maps and where it is an approximation; the coated
//! materials are pbrt-v4's own stochastic layered BSDFs.

use super::convert::Converter;
use super::params::{ParamSet, ParamType};
use super::parser::Directive;
use super::spectrum::{rgb_of, Use};
use super::tokenizer::Loc;
use crate::description::{
    BlendDesc, CoatedConductorDesc, CoatedDiffuseDesc, ConductorDesc, DielectricDesc, DiffuseDesc,
    DistributionDesc, IorDesc, MaterialDesc, RoughConductorDesc, RoughDielectricDesc, TextureDesc,
    ThinDielectricDesc, TwoSidedDesc,
};
use crate::error::Result;

/// A pbrt material as the description holds it.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Converted {
    Surface {
        /// What shapes use (the `twosided` wrapper of an opaque BSDF).
        name: String,
        /// The BSDF itself, for `mix`.
        plain: String,
        transmissive: bool,
    },
    /// `interface`: no surface, only the boundary of a medium.
    Interface,
}

/// pbrt-v4 treats a microfacet distribution this smooth as a perfect specular one.
const SMOOTH_ALPHA: f64 = 1e-3;

impl Converter {
    pub(super) fn make_named_material(&mut self, d: &Directive) -> Result<()> {
        let name = &d.strings[0];
        let p = &d.params;
        let kind = p
            .string("type")?
            .ok_or_else(|| d.loc.error("MakeNamedMaterial needs \"string type\""))?
            .to_string();
        if self.named_materials.contains_key(name) {
            return Err(d.loc.error(format!("material \"{name}\" is made twice")));
        }
        let m = self.material(&kind, p, &d.loc, name)?;
        self.named_materials.insert(name.clone(), m);
        Ok(())
    }

    /// Converts a material of pbrt type `kind`, naming it `name` in the description.
    pub(super) fn material(
        &mut self,
        kind: &str,
        p: &ParamSet,
        loc: &Loc,
        name: &str,
    ) -> Result<Converted> {
        for unsupported in ["displacement", "normalmap"] {
            if let Some(q) = p.get(unsupported) {
                return Err(q.error(format!(
                    "the material parameter \"{unsupported}\" is not supported"
                )));
            }
        }
        let (bsdf, transmissive) = match kind {
            "interface" => return Ok(Converted::Interface),
            "mix" => return self.mix(p, loc, name),
            "diffuse" => (
                MaterialDesc::Diffuse(DiffuseDesc {
                    reflectance: self.spectrum_tex(p, "reflectance", 0.5)?,
                }),
                false,
            ),
            "conductor" => (self.conductor(p, "")?, false),
            "dielectric" | "thindielectric" => {
                let eta = self.eta(p, "eta")?;
                let (au, av) = self.roughness(p, "")?;
                let d = if kind == "thindielectric" {
                    MaterialDesc::ThinDielectric(thin_dielectric(eta))
                } else if au.max(av) < SMOOTH_ALPHA {
                    MaterialDesc::Dielectric(dielectric(eta))
                } else {
                    let (alpha, alpha_u, alpha_v) = alphas(au, av);
                    MaterialDesc::RoughDielectric(RoughDielectricDesc {
                        int_ior: IorDesc::Value(eta as f32),
                        ext_ior: IorDesc::Value(1.0),
                        specular_reflectance: TextureDesc::Value(1.0),
                        specular_transmittance: TextureDesc::Value(1.0),
                        distribution: DistributionDesc::Ggx,
                        alpha,
                        alpha_u,
                        alpha_v,
                        sample_visible: true,
                    })
                };
                (d, true)
            }
            "coateddiffuse" => (self.coated_diffuse(p)?, false),
            "coatedconductor" => (self.coated_conductor(p)?, false),
            other => {
                return Err(loc.error(format!(
                    "unsupported material \"{other}\" (supported: diffuse, conductor, \
                     dielectric, thindielectric, coateddiffuse, coatedconductor, mix, interface)"
                )))
            }
        };
        let plain = if transmissive {
            name.to_string()
        } else {
            format!("{name}.bsdf")
        };
        self.materials.insert(plain.clone(), bsdf);
        if !transmissive {
            self.materials.insert(
                name.to_string(),
                MaterialDesc::TwoSided(TwoSidedDesc {
                    front: plain.clone(),
                    back: None,
                }),
            );
        }
        Ok(Converted::Surface {
            name: name.to_string(),
            plain,
            transmissive,
        })
    }

    /// pbrt's conductor: its index (see [`Self::conductor_index`]) and roughness.
    fn conductor(&mut self, p: &ParamSet, prefix: &str) -> Result<MaterialDesc> {
        let ConductorIndex { eta, k } = self.conductor_index(p, prefix)?;
        let (au, av) = self.roughness(p, prefix)?;
        Ok(if au.max(av) < SMOOTH_ALPHA {
            MaterialDesc::Conductor(ConductorDesc {
                material: None,
                eta: Some(eta),
                k: Some(k),
                specular_reflectance: TextureDesc::Value(1.0),
            })
        } else {
            let (alpha, alpha_u, alpha_v) = alphas(au, av);
            MaterialDesc::RoughConductor(RoughConductorDesc {
                material: None,
                eta: Some(eta),
                k: Some(k),
                specular_reflectance: TextureDesc::Value(1.0),
                distribution: DistributionDesc::Ggx,
                alpha,
                alpha_u,
                alpha_v,
                sample_visible: true,
            })
        })
    }

    /// A conductor's (or a coated conductor's, with `prefix` "conductor.") `eta` and `k`, copper
    /// by default; given by its `reflectance` it is not supported.
    fn conductor_index(&self, p: &ParamSet, prefix: &str) -> Result<ConductorIndex> {
        if let Some(q) = p.get(&format!("{prefix}reflectance")) {
            return Err(q.error(
                "a conductor given by its \"reflectance\" is not supported: give eta and k",
            ));
        }
        let spectrum = |this: &Self, name: &str, metal_part: &str| -> Result<[f32; 3]> {
            match p.any_of(
                &format!("{prefix}{name}"),
                &[
                    ParamType::Rgb,
                    ParamType::Spectrum,
                    ParamType::Float,
                    ParamType::Texture,
                ],
            )? {
                None => {
                    // pbrt's default metal is copper.
                    let (eta, k) = crate::description::spectra::conductor("Cu").expect("known");
                    let v = if metal_part == "eta" { eta } else { k };
                    Ok([v.x, v.y, v.z])
                }
                Some(q) if q.ty == ParamType::Float => Ok([q.numbers()[0] as f32; 3]),
                Some(q) if q.ty == ParamType::Texture => {
                    Err(q.error("a textured conductor index is not supported: give a constant"))
                }
                Some(q) => rgb_of(q, Use::Unbounded, &this.base_dir),
            }
        };
        Ok(ConductorIndex {
            eta: spectrum(self, "eta", "eta")?,
            k: spectrum(self, "k", "k")?,
        })
    }

    /// pbrt-v4's coateddiffuse, parameter for parameter: a diffuse base under a dielectric
    /// coating, evaluated stochastically as pbrt-v4's `LayeredBxDF` does.
    fn coated_diffuse(&mut self, p: &ParamSet) -> Result<MaterialDesc> {
        let (au, av) = self.roughness(p, "")?;
        let (alpha, alpha_u, alpha_v) = layered_alphas(au, av);
        Ok(MaterialDesc::CoatedDiffuse(CoatedDiffuseDesc {
            reflectance: self.spectrum_tex(p, "reflectance", 0.5)?,
            alpha,
            alpha_u,
            alpha_v,
            eta: self.eta(p, "eta")? as f32,
            thickness: self.layer_float(p, "thickness", 0.01)?,
            albedo: self.spectrum_tex(p, "albedo", 0.0)?,
            g: self.layer_float(p, "g", 0.0)?,
            maxdepth: layer_int(p, "maxdepth", 10)?,
            nsamples: layer_int(p, "nsamples", 1)?,
        }))
    }

    /// pbrt-v4's coatedconductor, parameter for parameter (`interface.X` and `conductor.X`).
    fn coated_conductor(&mut self, p: &ParamSet) -> Result<MaterialDesc> {
        let ConductorIndex { eta, k } = self.conductor_index(p, "conductor.")?;
        let (iu, iv) = self.roughness(p, "interface.")?;
        let (interface_alpha, interface_alpha_u, interface_alpha_v) = layered_alphas(iu, iv);
        let (cu, cv) = self.roughness(p, "conductor.")?;
        let (conductor_alpha, conductor_alpha_u, conductor_alpha_v) = layered_alphas(cu, cv);
        Ok(MaterialDesc::CoatedConductor(CoatedConductorDesc {
            interface_eta: self.eta(p, "interface.eta")? as f32,
            interface_alpha,
            interface_alpha_u,
            interface_alpha_v,
            conductor_material: "Cu".into(),
            conductor_eta: Some(eta),
            conductor_k: Some(k),
            conductor_alpha,
            conductor_alpha_u,
            conductor_alpha_v,
            thickness: self.layer_float(p, "thickness", 0.01)?,
            albedo: self.spectrum_tex(p, "albedo", 0.0)?,
            g: self.layer_float(p, "g", 0.0)?,
            maxdepth: layer_int(p, "maxdepth", 10)?,
            nsamples: layer_int(p, "nsamples", 1)?,
        }))
    }

    /// A layer's float parameter (`thickness`, `g`): a constant.
    fn layer_float(&self, p: &ParamSet, name: &str, default: f64) -> Result<f32> {
        match p.any_of(name, &[ParamType::Float, ParamType::Texture])? {
            None => Ok(default as f32),
            Some(q) if q.ty == ParamType::Float => Ok(q.numbers()[0] as f32),
            Some(q) => Err(q.error(format!(
                "a textured \"{name}\" is not supported: give a constant"
            ))),
        }
    }

    /// `mix`: one of two named materials chosen per point with probability `amount` for the
    /// second, as Mitsuba's `blendbsdf`.
    fn mix(&mut self, p: &ParamSet, loc: &Loc, name: &str) -> Result<Converted> {
        let q = p
            .array("materials", ParamType::String)?
            .ok_or_else(|| loc.error("a mix needs \"string materials\" naming two materials"))?;
        let names = q.strings();
        if names.len() != 2 {
            return Err(q.error("\"materials\" names exactly two materials"));
        }
        let mut parts = Vec::new();
        for n in names {
            match self.named_materials.get(n) {
                Some(Converted::Surface {
                    plain,
                    transmissive,
                    ..
                }) => {
                    if !self.materials[plain].references().is_empty() {
                        return Err(q.error(format!(
                            "\"{n}\" is itself a mix: a mix of mixes is not supported"
                        )));
                    }
                    parts.push((plain.clone(), *transmissive));
                }
                Some(Converted::Interface) => {
                    return Err(q.error(format!("\"{n}\" is an interface: it cannot be mixed")))
                }
                None => return Err(q.error(format!("no material named \"{n}\" has been made"))),
            }
        }
        let transmissive = parts[0].1;
        if parts[1].1 != transmissive {
            return Err(q.error(
                "a mix of a transmissive (dielectric) and an opaque material is not supported",
            ));
        }
        let weight = self.float_tex(p, "amount", 0.5)?;
        let plain = if transmissive {
            name.to_string()
        } else {
            format!("{name}.bsdf")
        };
        self.materials.insert(
            plain.clone(),
            MaterialDesc::Blend(BlendDesc {
                weight,
                materials: [parts[0].0.clone(), parts[1].0.clone()],
            }),
        );
        if !transmissive {
            self.materials.insert(
                name.to_string(),
                MaterialDesc::TwoSided(TwoSidedDesc {
                    front: plain.clone(),
                    back: None,
                }),
            );
        }
        Ok(Converted::Surface {
            name: name.to_string(),
            plain,
            transmissive,
        })
    }

    /// An index of refraction: a float, or a spectrum (pbrt's named glasses or pairs), whose
    /// colour's mean is taken (Appel's dielectrics do not disperse).
    fn eta(&self, p: &ParamSet, name: &str) -> Result<f64> {
        let eta = match p.any_of(
            name,
            &[ParamType::Float, ParamType::Spectrum, ParamType::Texture],
        )? {
            None => 1.5,
            Some(q) if q.ty == ParamType::Float => q.numbers()[0],
            Some(q) if q.ty == ParamType::Texture => {
                return Err(q.error("a textured index of refraction is not supported"))
            }
            Some(q) => {
                let rgb = rgb_of(q, Use::Unbounded, &self.base_dir)?;
                rgb.iter().map(|&x| x as f64).sum::<f64>() / 3.0
            }
        };
        if eta <= 0.0 {
            return Err(p.get(name).expect("read").error(format!(
                "the index of refraction must be positive, got {eta}"
            )));
        }
        Ok(eta)
    }

    /// pbrt's `roughness` (or `uroughness`/`vroughness`) under `prefix`, as Trowbridge-Reitz
    /// (GGX) alphas: `remaproughness` (true by default) takes the square root, pbrt-v4's
    /// `RoughnessToAlpha`.
    fn roughness(&self, p: &ParamSet, prefix: &str) -> Result<(f64, f64)> {
        let get = |n: &str| -> Result<Option<f64>> {
            let name = format!("{prefix}{n}");
            match p.any_of(&name, &[ParamType::Float, ParamType::Texture])? {
                None => Ok(None),
                Some(q) if q.ty == ParamType::Float => {
                    let v = q.numbers()[0];
                    if v < 0.0 {
                        return Err(q.error(format!("roughness must not be negative, got {v}")));
                    }
                    Ok(Some(v))
                }
                Some(q) => Err(q.error("a textured roughness is not supported: give a constant")),
            }
        };
        let r = get("roughness")?.unwrap_or(0.0);
        let u = get("uroughness")?.unwrap_or(r);
        let v = get("vroughness")?.unwrap_or(r);
        let remap = p.bool_or("remaproughness", true)?;
        let alpha = |x: f64| if remap { x.sqrt() } else { x };
        Ok((alpha(u), alpha(v)))
    }
}

fn dielectric(eta: f64) -> DielectricDesc {
    DielectricDesc {
        int_ior: IorDesc::Value(eta as f32),
        ext_ior: IorDesc::Value(1.0),
        specular_reflectance: TextureDesc::Value(1.0),
        specular_transmittance: TextureDesc::Value(1.0),
    }
}

fn thin_dielectric(eta: f64) -> ThinDielectricDesc {
    let d = dielectric(eta);
    ThinDielectricDesc {
        int_ior: d.int_ior,
        ext_ior: d.ext_ior,
        specular_reflectance: d.specular_reflectance,
        specular_transmittance: d.specular_transmittance,
    }
}

/// Isotropic `alpha`, or `alpha_u` and `alpha_v`.
fn alphas(
    au: f64,
    av: f64,
) -> (
    Option<TextureDesc>,
    Option<TextureDesc>,
    Option<TextureDesc>,
) {
    let t = |x: f64| Some(TextureDesc::Value(x.max(SMOOTH_ALPHA) as f32));
    if au == av {
        (t(au), None, None)
    } else {
        (None, t(au), t(av))
    }
}

/// A conductor's complex index of refraction, per RGB channel.
struct ConductorIndex {
    eta: [f32; 3],
    k: [f32; 3],
}

/// A layered BSDF's roughness: one `alpha` where isotropic, else `alpha_u` and `alpha_v`
/// (pbrt-v4's coatings below [`SMOOTH_ALPHA`] are smooth, as the BSDF itself decides).
fn layered_alphas(au: f64, av: f64) -> (TextureDesc, Option<TextureDesc>, Option<TextureDesc>) {
    let t = |x: f64| TextureDesc::Value(x as f32);
    if au == av {
        (t(au), None, None)
    } else {
        (t(0.0), Some(t(au)), Some(t(av)))
    }
}

/// A layer's integer parameter (`maxdepth`, `nsamples`), at least 1.
fn layer_int(p: &ParamSet, name: &str, default: u32) -> Result<u32> {
    match p.int(name)? {
        None => Ok(default),
        Some(v) if v >= 1 && v <= u32::MAX as i64 => Ok(v as u32),
        Some(v) => Err(p
            .get(name)
            .expect("read above")
            .error(format!("\"{name}\" must be at least 1, got {v}"))),
    }
}
