//! Mitsuba's `heterogeneous` medium: extinction `scale * sigma_t(p)` and albedo from volumes,
//! inside the box of its `sigma_t` volume only. Given as absorption and scattering volumes
//! (pbrt-v4's `RGBGridMedium`), `sigma_t` is their sum, built as one volume of the same
//! resolution (trilinear interpolation is linear, so the sum's lookup is the sum of theirs), and
//! the scattering volume is looked up itself rather than as a ratio (interpolating
//! `sigma_s / sigma_t` would not give the interpolated `sigma_s`). Its majorant is one number for the whole medium,
//! `scale` times the grid's largest value (Mitsuba's `m_max_density`): trilinear interpolation
//! never exceeds its largest sample, so null collisions have non-negative density.

use super::{MediumPlugin, Phase, Volume};
use crate::math::{Ray, Vec3};

#[derive(Clone, Debug)]
pub struct Heterogeneous {
    pub sigma_t: Volume,
    pub scattering: Scattering,
    pub scale: f32,
    pub phase: Phase,
    /// `scale * max sigma_t`, in every channel.
    pub majorant: f32,
}

/// Where a heterogeneous medium's scattering coefficient comes from.
#[derive(Clone, Debug)]
pub enum Scattering {
    /// The albedo: `sigma_s = sigma_t * albedo(p)`.
    Albedo(Volume),
    /// The scattering coefficient itself (before `scale`).
    Coefficient(Volume),
}

impl From<Volume> for Scattering {
    /// A volume alone is an albedo, Mitsuba's form.
    fn from(albedo: Volume) -> Self {
        Scattering::Albedo(albedo)
    }
}

impl Heterogeneous {
    pub fn new(sigma_t: Volume, scattering: impl Into<Scattering>, scale: f32, phase: Phase) -> Self {
        let majorant = scale * sigma_t.max();
        Heterogeneous {
            sigma_t,
            scattering: scattering.into(),
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
        let sigma_s = match &self.scattering {
            Scattering::Albedo(albedo) => sigma_t * albedo.eval(p),
            // Below the extinction but for rounding: the extinction's grid is this one plus the
            // absorption's.
            Scattering::Coefficient(sigma_s) => (sigma_s.eval(p) * self.scale).min(sigma_t),
        };
        (sigma_t, sigma_s)
    }

    fn phase(&self) -> &Phase {
        &self.phase
    }
}
