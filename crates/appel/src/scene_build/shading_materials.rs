//! The scene's materials, one per `[materials.NAME]` in name order after the default (index 0,
//! the grey `phong` material of shapes that name none); mesh files' materials follow, appended as
//! their files are read. Every integrator reads this one list: `path` and `direct` through
//! [`Material::bsdf`], `whitted` and `raycast` through [`Material::whitted`].

use super::textures::TextureCache;
use crate::description::{Description, MaterialDesc, PhongDesc};
use crate::error::{Error, Result};
use crate::shading::bsdf::PhongParams;
use crate::shading::material::Material;

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
    out.push(Material::Phong(PhongParams::from_desc(
        &PhongDesc::default(),
    )));
    for (name, m) in &d.materials {
        out.push(
            from_description(m, &index, textures)
                .map_err(|e| Error::Invalid(format!("material `{name}`: {e}")))?,
        );
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
