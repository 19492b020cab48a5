//! The isotropic phase function, `1 / 4 pi`: every direction equally likely.

use super::{PhasePlugin, PhaseSample};
use crate::math::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Isotropic;

impl PhasePlugin for Isotropic {
    const NAME: &'static str = "isotropic";

    #[inline]
    fn eval(&self, _d: Vec3, _wo: Vec3) -> f32 {
        0.25 / PI
    }

    #[inline]
    fn pdf(&self, _d: Vec3, _wo: Vec3) -> f32 {
        0.25 / PI
    }

    /// A uniform direction on the sphere (z uniform in [-1, 1], Archimedes).
    #[inline]
    fn sample(&self, d: Vec3, _u1: f32, u2: Vec2) -> Option<PhaseSample> {
        let cos_theta = 1.0 - 2.0 * u2.x;
        Some(PhaseSample {
            wo: super::around(d, cos_theta, 2.0 * PI * u2.y),
            pdf: 0.25 / PI,
            weight: 1.0,
        })
    }
}
