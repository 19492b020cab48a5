//! Mitsuba's `heterogeneous` medium: extinction `scale * sigma_t(p)` and albedo from volumes,
//! inside the box of its `sigma_t` volume only. Its majorant is one number for the whole medium,
//! `scale` times the grid's largest value (Mitsuba's `m_max_density`): trilinear interpolation
//! never exceeds its largest sample, so null collisions have non-negative density.

use super::{MediumPlugin, Phase, Volume};
use crate::math::{Ray, Vec3};

#[derive(Clone, Debug)]
pub struct Heterogeneous {
    pub sigma_t: Volume,
    pub albedo: Volume,
    pub scale: f32,
    pub phase: Phase,
    /// `scale * max sigma_t`, in every channel.
    pub majorant: f32,
}

impl Heterogeneous {
    pub fn new(sigma_t: Volume, albedo: Volume, scale: f32, phase: Phase) -> Self {
        let majorant = scale * sigma_t.max();
        Heterogeneous {
            sigma_t,
            albedo,
            scale,
            phase,
            majorant,
        }
    }
}

impl MediumPlugin for Heterogeneous {
    const NAME: &'static str = "heterogeneous";
    const HOMOGENEOUS: bool = false;

    #[inline]
    fn range(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32)> {
        self.sigma_t.range(ray, t_max)
    }

    #[inline]
    fn majorant(&self) -> Vec3 {
        Vec3::splat(self.majorant)
    }

    #[inline]
    fn coefficients(&self, p: Vec3) -> (Vec3, Vec3) {
        let sigma_t = self.sigma_t.eval(p) * self.scale;
        (sigma_t, sigma_t * self.albedo.eval(p))
    }

    fn phase(&self) -> &Phase {
        &self.phase
    }
}
