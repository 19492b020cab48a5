//! Choosing one light per shading point. Lights at a finite distance are chosen in proportion to
//! their emitted power (pbrt-v4's `PowerLightSampler`), so that bright lights get most of the
//! shadow rays. Lights at infinity (environments, the sun, directional lights) are not compared
//! with them by power: theirs is counted through the scene's bounding sphere, so it grows with the
//! scene's size and says nothing of the light a point receives, and a bright sky would starve a
//! spot beside it (Mitsuba's `spot_light` scene: 50 to 1 by power). Instead, as pbrt-v4's
//! `BVHLightSampler` does at its top level, each infinite light and the set of finite lights are
//! chosen with equal probability, then a finite light by power within its set.

use super::distribution::Distribution1D;

#[derive(Clone, Debug)]
pub struct LightPicker {
    distribution: Distribution1D,
}

impl LightPicker {
    /// `powers[i]` is light `i`'s power, `infinite[i]` whether it lies at infinity. Lights of
    /// zero (or negative, or non-finite) power are never picked; if every light has zero power
    /// the choice is uniform.
    pub fn new(powers: &[f32], infinite: &[bool]) -> Self {
        assert_eq!(powers.len(), infinite.len(), "one flag per light");
        let positive = |p: f32| p.is_finite() && p > 0.0;
        let finite_sum: f64 = powers
            .iter()
            .zip(infinite)
            .filter(|&(&p, &inf)| !inf && positive(p))
            .map(|(&p, _)| p as f64)
            .sum();
        let any_infinite = powers
            .iter()
            .zip(infinite)
            .any(|(&p, &inf)| inf && positive(p));
        // Finite lights keep their powers as weights (a scene without infinite lights is chosen
        // from exactly as by power alone); each infinite light weighs as much as all of them
        // together, or 1 where there are none.
        let weights: Vec<f32> = if !any_infinite {
            powers.to_vec()
        } else {
            let share = if finite_sum > 0.0 {
                finite_sum as f32
            } else {
                1.0
            };
            powers
                .iter()
                .zip(infinite)
                .map(|(&p, &inf)| match (inf, positive(p)) {
                    (_, false) => 0.0,
                    (true, true) => share,
                    (false, true) => p,
                })
                .collect()
        };
        Self {
            distribution: Distribution1D::new(&weights),
        }
    }

    pub fn len(&self) -> usize {
        self.distribution.len()
    }

    pub fn is_empty(&self) -> bool {
        self.distribution.is_empty()
    }

    /// (index, its probability) for `u` in [0, 1); (0, 0.0) when there are no lights.
    pub fn pick(&self, u: f32) -> (usize, f32) {
        if self.distribution.is_empty() {
            return (0, 0.0);
        }
        let (i, p, _) = self.distribution.sample_discrete(u);
        (i, p)
    }

    pub fn pmf(&self, index: usize) -> f32 {
        self.distribution.pmf(index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn picks_in_proportion_to_power() {
        let picker = LightPicker::new(&[1.0, 0.0, 3.0], &[false; 3]);
        assert_eq!(picker.pmf(0), 0.25);
        assert_eq!(picker.pmf(1), 0.0);
        assert_eq!(picker.pmf(2), 0.75);
        let mut counts = [0usize; 3];
        let n = 10_000;
        for k in 0..n {
            let (i, p) = picker.pick((k as f32 + 0.5) / n as f32);
            assert_eq!(p, picker.pmf(i));
            counts[i] += 1;
        }
        // Stratified u: the counts are exact up to one per boundary.
        assert_eq!(counts[1], 0);
        assert!((counts[0] as i64 - 2500).abs() <= 1, "{counts:?}");
        // The very ends of [0, 1) stay on lights of non-zero power.
        assert_eq!(picker.pick(0.0).0, 0);
        assert_eq!(picker.pick(0.25).0, 2);
        assert_eq!(picker.pick(0.999_999_9).0, 2);
    }

    #[test]
    fn all_zero_is_uniform_and_none_is_none() {
        let picker = LightPicker::new(&[0.0, 0.0, 0.0, 0.0], &[false, true, false, true]);
        assert_eq!(picker.pmf(3), 0.25);
        assert_eq!(picker.pick(0.6), (2, 0.25));
        assert_eq!(LightPicker::new(&[], &[]).pick(0.5), (0, 0.0));
        assert_eq!(LightPicker::new(&[f32::NAN, 2.0], &[false; 2]).pmf(0), 0.0);
    }

    /// Each infinite light and the finite lights as a whole are equally likely, whatever their
    /// powers; the finite ones share their part by power.
    #[test]
    fn infinite_lights_are_not_weighed_against_finite_ones_by_power() {
        // A spot beside a sky 50 times its power: half the choices each.
        let spot_and_sky = LightPicker::new(&[1.0, 50.0], &[false, true]);
        assert!((spot_and_sky.pmf(0) - 0.5).abs() < 1e-6);
        assert!((spot_and_sky.pmf(1) - 0.5).abs() < 1e-6);
        // Two skies, a dark one (never chosen) and two finite lights of power 1 and 3.
        let p = LightPicker::new(
            &[1.0, 1e6, 3.0, 0.0, 2.0],
            &[false, true, false, true, true],
        );
        let expected = [1.0 / 12.0, 1.0 / 3.0, 3.0 / 12.0, 0.0, 1.0 / 3.0];
        for (i, e) in expected.iter().enumerate() {
            assert!((p.pmf(i) - e).abs() < 1e-6, "{i}: {} vs {e}", p.pmf(i));
        }
        // Infinite lights alone are chosen uniformly.
        let skies = LightPicker::new(&[1.0, 9.0], &[true, true]);
        assert!((skies.pmf(0) - 0.5).abs() < 1e-6);
    }
}
