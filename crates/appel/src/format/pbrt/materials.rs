//! pbrt-v4's materials onto Appel's BSDFs (Mitsuba's models). pbrt's BSDFs scatter on both sides
//! of a surface, Mitsuba's opaque ones on the front only: every opaque material is wrapped in
//! `twosided`. docs/pbrt.md says how each maps and where it is an approximation.

use super::convert::Converter;
use super::params::{ParamSet, ParamType};
use super::parser::Directive;
use super::spectrum::{rgb_of, Use};
use super::tokenizer::Loc;
use crate::description::{
    BlendDesc, ConductorDesc, DielectricDesc, DiffuseDesc, DistributionDesc, IorDesc, MaterialDesc,
    PlasticDesc, RoughConductorDesc, RoughDielectricDesc, RoughPlasticDesc, TextureDesc,
    TwoSidedDesc,
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
                    MaterialDesc::ThinDielectric(dielectric(eta))
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
            "coatedconductor" => {
                // The metal seen through the coating: its index relative to the coating's.
                let eta = self.eta(p, "interface.eta")?;
                let (au, av) = self.roughness(p, "interface.")?;
                if au.max(av) >= SMOOTH_ALPHA {
                    let at = p
                        .get("interface.roughness")
                        .or_else(|| p.get("interface.uroughness"))
                        .map_or(loc, |q| &q.loc);
                    return Err(at.error(
                        "a coatedconductor with a rough coating is not supported (Appel maps a \
                         smooth coating onto the conductor; see docs/pbrt.md)",
                    ));
                }
                for layered in ["thickness", "albedo", "g", "maxdepth", "nsamples"] {
                    p.ignore(layered);
                }
                let metal = self.conductor(p, "conductor.")?;
                (relative_to_coating(metal, eta as f32), false)
            }
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

    /// pbrt's conductor (or a coated conductor's, with `prefix` "conductor."): `eta` and `k`, or
    /// a `reflectance` (not supported), and its roughness.
    fn conductor(&mut self, p: &ParamSet, prefix: &str) -> Result<MaterialDesc> {
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
        let eta = spectrum(self, "eta", "eta")?;
        let k = spectrum(self, "k", "k")?;
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

    /// pbrt's coateddiffuse: a diffuse base under a dielectric coating, as Mitsuba's (rough)
    /// plastic. The coating is taken as infinitely thin and clear (`thickness`, `albedo` and
    /// `g` of pbrt's layer medium are not modelled); Mitsuba's `nonlinear` accounts for light
    /// reflected back and forth under the coating, as pbrt's random walk does.
    fn coated_diffuse(&mut self, p: &ParamSet) -> Result<MaterialDesc> {
        let reflectance = self.spectrum_tex(p, "reflectance", 0.5)?;
        let eta = self.eta(p, "eta")?;
        if let Some(q) = p.any_of(
            "albedo",
            &[
                ParamType::Float,
                ParamType::Rgb,
                ParamType::Spectrum,
                ParamType::Texture,
            ],
        )? {
            let zero = matches!(q.ty, ParamType::Float | ParamType::Rgb)
                && q.numbers().iter().all(|x| *x == 0.0);
            if !zero {
                return Err(q.error(
                    "a coateddiffuse whose coating scatters (\"albedo\" > 0) is not supported",
                ));
            }
        }
        for layered in ["thickness", "g", "maxdepth", "nsamples"] {
            p.ignore(layered);
        }
        let (au, av) = self.roughness(p, "")?;
        Ok(if au.max(av) < SMOOTH_ALPHA {
            MaterialDesc::Plastic(PlasticDesc {
                int_ior: IorDesc::Value(eta as f32),
                ext_ior: IorDesc::Value(1.0),
                diffuse_reflectance: reflectance,
                specular_reflectance: TextureDesc::Value(1.0),
                nonlinear: true,
            })
        } else {
            let (alpha, alpha_u, _) = alphas(au, av);
            if alpha_u.is_some() {
                return Err(p.get("uroughness").expect("anisotropic").error(
                    "an anisotropic coateddiffuse is not supported (Appel's rough plastic is \
                     isotropic)",
                ));
            }
            MaterialDesc::RoughPlastic(RoughPlasticDesc {
                int_ior: IorDesc::Value(eta as f32),
                ext_ior: IorDesc::Value(1.0),
                diffuse_reflectance: reflectance,
                specular_reflectance: TextureDesc::Value(1.0),
                nonlinear: true,
                distribution: DistributionDesc::Ggx,
                alpha,
                alpha_u: None,
                alpha_v: None,
                sample_visible: true,
            })
        })
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

/// A conductor's index divided by the coating's: what the metal's Fresnel sees under it.
fn relative_to_coating(m: MaterialDesc, eta: f32) -> MaterialDesc {
    let rel = |v: Option<[f32; 3]>| v.map(|v| v.map(|x| x / eta));
    match m {
        MaterialDesc::Conductor(mut c) => {
            c.eta = rel(c.eta);
            c.k = rel(c.k);
            MaterialDesc::Conductor(c)
        }
        MaterialDesc::RoughConductor(mut c) => {
            c.eta = rel(c.eta);
            c.k = rel(c.k);
            MaterialDesc::RoughConductor(c)
        }
        other => other,
    }
}
