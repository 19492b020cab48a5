//! Mitsuba's `blendphase`: `(1 - w) p0 + w p1`. Sampling picks `p1` with probability `w` (the
//! component number reused, rescaled, for the component's own choice), and the density is the
//! mixture's, so the weight is exactly the mixture over its density.

use super::{Phase, PhasePlugin, PhaseSample};
use crate::math::{Vec2, Vec3};

#[derive(Clone, Debug, PartialEq)]
pub struct BlendPhase {
    /// The weight of `phases[1]`, in [0, 1].
    pub weight: f32,
    pub phases: Box<[Phase; 2]>,
}

impl PhasePlugin for BlendPhase {
    const NAME: &'static str = "blendphase";

    #[inline]
    fn eval(&self, d: Vec3, wo: Vec3) -> f32 {
        let [a, b] = &*self.phases;
        (1.0 - self.weight) * a.eval(d, wo) + self.weight * b.eval(d, wo)
    }

    #[inline]
    fn pdf(&self, d: Vec3, wo: Vec3) -> f32 {
        let [a, b] = &*self.phases;
        (1.0 - self.weight) * a.pdf(d, wo) + self.weight * b.pdf(d, wo)
    }

    fn sample(&self, d: Vec3, u1: f32, u2: Vec2) -> Option<PhaseSample> {
        let [a, b] = &*self.phases;
        let w = self.weight;
        let s = if u1 < w {
            b.sample(d, u1 / w, u2)?
        } else {
            a.sample(d, ((u1 - w) / (1.0 - w)).min(1.0 - f32::EPSILON / 2.0), u2)?
        };
        let pdf = self.pdf(d, s.wo);
        (pdf > 0.0).then(|| PhaseSample {
            wo: s.wo,
            pdf,
            weight: self.eval(d, s.wo) / pdf,
        })
    }
}
