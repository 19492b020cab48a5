//! pbrt-v4's `coateddiffuse`: a Lambertian base under a dielectric coating, evaluated by the
//! random walks of [`super::layered`] (Guo et al. 2018; pbrt-v4 book, section 14.3).

use super::layered::{Interface, Layer, Layered};
use super::{BsdfMaterial, Diffuse, TextureSource};
use crate::error::Result;
use crate::math::Vec3;
use crate::description::{CoatedDiffuseDesc, LayerDesc};
use crate::shading::texture::{TexPoint, Texture};

/// A Lambertian base under a dielectric coating.
pub type CoatedDiffuse = Layered<Diffuse>;

/// The layer's medium with its albedo textured.
#[derive(Clone, Debug)]
pub struct LayerTextures {
    pub thickness: f32,
    pub albedo: Texture,
    pub g: f32,
    pub max_depth: u16,
    pub samples: u16,
}

impl LayerTextures {
    pub(crate) fn build(d: &LayerDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        Ok(LayerTextures {
            thickness: d.thickness,
            albedo: textures.texture(&d.albedo)?,
            g: d.g,
            // Validation bounds both well below u16::MAX.
            max_depth: d.maxdepth.min(u16::MAX as u32) as u16,
            samples: d.nsamples.clamp(1, u16::MAX as u32) as u16,
        })
    }

    #[inline]
    pub(crate) fn at(&self, p: &TexPoint) -> Layer {
        Layer {
            thickness: self.thickness.max(f32::MIN_POSITIVE),
            albedo: self.albedo.eval_at(p).clamp(Vec3::ZERO, Vec3::ONE),
            g: self.g,
            max_depth: self.max_depth,
            samples: self.samples,
        }
    }
}

/// [`CoatedDiffuse`] with its reflectance, roughness and albedo textured.
#[derive(Clone, Debug)]
pub struct CoatedDiffuseMaterial {
    pub reflectance: Texture,
    pub alpha_u: Texture,
    pub alpha_v: Texture,
    pub eta: f32,
    pub layer: LayerTextures,
}

impl BsdfMaterial for CoatedDiffuseMaterial {
    type Desc = CoatedDiffuseDesc;
    type Bsdf = CoatedDiffuse;

    fn build(d: &CoatedDiffuseDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        let (alpha_u, alpha_v) = d.alphas();
        Ok(CoatedDiffuseMaterial {
            reflectance: textures.texture(&d.reflectance)?,
            alpha_u: textures.texture(&alpha_u)?,
            alpha_v: textures.texture(&alpha_v)?,
            eta: d.eta,
            layer: LayerTextures::build(&d.layer(), textures)?,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> CoatedDiffuse {
        Layered {
            top: Interface::new(
                self.eta,
                self.alpha_u.eval_1_at(p),
                self.alpha_v.eval_1_at(p),
            ),
            base: Diffuse::new(self.reflectance.eval_at(p).clamp(Vec3::ZERO, Vec3::ONE)),
            layer: self.layer.at(p),
        }
    }
}
