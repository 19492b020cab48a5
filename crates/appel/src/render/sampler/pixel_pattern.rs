//! The same sub-pixel positions in every pixel: sample 0 at the pixel centre (so that one sample
//! per pixel is exactly the ray through the centre, the convention of raycast and Whitted, whose
//! AOVs then describe the centre), the rest on the R2 low-discrepancy sequence (Roberts 2018).
//! Dimensions after the film position are independent numbers (PCG32), so that a Monte Carlo
//! integrator may run on it too. A lens point is one of them too, except in sample 0, which
//! passes through the lens's centre: one sample per pixel through a lens is the pinhole image
//! (and its AOVs describe it), more samples cover the aperture.

use super::{IndependentSampler, Sampler};
use crate::math::Vec2;
use std::sync::Arc;

/// The R2 sequence's generators: the reciprocals of the plastic number and of its square.
const A1: f64 = 0.754_877_666_246_692_7;
const A2: f64 = 0.569_840_290_998_053_2;

/// Offset of sample `s` in the pixel.
fn offset(s: u32) -> Vec2 {
    let s = s as f64;
    Vec2::new((0.5 + A1 * s).fract() as f32, (0.5 + A2 * s).fract() as f32)
}

#[derive(Clone, Debug)]
pub struct PixelPatternSampler {
    /// The offsets of the first `spp` samples, computed once: `fract` is a library call on x86_64
    /// without SSE4.1, and a frame of Whitted's scene has 300,000 pixels.
    offsets: Arc<[Vec2]>,
    /// The numbers after the film position, started only when asked for (raycast and Whitted
    /// never ask).
    rest: IndependentSampler,
    pixel: (u32, u32),
    index: u32,
    /// Whether the next 2D request is the film position.
    at_film: bool,
    rest_started: bool,
}

impl PixelPatternSampler {
    pub fn new(seed: u64, spp: u32) -> Self {
        Self {
            offsets: (0..spp.max(1)).map(offset).collect(),
            rest: IndependentSampler::new(seed),
            pixel: (0, 0),
            index: 0,
            at_film: true,
            rest_started: false,
        }
    }

    #[inline]
    fn rest(&mut self) -> &mut IndependentSampler {
        self.at_film = false;
        if !self.rest_started {
            self.rest_started = true;
            let (x, y) = self.pixel;
            self.rest.start_pixel_sample(x, y, self.index);
        }
        &mut self.rest
    }
}

impl Sampler for PixelPatternSampler {
    #[inline]
    fn start_pixel_sample(&mut self, x: u32, y: u32, index: u32) {
        self.pixel = (x, y);
        self.index = index;
        self.at_film = true;
        self.rest_started = false;
    }

    #[inline]
    fn get_1d(&mut self) -> f32 {
        self.rest().get_1d()
    }

    /// The first request of a sample is its film position.
    #[inline]
    fn get_2d(&mut self) -> Vec2 {
        if self.at_film {
            self.at_film = false;
            return match self.offsets.get(self.index as usize) {
                Some(&o) => o,
                None => offset(self.index),
            };
        }
        self.rest().get_2d()
    }

    /// Sample 0 through the lens's centre, which the concentric map puts at `(0.5, 0.5)`.
    #[inline]
    fn get_lens_2d(&mut self) -> Vec2 {
        if self.index == 0 {
            return Vec2::splat(0.5);
        }
        self.get_2d()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_zero_is_the_centre_and_later_ones_fill_the_pixel() {
        let mut s = PixelPatternSampler::new(0, 64);
        s.start_pixel_sample(3, 7, 0);
        assert_eq!(s.get_2d(), Vec2::splat(0.5));
        // The same pattern in every pixel, and past the precomputed count.
        let mut cells = [0u32; 16];
        for i in 0..64 {
            s.start_pixel_sample(i % 5, 2, i);
            let p = s.get_2d();
            assert_eq!(p, offset(i));
            cells[(p.y * 4.0) as usize * 4 + (p.x * 4.0) as usize] += 1;
        }
        s.start_pixel_sample(0, 0, 100);
        assert_eq!(s.get_2d(), offset(100));
        // Low discrepancy: 64 points put 2 to 6 in each of 16 cells (independent points leave
        // some cells with one or none in most draws).
        assert!(cells.iter().all(|&c| (2..=6).contains(&c)), "{cells:?}");
    }

    #[test]
    fn later_dimensions_are_the_independent_samplers() {
        let mut s = PixelPatternSampler::new(9, 4);
        let mut ind = IndependentSampler::new(9);
        s.start_pixel_sample(4, 5, 2);
        ind.start_pixel_sample(4, 5, 2);
        s.get_2d();
        assert_eq!(s.get_1d(), ind.get_1d());
        assert_eq!(s.get_2d(), ind.get_2d());
    }
}
