//! The Monte Carlo integrators' materials, one per entry of the scene's (Whitted) material list and
//! in the same order: described materials as written, Whitted's (the default, mesh files' MTL and
//! glTF materials, `type = "whitted"`) by their physically based equivalent.

use super::textures::TextureCache;
use super::Material as WhittedMaterial;
use crate::description::{Description, MaterialDesc};
use crate::error::{Error, Result};
use crate::shading::bsdf::{ConductorMaterial, DielectricMaterial, DiffuseMaterial};
use crate::shading::material::Material;
use crate::shading::texture::{Checkerboard, Texture};
use glam::{Mat3, Vec2, Vec3};

/// `from_files` are mesh files' physically based materials, by index; the other entries past the
/// described ones are read from their Whitted view.
pub fn build(
    d: &Description,
    whitted: &[WhittedMaterial],
    from_files: &[(u32, Material)],
    textures: &mut TextureCache,
) -> Result<Vec<Material>> {
    let names: Vec<&String> = d.materials.keys().collect();
    let index = |name: &str| {
        names
            .iter()
            .position(|n| n.as_str() == name)
            .map_or(0, |i| i as u32 + 1)
    };
    let mut out = Vec::with_capacity(whitted.len());
    out.push(from_whitted(&whitted[0]));
    for (name, m) in &d.materials {
        out.push(
            from_description(m, &index, textures)
                .map_err(|e| Error::Invalid(format!("material `{name}`: {e}")))?,
        );
    }
    out.extend(whitted[out.len()..].iter().map(from_whitted));
    for (i, m) in from_files {
        out[*i as usize] = m.clone();
    }
    Ok(out)
}

fn from_description(
    m: &MaterialDesc,
    index: &dyn Fn(&str) -> u32,
    textures: &mut TextureCache,
) -> Result<Material> {
    if let Some(bsdf) = Material::from_bsdf_desc(m, textures) {
        return bsdf;
    }
    Ok(match m {
        MaterialDesc::Whitted(w) => from_whitted(&WhittedMaterial::new(w)),
        MaterialDesc::TwoSided(t) => Material::TwoSided {
            front: index(&t.front),
            back: index(t.back.as_deref().unwrap_or(&t.front)),
        },
        MaterialDesc::Mask(x) => Material::Mask {
            opacity: textures.texture(&x.opacity)?,
            inner: index(&x.material),
        },
        MaterialDesc::NormalMap(x) => Material::NormalMap {
            normals: textures.texture(&x.normalmap)?,
            inner: index(&x.material),
            flip_invalid: x.flip_invalid_normals,
            shadowing: x.use_shadowing_function,
        },
        MaterialDesc::Blend(x) => Material::Blend {
            weight: textures.texture(&x.weight)?,
            first: index(&x.materials[0]),
            second: index(&x.materials[1]),
        },
        MaterialDesc::BumpMap(x) => Material::BumpMap {
            height: textures.texture(&x.bumpmap)?,
            scale: x.scale,
            inner: index(&x.material),
            flip_invalid: x.flip_invalid_normals,
            shadowing: x.use_shadowing_function,
        },
        // Every BSDF of the registry was built above.
        _ => unreachable!("`{m:?}` is a BSDF"),
    })
}

/// Whitted's model by its nearest physically based material: a transparent one as glass of its
/// index, a mostly reflecting one as a mirror of its reflection coefficient, anything else as
/// Lambertian of its diffuse colour (checkerboards included).
fn from_whitted(w: &WhittedMaterial) -> Material {
    if w.transmission > 0.0 {
        return Material::Dielectric(DielectricMaterial {
            eta: w.ior,
            reflectance: Texture::Constant(Vec3::ONE),
            transmittance: Texture::Constant(Vec3::splat(w.transmission.min(1.0))),
        });
    }
    if w.reflection >= 0.5 {
        return Material::Conductor(ConductorMaterial {
            eta: Vec3::ZERO,
            k: Vec3::ONE,
            specular: Texture::Constant(Vec3::splat(w.reflection.min(1.0))),
        });
    }
    let albedo = |c: Vec3| (c * w.diffuse).clamp(Vec3::ZERO, Vec3::ONE);
    let reflectance = match w.checker {
        // Whitted's squares of side `size` alternate with the parity of floor(u/size) +
        // floor(v/size); Mitsuba's checkerboard has squares of 1/2: scale uv by 1/(2 size).
        Some(c) => Texture::Checkerboard(Checkerboard {
            color0: albedo(w.color),
            color1: albedo(c.color),
            to_uv: Mat3::from_scale(Vec2::splat(0.5 / c.size)),
        }),
        None => Texture::Constant(albedo(w.color)),
    };
    Material::Diffuse(DiffuseMaterial { reflectance })
}
