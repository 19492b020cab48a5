//! A thin dielectric sheet (a window pane): the two interfaces' inter-reflections summed, light
//! passing straight through undeviated, Mitsuba's `thindielectric`. As in Mitsuba 3 its
//! transmission is a null lobe (`BsdfFlags::NULL`): the volumetric path tracer's shadow rays pass
//! the sheet with [`Bsdf::null_transmission`], and its paths cross it as no bounce (so that a light
//! seen through the pane by next-event estimation and by a path through it is weighed once, by
//! the last real vertex's MIS). Every other integrator reads the lobe as the delta transmission
//! it contains.

use super::fresnel::{fresnel_dielectric, reflect};
use super::{Phong, Bsdf, BsdfFlags, BsdfSample};
use crate::math::{Vec2, Vec3};
use super::{ior_ratio, BsdfMaterial, TextureSource};
use crate::error::Result;
use crate::description::ThinDielectricDesc;
use crate::shading::texture::{TexPoint, Texture};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectric {
    /// Interior IOR over exterior IOR.
    pub eta: f32,
    pub specular_reflectance: Vec3,
    pub specular_transmittance: Vec3,
}

impl ThinDielectric {
    pub fn new(eta: f32, specular_reflectance: Vec3, specular_transmittance: Vec3) -> Self {
        ThinDielectric {
            eta,
            specular_reflectance,
            specular_transmittance,
        }
    }

    /// Total reflectance of the sheet: with `R` of one interface, the series of bounces inside
    /// `R + T² R + T² R³ + ... = R + (1 - R)² R / (1 - R²) = 2R / (1 + R)`.
    #[inline]
    pub fn reflectance(&self, cos_theta: f32) -> f32 {
        let r = fresnel_dielectric(cos_theta.abs(), self.eta).0;
        r * 2.0 / (1.0 + r)
    }
}

impl Bsdf for ThinDielectric {
    /// Fresnel-weighted reflection and refraction (of the sheet's index).
    fn whitted(&self) -> Phong {
        Phong::glass(self.eta)
    }

    /// Reflection with probability `2R / (1 + R)`, else straight through (`-wo`, eta 1: the two
    /// refractions cancel, and so does the radiance scaling), the null lobe.
    #[inline]
    fn sample(&self, wo: Vec3, u1: f32, _u2: Vec2) -> Option<BsdfSample> {
        let r = self.reflectance(wo.z);
        Some(if u1 <= r {
            BsdfSample {
                wi: reflect(wo),
                weight: self.specular_reflectance,
                pdf: r,
                eta: 1.0,
                lobe: BsdfFlags::DELTA_REFLECTION,
            }
        } else {
            BsdfSample {
                wi: -wo,
                weight: self.specular_transmittance,
                pdf: 1.0 - r,
                eta: 1.0,
                lobe: BsdfFlags::NULL,
            }
        })
    }

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DELTA_REFLECTION | BsdfFlags::NULL
    }

    /// What passes straight through: `1 - 2R / (1 + R) = (1 - R) / (1 + R)` (the series
    /// `(1 - R)² (1 + R² + R⁴ + ...)`), times the transmittance factor; what `sample` passes on
    /// average.
    #[inline]
    fn null_transmission(&self, wo: Vec3) -> Vec3 {
        self.specular_transmittance * (1.0 - self.reflectance(wo.z))
    }
}

/// [`ThinDielectric`] with its reflectance and transmittance factors textured.
#[derive(Clone, Debug)]
pub struct ThinDielectricMaterial {
    /// Interior IOR over exterior IOR.
    pub eta: f32,
    pub reflectance: Texture,
    pub transmittance: Texture,
}

impl BsdfMaterial for ThinDielectricMaterial {
    type Desc = ThinDielectricDesc;
    type Bsdf = ThinDielectric;

    fn build(d: &ThinDielectricDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        Ok(ThinDielectricMaterial {
            eta: ior_ratio(&d.int_ior, &d.ext_ior)?,
            reflectance: textures.texture(&d.specular_reflectance)?,
            transmittance: textures.texture(&d.specular_transmittance)?,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> ThinDielectric {
        ThinDielectric::new(self.eta, self.reflectance.eval_at(p), self.transmittance.eval_at(p))
    }
}
