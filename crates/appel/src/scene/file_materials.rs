//! Mesh files' materials as Appel's (the mapping and its references are in `docs/meshes.md`).
//!
//! A glTF metallic-roughness material, or an MTL material with texture maps, becomes Mitsuba's
//! `principled` BSDF (Burley 2012), wrapped in `twosided` unless it transmits, and in `mask` where
//! it has alpha. An MTL material without maps keeps its Whitted-model reading
//! ([`super::mesh_shape::material_from_file`]). Each becomes a short run of entries in the scene's
//! material list (the wrapped materials first); `raycast` and `whitted` read them through
//! [`crate::shading::bsdf::Bsdf::whitted`] (the base colour at the point, a highlight).
//!
//! Textures are decoded once per image and decoding (sRGB or raw), in parallel. A factor that
//! multiplies a texture, and the channel a parameter reads (glTF packs roughness in G and metalness
//! in B), are baked into a derived image at load, so that lookups stay plain bitmap lookups.

use crate::description::loaded_mesh::{AlphaMode, FileMaterial, FileTexture, LoadedMesh};
use crate::error::Result;
use crate::io::bitmap_read::{decode_bitmap, Bitmap};
use crate::shading::bsdf::principled::specular_to_eta;
use crate::shading::material::{Material, PrincipledTextures};
use crate::shading::texture::{luminance, BitmapTexture, Texture};
use glam::Vec3;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

/// One file material as scene materials: `entries` in order (indices inside refer to `first + k`),
/// the last being the one its triangles use.
pub struct BuiltMaterial {
    pub entries: Vec<Material>,
    /// What the surface emits (glTF `emissiveFactor` times `emissiveTexture`), if anything.
    pub emission: Option<Texture>,
}

/// Whether `m` maps onto the principled BSDF (a glTF material, or MTL with texture maps).
pub fn is_physically_based(m: &FileMaterial) -> bool {
    m.pbr.is_some()
        || m.diffuse_map.is_some()
        || m.specular_map.is_some()
        || m.shininess_map.is_some()
        || m.opacity_map.is_some()
        || m.normal_map.is_some()
        || m.bump_map.is_some()
}

/// The decoded images of one file, by (image, raw).
pub struct Images {
    decoded: HashMap<(u32, bool), Arc<Bitmap>>,
}

impl Images {
    /// Decodes every image the physically based materials of `loaded` read (occlusion maps are
    /// not used, so not decoded). An image that could not be read was reported
    /// as a warning by the reader and is skipped; one that cannot be decoded is an error.
    pub fn decode(loaded: &LoadedMesh) -> Result<Self> {
        let mut wanted: Vec<(u32, bool)> = vec![];
        for m in loaded.materials.iter().filter(|m| is_physically_based(m)) {
            let mut want = |t: &Option<FileTexture>, raw: bool| {
                if let Some(t) = t {
                    if !wanted.contains(&(t.image, raw)) {
                        wanted.push((t.image, raw));
                    }
                }
            };
            want(&m.diffuse_map, false);
            want(&m.specular_map, false);
            want(&m.shininess_map, true);
            want(&m.opacity_map, true);
            want(&m.normal_map.as_ref().map(|n| n.0.clone()), true);
            want(&m.bump_map.as_ref().map(|b| b.0.clone()), true);
            if let Some(p) = &m.pbr {
                want(&p.metallic_roughness_map, true);
                want(&p.emissive_map, false);
                want(&p.transmission_map, true);
                want(&p.clearcoat_map, true);
                want(&p.clearcoat_roughness_map, true);
            }
        }
        let files = &loaded.images;
        type Decoded = ((u32, bool), Option<Arc<Bitmap>>);
        let decoded: Vec<Decoded> = wanted
            .par_iter()
            .map(|&(i, raw)| {
                let Some(f) = files.get(i as usize) else {
                    return Ok(((i, raw), None));
                };
                let Ok(bytes) = &f.bytes else {
                    return Ok(((i, raw), None));
                };
                let b = decode_bitmap(bytes, &f.name, raw)?;
                Ok(((i, raw), (b.width > 0 && b.height > 0).then(|| Arc::new(b))))
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            decoded: decoded
                .into_iter()
                .filter_map(|(k, b)| b.map(|b| (k, b)))
                .collect(),
        })
    }

    fn get(&self, t: &FileTexture, raw: bool) -> Option<&Arc<Bitmap>> {
        self.decoded.get(&(t.image, raw))
    }

    fn texture(&self, t: &FileTexture, bitmap: Arc<Bitmap>) -> Texture {
        Texture::Bitmap(BitmapTexture::new(bitmap, t.filter, t.wrap, t.to_uv))
    }

    /// A colour: the texture's RGB times `factor`, or `factor` without a (readable) texture.
    fn colour(&self, t: &Option<FileTexture>, factor: [f32; 3]) -> Texture {
        let f = Vec3::from(factor);
        let Some((t, b)) = t.as_ref().and_then(|t| Some((t, self.get(t, false)?))) else {
            return Texture::Constant(f);
        };
        if f == Vec3::ONE {
            // RGB(A) or grey(A) bitmaps are looked up as colours as they are (alpha ignored).
            return self.texture(t, b.clone());
        }
        let derived = derive(b, 3, |px, out| {
            let c = if px.len() <= 2 {
                Vec3::splat(px[0])
            } else {
                Vec3::new(px[0], px[1], px[2])
            };
            out.copy_from_slice(&(c * f).to_array());
        });
        self.texture(t, Arc::new(derived))
    }

    /// A scalar: `map(value)` where `value` is the texture's `channel` (0 for grey images) times
    /// `factor`; `map(factor)` without a texture.
    fn scalar(
        &self,
        t: &Option<FileTexture>,
        raw: bool,
        channel: usize,
        factor: f32,
        map: impl Fn(f32) -> f32 + Sync,
    ) -> Texture {
        let Some((t, b)) = t.as_ref().and_then(|t| Some((t, self.get(t, raw)?))) else {
            return Texture::Constant(Vec3::splat(map(factor)));
        };
        let derived = derive(b, 1, |px, out| {
            let v = if px.len() <= 2 { px[0] } else { px[channel] };
            out[0] = map(v * factor);
        });
        self.texture(t, Arc::new(derived))
    }

    /// Coverage: the image's alpha (or, without alpha, its grey value or luminance) times
    /// `factor`, thresholded at `cutoff` if given.
    fn alpha(
        &self,
        t: &FileTexture,
        raw: bool,
        factor: f32,
        cutoff: Option<f32>,
    ) -> Option<Texture> {
        let b = self.get(t, raw)?;
        let derived = derive(b, 1, |px, out| {
            let a = match px.len() {
                2 => px[1],
                4 => px[3],
                1 => px[0],
                _ => luminance(Vec3::new(px[0], px[1], px[2])),
            } * factor;
            out[0] = match cutoff {
                Some(c) => f32::from(u8::from(a >= c)),
                None => a.clamp(0.0, 1.0),
            };
        });
        Some(self.texture(t, Arc::new(derived)))
    }
}

/// A new bitmap of `channels` values per pixel computed from each pixel of `b`.
fn derive(b: &Bitmap, channels: u8, f: impl Fn(&[f32], &mut [f32]) + Sync) -> Bitmap {
    let (c_in, c_out) = (b.channels as usize, channels as usize);
    let mut data = vec![0.0; b.width as usize * b.height as usize * c_out];
    data.par_chunks_mut(c_out * 4096)
        .zip(b.data.par_chunks(c_in * 4096))
        .for_each(|(out, inp)| {
            for (o, i) in out.chunks_exact_mut(c_out).zip(inp.chunks_exact(c_in)) {
                f(i, o);
            }
        });
    Bitmap {
        width: b.width,
        height: b.height,
        channels,
        data,
    }
}

/// Blinn-Phong exponent to microfacet roughness: Walter et al. (2007) match Beckmann's alpha to
/// Phong's exponent as alpha = sqrt(2 / (n + 2)); the principled BSDF's roughness is sqrt(alpha).
fn shininess_to_roughness(n: f32) -> f32 {
    (2.0 / (n.max(0.0) + 2.0)).sqrt().sqrt()
}

/// Builds material `m` of a file whose images are `images`; `first` is where its entries will
/// start in the scene's material list.
pub fn build(m: &FileMaterial, images: &Images, first: u32) -> BuiltMaterial {
    let clamp01 = |x: f32| {
        if x.is_finite() {
            x.clamp(0.0, 1.0)
        } else {
            0.0
        }
    };
    let base_color = images.colour(&m.diffuse_map, m.diffuse.map(|c| c.max(0.0)));
    let (leaf, transmits, emission) = match &m.pbr {
        Some(p) => {
            let transmits = p.transmission > 0.0;
            let ior = if m.ior.is_finite() && m.ior >= 1.0 {
                m.ior
            } else {
                1.5
            };
            // KHR_materials_specular scales the dielectric reflectance at normal incidence,
            // F0 = ((ior - 1) / (ior + 1))^2; the principled BSDF takes F0 through its relative IOR
            // (eta), so a scaled F0 becomes the eta that gives it. A transmitting material keeps
            // its IOR, which also bends the light it refracts.
            let f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
            let scale = p.specular.max(0.0) * (p.specular_color.iter().sum::<f32>() / 3.0).max(0.0);
            let eta = if transmits || (scale - 1.0).abs() < 1e-6 {
                if transmits && ior == 1.0 {
                    1.001
                } else {
                    ior
                }
            } else {
                specular_to_eta(((f0 * scale).min(0.99)) / 0.08).max(1.0)
            };
            let leaf = Material::Principled(Box::new(PrincipledTextures {
                base_color: base_color.clone(),
                roughness: images.scalar(
                    &p.metallic_roughness_map,
                    true,
                    1,
                    clamp01(p.roughness),
                    clamp01,
                ),
                anisotropic: Texture::Constant(Vec3::ZERO),
                metallic: images.scalar(
                    &p.metallic_roughness_map,
                    true,
                    2,
                    clamp01(p.metallic),
                    clamp01,
                ),
                spec_trans: images.scalar(
                    &p.transmission_map,
                    true,
                    0,
                    clamp01(p.transmission),
                    clamp01,
                ),
                spec_tint: Texture::Constant(Vec3::ZERO),
                sheen: Texture::Constant(Vec3::ZERO),
                sheen_tint: Texture::Constant(Vec3::ZERO),
                flatness: Texture::Constant(Vec3::ZERO),
                clearcoat: images.scalar(&p.clearcoat_map, true, 0, clamp01(p.clearcoat), clamp01),
                // Burley's clearcoat is parametrised by gloss, the opposite of roughness.
                clearcoat_gloss: images.scalar(
                    &p.clearcoat_roughness_map,
                    true,
                    1,
                    clamp01(p.clearcoat_roughness),
                    |r| 1.0 - clamp01(r),
                ),
                eta,
                rates: [1.0; 3],
            }));
            let e = Vec3::from(p.emissive);
            let emission = (e.is_finite() && e.max_element() > 0.0)
                .then(|| images.colour(&p.emissive_map, e.max(Vec3::ZERO).to_array()));
            (leaf, transmits, emission)
        }
        None => {
            // MTL: Kd (times map_Kd) is the base colour; Ns (times map_Ns) the roughness; Ks's
            // luminance (times map_Ks's mean) the reflectance at normal incidence, which principled
            // takes as `specular = F0 / 0.08` (capped at 1, eta 1.8).
            let ks = images
                .colour(&m.specular_map, m.specular.map(|c| c.max(0.0)))
                .mean();
            let specular = (luminance(ks) / 0.08).clamp(0.0, 1.0);
            let n = m.shininess;
            let leaf = Material::Principled(Box::new(PrincipledTextures {
                base_color: base_color.clone(),
                roughness: images.scalar(&m.shininess_map, true, 0, 1.0, move |v| {
                    shininess_to_roughness(v * n)
                }),
                anisotropic: Texture::Constant(Vec3::ZERO),
                metallic: Texture::Constant(Vec3::ZERO),
                spec_trans: Texture::Constant(Vec3::ZERO),
                spec_tint: Texture::Constant(Vec3::ZERO),
                sheen: Texture::Constant(Vec3::ZERO),
                sheen_tint: Texture::Constant(Vec3::ZERO),
                flatness: Texture::Constant(Vec3::ZERO),
                clearcoat: Texture::Constant(Vec3::ZERO),
                clearcoat_gloss: Texture::Constant(Vec3::ZERO),
                eta: specular_to_eta(specular.max(1e-3)),
                rates: [1.0; 3],
            }));
            (leaf, false, None)
        }
    };
    let mut entries = vec![leaf];
    // One-sided BSDFs are black from behind; a file's surfaces are meant to be seen from either
    // side (glTF's single-sided materials are culled by rasterisers, not blackened), so every
    // material that does not refract is made two-sided.
    if !transmits {
        let leaf = first;
        entries.push(Material::TwoSided {
            front: leaf,
            back: leaf,
        });
    }
    // The perturbed normal wraps the two-sided material, as the shading code expects: the map's
    // normal is read in the unmirrored frame, and the back side is mirrored inside it.
    if let Some(perturb) = perturbation(m, images, first + entries.len() as u32 - 1) {
        entries.push(perturb);
    }
    let opacity = coverage(m, images);
    if let Some(opacity) = opacity {
        let inner = first + entries.len() as u32 - 1;
        entries.push(Material::Mask { opacity, inner });
    }
    BuiltMaterial { entries, emission }
}

/// `inner` shaded with `m`'s normal map (glTF `normalTexture`, MTL `norm`) or, without one, its
/// bump map (MTL `bump`/`map_bump`), through Mitsuba's `normalmap` and `bumpmap` adapters with
/// their defaults. The normal map's tangent frame is the shading frame, whose tangent follows
/// dp/du and whose bitangent is n x dp/du: glTF's frame for tangents computed from the uvs
/// (MikkTSpace with a positive handedness; a `TANGENT` attribute is not read). glTF's `scale`
/// multiplies the map's x and y (`normalize((2 rgb - 1) * (scale, scale, 1))`), baked into the
/// image; MTL's `-bm` is the bump map's height scale.
fn perturbation(m: &FileMaterial, images: &Images, inner: u32) -> Option<Material> {
    if let Some((t, scale)) = &m.normal_map {
        if let Some(b) = images.get(t, true) {
            let normals = if *scale == 1.0 || !scale.is_finite() {
                images.texture(t, b.clone())
            } else {
                let scale = *scale;
                let derived = derive(b, 3, |px, out| {
                    let c = |k: usize| px.get(k).copied().unwrap_or(px[0]);
                    out[0] = 0.5 + (c(0) - 0.5) * scale;
                    out[1] = 0.5 + (c(1) - 0.5) * scale;
                    out[2] = c(2);
                });
                images.texture(t, Arc::new(derived))
            };
            return Some(Material::NormalMap {
                normals,
                inner,
                flip_invalid: true,
                shadowing: true,
            });
        }
    }
    let (t, scale) = m.bump_map.as_ref()?;
    let b = images.get(t, true)?;
    Some(Material::BumpMap {
        // Grey value, or luminance of a colour image, as the bump adapter reads a texture.
        height: images.texture(t, b.clone()),
        scale: if scale.is_finite() { *scale } else { 1.0 },
        inner,
        flip_invalid: true,
        shadowing: true,
    })
}

/// The coverage of `m`, or `None` if it is opaque everywhere.
fn coverage(m: &FileMaterial, images: &Images) -> Option<Texture> {
    let a = if m.opacity.is_finite() {
        m.opacity.clamp(0.0, 1.0)
    } else {
        1.0
    };
    let (map, raw, cutoff) = match m.alpha {
        AlphaMode::Opaque => return None,
        // glTF's alpha is the base colour texture's alpha channel; MTL's is map_d.
        AlphaMode::Mask(c) if m.pbr.is_some() => (&m.diffuse_map, false, Some(c)),
        AlphaMode::Mask(c) => (&m.opacity_map, true, Some(c)),
        AlphaMode::Blend if m.pbr.is_some() => (&m.diffuse_map, false, None),
        AlphaMode::Blend => (&m.opacity_map, true, None),
    };
    let textured = map.as_ref().and_then(|t| {
        // A glTF base colour image without alpha is opaque: its alpha is 1.
        let b = images.get(t, raw)?;
        (m.pbr.is_none() || b.has_alpha()).then(|| images.alpha(t, raw, a, cutoff))?
    });
    match textured {
        Some(t) => Some(t),
        None => {
            let v = match cutoff {
                Some(c) => f32::from(u8::from(a >= c)),
                None => a,
            };
            (v < 1.0).then(|| Texture::Constant(Vec3::splat(v)))
        }
    }
}
