//! Henyey and Greenstein's phase function (1941), `(1 - g^2) / (4 pi (1 + g^2 - 2 g cos θ)^1.5)`
//! with `cos θ = d · wo`: `g > 0` scatters forward, `g < 0` backward, `g = 0` is isotropic. `g`
//! is the mean cosine. Sampled exactly by inverting its cumulative distribution in `cos θ`
//! (pbrt-v4 section 11.3.1 derives the inverse).

use super::{PhasePlugin, PhaseSample};
use crate::math::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    /// In (-1, 1).
    pub g: f32,
}

impl HenyeyGreenstein {
    /// The density as a function of the scattering angle's cosine.
    #[inline]
    pub fn density(&self, cos_theta: f32) -> f32 {
        let g = self.g;
        let denom = 1.0 + g * g - 2.0 * g * cos_theta;
        (1.0 - g * g) / (4.0 * PI * denom * denom.max(0.0).sqrt())
    }

    /// The cosine whose cumulative probability is `u` (u = 1 forward, u = 0 backward).
    #[inline]
    fn cos_theta(&self, u: f32) -> f32 {
        let g = self.g;
        if g.abs() < 1e-3 {
            return 1.0 - 2.0 * u;
        }
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
        ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
    }
}

impl PhasePlugin for HenyeyGreenstein {
    const NAME: &'static str = "hg";

    #[inline]
    fn eval(&self, d: Vec3, wo: Vec3) -> f32 {
        self.density(d.dot(wo))
    }

    #[inline]
    fn pdf(&self, d: Vec3, wo: Vec3) -> f32 {
        self.density(d.dot(wo))
    }

    #[inline]
    fn sample(&self, d: Vec3, _u1: f32, u2: Vec2) -> Option<PhaseSample> {
        let cos_theta = self.cos_theta(u2.x);
        let wo = super::around(d, cos_theta, 2.0 * PI * u2.y);
        let pdf = self.density(cos_theta);
        (pdf > 0.0).then_some(PhaseSample {
            wo,
            pdf,
            weight: 1.0,
        })
    }
}
