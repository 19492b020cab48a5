//! Mitsuba's `homogeneous` medium: one extinction everywhere (scaled by `scale`), the albedo a
//! volume, filling all space on its side of the surfaces that bound it. Its majorant is its
//! extinction, so distance sampling meets no null collisions.

use super::majorant_grid::{MajorantSegment, Majorants};
use super::{MediumPlugin, Phase, Volume};
use crate::math::{Ray, Vec3};

#[derive(Clone, Debug)]
pub struct Homogeneous {
    pub sigma_t: Vec3,
    pub albedo: Volume,
    pub phase: Phase,
}

impl MediumPlugin for Homogeneous {
    const NAME: &'static str = "homogeneous";
    const HOMOGENEOUS: bool = true;

    #[inline]
    fn majorants(&self, _ray: &Ray, t_max: f32) -> Majorants<'_> {
        Majorants::One(Some(MajorantSegment {
            t0: 0.0,
            t1: t_max,
            majorant: self.sigma_t,
        }))
    }

    #[inline]
    fn coefficients(&self, p: Vec3) -> (Vec3, Vec3) {
        (self.sigma_t, self.sigma_t * self.albedo.eval(p))
    }

    fn phase(&self) -> &Phase {
        &self.phase
    }
}
