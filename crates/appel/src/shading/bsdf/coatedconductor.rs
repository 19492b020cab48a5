//! pbrt-v4's `coatedconductor`: a metal under a dielectric coating, evaluated by the random walks
//! of [`super::layered`] (Guo et al. 2018; pbrt-v4 book, section 14.3).

use super::coateddiffuse::LayerTextures;
use super::conductor::metal;
use super::layered::{Interface, Layered, Metal};
use super::{BsdfMaterial, TextureSource};
use crate::error::Result;
use crate::math::Vec3;
use crate::description::CoatedConductorDesc;
use crate::shading::texture::{TexPoint, Texture};

/// A metal under a dielectric coating.
pub type CoatedConductor = Layered<Metal>;

/// [`CoatedConductor`] with its roughnesses and albedo textured.
#[derive(Clone, Debug)]
pub struct CoatedConductorMaterial {
    pub interface_eta: f32,
    pub interface_alpha_u: Texture,
    pub interface_alpha_v: Texture,
    /// The metal's complex index relative to the coating's (pbrt-v4 divides it by the
    /// interface's index: the metal's Fresnel sees the coating, not vacuum).
    pub eta: Vec3,
    pub k: Vec3,
    pub conductor_alpha_u: Texture,
    pub conductor_alpha_v: Texture,
    pub layer: LayerTextures,
}

impl BsdfMaterial for CoatedConductorMaterial {
    type Desc = CoatedConductorDesc;
    type Bsdf = CoatedConductor;

    fn build(d: &CoatedConductorDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        let (eta, k) = metal(Some(&d.conductor_material), d.conductor_eta, d.conductor_k)?;
        let (iu, iv) = d.interface_alphas();
        let (cu, cv) = d.conductor_alphas();
        Ok(CoatedConductorMaterial {
            interface_eta: d.interface_eta,
            interface_alpha_u: textures.texture(&iu)?,
            interface_alpha_v: textures.texture(&iv)?,
            eta: eta / d.interface_eta,
            k: k / d.interface_eta,
            conductor_alpha_u: textures.texture(&cu)?,
            conductor_alpha_v: textures.texture(&cv)?,
            layer: LayerTextures::build(&d.layer(), textures)?,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> CoatedConductor {
        Layered {
            top: Interface::new(
                self.interface_eta,
                self.interface_alpha_u.eval_1_at(p),
                self.interface_alpha_v.eval_1_at(p),
            ),
            base: Metal::new(
                self.eta,
                self.k,
                self.conductor_alpha_u.eval_1_at(p),
                self.conductor_alpha_v.eval_1_at(p),
            ),
            layer: self.layer.at(p),
        }
    }
}
