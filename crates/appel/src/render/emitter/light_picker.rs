//! Choosing one light per shading point in proportion to its emitted power (pbrt-v4's
//! `PowerLightSampler`), so that bright lights get most of the shadow rays.

use super::distribution::Distribution1D;

#[derive(Clone, Debug)]
pub struct LightPicker {
    distribution: Distribution1D,
}

impl LightPicker {
    /// Lights of zero (or negative, or non-finite) power are never picked; if every light has zero
    /// power the choice is uniform.
    pub fn new(powers: &[f32]) -> Self {
        Self {
            distribution: Distribution1D::new(powers),
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
        let picker = LightPicker::new(&[1.0, 0.0, 3.0]);
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
        let picker = LightPicker::new(&[0.0, 0.0, 0.0, 0.0]);
        assert_eq!(picker.pmf(3), 0.25);
        assert_eq!(picker.pick(0.6), (2, 0.25));
        assert_eq!(LightPicker::new(&[]).pick(0.5), (0, 0.0));
        assert_eq!(LightPicker::new(&[f32::NAN, 2.0]).pmf(0), 0.0);
    }
}
