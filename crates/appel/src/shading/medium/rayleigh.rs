//! Rayleigh's phase function, `3 (1 + cos^2 θ) / 16 pi`, for particles much smaller than the
//! wavelength (unpolarised). Sampled exactly: the cumulative distribution in `μ = cos θ` is
//! `(μ^3 + 3 μ + 4) / 8`, a depressed cubic in `μ` solved by Cardano's formula (it has one real
//! root, its discriminant being positive).

use super::{PhasePlugin, PhaseSample};
use crate::math::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rayleigh;

#[inline]
fn density(cos_theta: f32) -> f32 {
    3.0 / (16.0 * PI) * (1.0 + cos_theta * cos_theta)
}

impl PhasePlugin for Rayleigh {
    const NAME: &'static str = "rayleigh";

    #[inline]
    fn eval(&self, d: Vec3, wo: Vec3) -> f32 {
        density(d.dot(wo))
    }

    #[inline]
    fn pdf(&self, d: Vec3, wo: Vec3) -> f32 {
        density(d.dot(wo))
    }

    #[inline]
    fn sample(&self, d: Vec3, _u1: f32, u2: Vec2) -> Option<PhaseSample> {
        // μ^3 + 3 μ + q = 0 with q = 4 - 8 u.
        let half_q = 2.0 - 4.0 * u2.x;
        let root = (half_q * half_q + 1.0).sqrt();
        let cos_theta = ((-half_q + root).cbrt() + (-half_q - root).cbrt()).clamp(-1.0, 1.0);
        Some(PhaseSample {
            wo: super::around(d, cos_theta, 2.0 * PI * u2.y),
            pdf: density(cos_theta),
            weight: 1.0,
        })
    }
}
