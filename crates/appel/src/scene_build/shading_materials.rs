//! The scene's materials, one per `[materials.NAME]` in name order after the default (index 0,
//! the grey `phong` material of shapes that name none); mesh files' materials follow, appended as
//! their files are read. Every integrator reads this one list: `path` and `direct` through
//! [`Material::bsdf`], `whitted` and `raycast` through [`Material::whitted`].

use super::textures::TextureCache;
use crate::description::{
    Description, DistributionDesc, IorDesc, MaterialDesc, PhongDesc, TextureDesc,
};
use crate::error::{Error, Result};
use crate::shading::bsdf::principled::specular_to_eta;
use crate::shading::bsdf::{
    Checker, MicrofacetKind, PhongParams, PlasticParams, RoughPlasticParams,
};
use crate::shading::material::{Material, PrincipledTextures, PrincipledThinTextures, Roughness};
use crate::shading::spectra;
use crate::shading::texture::Texture;
use glam::Vec3;

/// Mitsuba's default roughness.
const DEFAULT_ALPHA: f32 = 0.1;

/// The default material, then the described ones.
pub fn build(d: &Description, textures: &mut TextureCache) -> Result<Vec<Material>> {
    let names: Vec<&String> = d.materials.keys().collect();
    let index = |name: &str| {
        names
            .iter()
            .position(|n| n.as_str() == name)
            .map_or(0, |i| i as u32 + 1)
    };
    let mut out = Vec::with_capacity(d.materials.len() + 1);
    out.push(Material::Phong(phong(&PhongDesc::default())));
    for (name, m) in &d.materials {
        out.push(
            from_description(m, &index, textures)
                .map_err(|e| Error::Invalid(format!("material `{name}`: {e}")))?,
        );
    }
    Ok(out)
}

/// A `phong` material's parameters as written.
pub fn phong(d: &PhongDesc) -> PhongParams {
    PhongParams {
        color: d.color.into(),
        checker: d.checker.as_ref().map(|c| Checker {
            color: c.color.into(),
            size: c.size,
        }),
        ambient: d.ambient,
        diffuse: d.diffuse,
        specular: d.specular,
        shininess: d.shininess,
        reflection: d.reflection,
        transmission: d.transmission,
        ior: d.ior,
        fresnel: d.fresnel,
    }
}

fn from_description(
    m: &MaterialDesc,
    index: &dyn Fn(&str) -> u32,
    textures: &mut TextureCache,
) -> Result<Material> {
    let mut tex = |t: &TextureDesc| textures.texture(t);
    Ok(match m {
        MaterialDesc::Phong(w) => Material::Phong(phong(w)),
        MaterialDesc::Diffuse(x) => Material::Diffuse {
            reflectance: tex(&x.reflectance)?,
        },
        MaterialDesc::Conductor(x) => {
            let (eta, k) = conductor(x.material.as_deref(), x.eta, x.k)?;
            Material::Conductor {
                eta,
                k,
                specular: tex(&x.specular_reflectance)?,
            }
        }
        MaterialDesc::RoughConductor(x) => {
            let (eta, k) = conductor(x.material.as_deref(), x.eta, x.k)?;
            Material::RoughConductor {
                roughness: Roughness {
                    kind: kind(x.distribution),
                    alpha_u: tex(x.alpha_u.as_ref().or(x.alpha.as_ref()).unwrap_or(&alpha0()))?,
                    alpha_v: tex(x.alpha_v.as_ref().or(x.alpha.as_ref()).unwrap_or(&alpha0()))?,
                    sample_visible: x.sample_visible,
                },
                eta,
                k,
                specular: tex(&x.specular_reflectance)?,
            }
        }
        MaterialDesc::Dielectric(x) => Material::Dielectric {
            eta: ior(&x.int_ior)? / ior(&x.ext_ior)?,
            reflectance: tex(&x.specular_reflectance)?,
            transmittance: tex(&x.specular_transmittance)?,
        },
        MaterialDesc::ThinDielectric(x) => Material::ThinDielectric {
            eta: ior(&x.int_ior)? / ior(&x.ext_ior)?,
            reflectance: tex(&x.specular_reflectance)?,
            transmittance: tex(&x.specular_transmittance)?,
        },
        MaterialDesc::RoughDielectric(x) => Material::RoughDielectric {
            roughness: Roughness {
                kind: kind(x.distribution),
                alpha_u: tex(x.alpha_u.as_ref().or(x.alpha.as_ref()).unwrap_or(&alpha0()))?,
                alpha_v: tex(x.alpha_v.as_ref().or(x.alpha.as_ref()).unwrap_or(&alpha0()))?,
                sample_visible: x.sample_visible,
            },
            eta: ior(&x.int_ior)? / ior(&x.ext_ior)?,
            reflectance: tex(&x.specular_reflectance)?,
            transmittance: tex(&x.specular_transmittance)?,
        },
        MaterialDesc::Plastic(x) => {
            let (diffuse, specular) = (tex(&x.diffuse_reflectance)?, tex(&x.specular_reflectance)?);
            Material::Plastic {
                params: PlasticParams::precompute(
                    ior(&x.int_ior)? / ior(&x.ext_ior)?,
                    x.nonlinear,
                    mean(&diffuse),
                    mean(&specular),
                ),
                diffuse,
                specular,
            }
        }
        MaterialDesc::RoughPlastic(x) => {
            let (diffuse, specular) = (tex(&x.diffuse_reflectance)?, tex(&x.specular_reflectance)?);
            // The coating's precomputed albedo depends on the roughness: it must be a constant
            // (as Mitsuba requires).
            let alpha = match x.alpha.as_ref().or(x.alpha_u.as_ref()) {
                None => DEFAULT_ALPHA,
                Some(TextureDesc::Value(a)) => *a,
                Some(_) => {
                    return Err(Error::Invalid(
                        "a rough plastic's `alpha` must be a number: its coating's albedo is \
                         precomputed for one roughness"
                            .into(),
                    ))
                }
            };
            let distribution = crate::shading::bsdf::Microfacet::new(
                kind(x.distribution),
                alpha,
                alpha,
                x.sample_visible,
            );
            Material::RoughPlastic {
                params: RoughPlasticParams::precompute(
                    distribution,
                    ior(&x.int_ior)? / ior(&x.ext_ior)?,
                    x.nonlinear,
                    mean(&diffuse),
                    mean(&specular),
                ),
                diffuse,
                specular,
            }
        }
        MaterialDesc::Principled(x) => {
            // Mitsuba's constructor: a transmitting material (spec_trans given and not a zero
            // number) never gets eta exactly 1 (no refraction) or specular 0 (the same).
            let transmits = x.spec_trans != TextureDesc::Value(0.0);
            let eta = match (x.eta, x.specular) {
                (Some(eta), _) if transmits && eta == 1.0 => 1.001,
                (Some(eta), _) => eta,
                (None, s) => {
                    let s = s.unwrap_or(0.5);
                    specular_to_eta(if transmits && s == 0.0 { 1e-3 } else { s })
                }
            };
            Material::Principled(Box::new(PrincipledTextures {
                base_color: tex(&x.base_color)?,
                roughness: tex(&x.roughness)?,
                anisotropic: tex(&x.anisotropic)?,
                metallic: tex(&x.metallic)?,
                spec_trans: tex(&x.spec_trans)?,
                spec_tint: tex(&x.spec_tint)?,
                sheen: tex(&x.sheen)?,
                sheen_tint: tex(&x.sheen_tint)?,
                flatness: tex(&x.flatness)?,
                clearcoat: tex(&x.clearcoat)?,
                clearcoat_gloss: tex(&x.clearcoat_gloss)?,
                eta,
                rates: [
                    x.diffuse_reflectance_sampling_rate,
                    x.main_specular_sampling_rate,
                    x.clearcoat_sampling_rate,
                ],
            }))
        }
        MaterialDesc::PrincipledThin(x) => {
            Material::PrincipledThin(Box::new(PrincipledThinTextures {
                base_color: tex(&x.base_color)?,
                roughness: tex(&x.roughness)?,
                anisotropic: tex(&x.anisotropic)?,
                spec_trans: tex(&x.spec_trans)?,
                spec_tint: tex(&x.spec_tint)?,
                sheen: tex(&x.sheen)?,
                sheen_tint: tex(&x.sheen_tint)?,
                flatness: tex(&x.flatness)?,
                diff_trans: tex(&x.diff_trans)?,
                eta: tex(&x.eta)?,
                rates: [
                    x.specular_reflectance_sampling_rate,
                    x.specular_transmittance_sampling_rate,
                    x.diffuse_reflectance_sampling_rate,
                    x.diffuse_transmittance_sampling_rate,
                ],
            }))
        }
        MaterialDesc::TwoSided(t) => Material::TwoSided {
            front: index(&t.front),
            back: index(t.back.as_deref().unwrap_or(&t.front)),
        },
        MaterialDesc::Mask(x) => Material::Mask {
            opacity: tex(&x.opacity)?,
            inner: index(&x.material),
        },
        MaterialDesc::NormalMap(x) => Material::NormalMap {
            normals: tex(&x.normalmap)?,
            inner: index(&x.material),
            flip_invalid: x.flip_invalid_normals,
            shadowing: x.use_shadowing_function,
        },
        MaterialDesc::Blend(x) => Material::Blend {
            weight: tex(&x.weight)?,
            first: index(&x.materials[0]),
            second: index(&x.materials[1]),
        },
        MaterialDesc::BumpMap(x) => Material::BumpMap {
            height: tex(&x.bumpmap)?,
            scale: x.scale,
            inner: index(&x.material),
            flip_invalid: x.flip_invalid_normals,
            shadowing: x.use_shadowing_function,
        },
    })
}

fn ior(i: &IorDesc) -> Result<f32> {
    match i {
        IorDesc::Value(v) if v.is_finite() && *v > 0.0 => Ok(*v),
        IorDesc::Value(v) => Err(Error::Invalid(format!(
            "an index of refraction must be positive, got {v}"
        ))),
        IorDesc::Named(n) => spectra::ior(n).ok_or_else(|| {
            Error::Invalid(format!(
                "unknown index of refraction `{n}`, expected a number or one of: {}",
                spectra::IOR_NAMES.join(", ")
            ))
        }),
    }
}

fn conductor(
    material: Option<&str>,
    eta: Option<[f32; 3]>,
    k: Option<[f32; 3]>,
) -> Result<(Vec3, Vec3)> {
    if let (Some(eta), Some(k)) = (eta, k) {
        return Ok((eta.into(), k.into()));
    }
    let name = material.unwrap_or(spectra::NO_CONDUCTOR);
    let (e, kk) = spectra::conductor(name).ok_or_else(|| {
        Error::Invalid(format!(
            "unknown conductor `{name}`, expected one of: {}",
            spectra::CONDUCTOR_NAMES.join(", ")
        ))
    })?;
    Ok((eta.map_or(e, Vec3::from), k.map_or(kk, Vec3::from)))
}

fn kind(d: DistributionDesc) -> MicrofacetKind {
    match d {
        DistributionDesc::Beckmann => MicrofacetKind::Beckmann,
        DistributionDesc::Ggx => MicrofacetKind::Ggx,
    }
}

fn alpha0() -> TextureDesc {
    TextureDesc::Value(DEFAULT_ALPHA)
}

/// The channel mean of a texture's mean, as Mitsuba's `Texture::mean` for lobe weights.
fn mean(t: &Texture) -> f32 {
    let m = t.mean();
    (m.x + m.y + m.z) / 3.0
}
