//! Samplers: the random numbers of Monte Carlo integrators, as a pure function of (pixel, sample
//! index, dimension) and the scene's seed, so that an image does not depend on the number of
//! threads, on the tiling, or on which machine renders which tile.

mod hash;
mod independent;
mod pixel_pattern;
mod sobol;

pub use hash::mix64;
pub use independent::{IndependentSampler, Pcg32};
pub use pixel_pattern::PixelPatternSampler;
pub use sobol::SobolSampler;

use crate::math::Vec2;

/// The interface of pbrt-v4's and Mitsuba's samplers: a sample of a pixel is a stream of
/// dimensions, consumed in the same order by the integrator for every sample.
pub trait Sampler: Clone + Send + Sync {
    /// Positions the sampler at sample `index` of pixel `(x, y)`, dimension 0.
    fn start_pixel_sample(&mut self, x: u32, y: u32, index: u32);
    /// The next dimension, uniform in `[0, 1)`.
    fn get_1d(&mut self) -> f32;
    /// The next two dimensions, uniform in `[0, 1)^2` (stratified together by low-discrepancy
    /// samplers).
    fn get_2d(&mut self) -> Vec2;
    /// The point on a camera's lens, drawn right after the film position by cameras with an
    /// aperture only (pbrt-v4's `GetCameraSample` and Mitsuba's sample order: film, then
    /// aperture), so that a pinhole camera's samples use the dimensions they always did. The next
    /// two dimensions, unless the sampler places lens points itself.
    #[inline]
    fn get_lens_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}

/// `u` in `[0, 1)` from 32 random bits: the top 24 bits, so that the result is exactly
/// representable and never rounds up to 1.
#[inline]
pub fn unit_f32(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mean, variance and a 2D stratification check of many samples of one sampler.
    fn moments<S: Sampler>(mut s: S, spp: u32) -> (f64, f64) {
        let (mut sum, mut sum2, mut n) = (0.0f64, 0.0f64, 0u32);
        for y in 0..4 {
            for x in 0..4 {
                for i in 0..spp {
                    s.start_pixel_sample(x, y, i);
                    for _ in 0..6 {
                        let u = s.get_1d() as f64;
                        assert!((0.0..1.0).contains(&u));
                        sum += u;
                        sum2 += u * u;
                        n += 1;
                        let p = s.get_2d();
                        assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
                    }
                }
            }
        }
        let mean = sum / n as f64;
        (mean, sum2 / n as f64 - mean * mean)
    }

    #[test]
    fn samples_are_uniform() {
        for (mean, var) in [
            moments(IndependentSampler::new(7), 64),
            moments(SobolSampler::new(7, 64), 64),
            moments(SobolSampler::new(7, 48), 48),
            moments(PixelPatternSampler::new(7, 64), 64),
        ] {
            // 6144 samples: the mean's standard error is 0.0037.
            assert!((mean - 0.5).abs() < 0.02, "mean {mean}");
            assert!((var - 1.0 / 12.0).abs() < 0.01, "variance {var}");
        }
    }

    #[test]
    fn a_sample_is_a_function_of_pixel_index_and_dimension() {
        fn stream<S: Sampler>(s: &mut S, x: u32, y: u32, i: u32) -> Vec<f32> {
            s.start_pixel_sample(x, y, i);
            (0..5).flat_map(|_| [s.get_1d(), s.get_2d().x]).collect()
        }
        let mut s = IndependentSampler::new(3);
        let a = stream(&mut s, 5, 9, 2);
        stream(&mut s, 1, 1, 0);
        assert_eq!(a, stream(&mut s.clone(), 5, 9, 2));
        assert_ne!(a, stream(&mut s, 5, 9, 3));
        assert_ne!(a, stream(&mut s, 9, 5, 2));
        let mut s = SobolSampler::new(3, 16);
        let a = stream(&mut s, 5, 9, 2);
        stream(&mut s, 1, 1, 0);
        assert_eq!(a, stream(&mut s, 5, 9, 2));
        assert_ne!(a, stream(&mut s, 5, 9, 3));
        assert_ne!(a, stream(&mut s, 9, 5, 2));
        assert_ne!(a, stream(&mut SobolSampler::new(4, 16), 5, 9, 2));
    }

    /// The Sobol sampler's 2D points of one pixel are stratified: with 64 samples every one of
    /// the 8x8 cells, and every 64x1 and 1x64 strip, holds exactly one (a (0, 6, 2)-net, kept by
    /// Owen scrambling). Independent samples leave many cells empty.
    #[test]
    fn sobol_pairs_form_a_net() {
        let mut s = SobolSampler::new(11, 64);
        for dim_pair in 0..4 {
            let mut cells = [0u32; 64];
            let mut rows = [0u32; 64];
            let mut cols = [0u32; 64];
            for i in 0..64 {
                s.start_pixel_sample(3, 4, i);
                for _ in 0..dim_pair {
                    s.get_2d();
                }
                let p = s.get_2d();
                let (cx, cy) = ((p.x * 8.0) as usize, (p.y * 8.0) as usize);
                cells[cy * 8 + cx] += 1;
                rows[(p.y * 64.0) as usize] += 1;
                cols[(p.x * 64.0) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "pair {dim_pair}: {cells:?}");
            assert!(rows.iter().all(|&c| c == 1) && cols.iter().all(|&c| c == 1));
        }
    }

    /// Dimensions of the Sobol sampler are decorrelated by their own index shuffles: the
    /// correlation between dimension 0 and 2 (both van der Corput before scrambling) is small.
    #[test]
    fn sobol_dimensions_are_decorrelated() {
        let mut s = SobolSampler::new(5, 256);
        let (mut sab, mut sa, mut sb) = (0.0f64, 0.0f64, 0.0f64);
        let mut n = 0.0;
        for px in 0..8 {
            for i in 0..256 {
                s.start_pixel_sample(px, 0, i);
                let a = s.get_2d().x as f64;
                let b = s.get_2d().x as f64;
                sab += a * b;
                sa += a;
                sb += b;
                n += 1.0;
            }
        }
        let cov = sab / n - (sa / n) * (sb / n);
        let corr = cov * 12.0;
        // Independent: sd of the estimate about 1/sqrt(2048) = 0.022.
        assert!(corr.abs() < 0.1, "correlation {corr}");
    }
}
