//! Independent uniform samples from PCG32 (O'Neill 2014), one stream per pixel sample.

use super::hash::hash_words;
use super::{unit_f32, Sampler};
use crate::math::Vec2;

/// PCG-XSH-RR with 64-bit state: small, fast and statistically sound.
#[derive(Clone, Copy, Debug)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    const MULTIPLIER: u64 = 6_364_136_223_846_793_005;

    /// The generator of `stream` started at `seed`, with O'Neill's seeding procedure.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut r = Self {
            state: 0,
            inc: (stream << 1) | 1,
        };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }

    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(Self::MULTIPLIER).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        unit_f32(self.next_u32())
    }
}

#[derive(Clone, Debug)]
pub struct IndependentSampler {
    seed: u64,
    rng: Pcg32,
}

impl IndependentSampler {
    pub fn new(seed: u64) -> Self {
        Self {
            seed,
            rng: Pcg32::new(0, 0),
        }
    }
}

impl Sampler for IndependentSampler {
    #[inline]
    fn start_pixel_sample(&mut self, x: u32, y: u32, index: u32) {
        // The pixel picks the stream, the index and seed the start: streams of one pixel never
        // overlap, and no two pixels share a stream.
        let pixel = ((y as u64) << 32) | x as u64;
        let start = hash_words(&[self.seed, index as u64]);
        self.rng = Pcg32::new(start, hash_words(&[pixel, self.seed]));
    }

    #[inline]
    fn get_1d(&mut self) -> f32 {
        self.rng.next_f32()
    }

    #[inline]
    fn get_2d(&mut self) -> Vec2 {
        let x = self.rng.next_f32();
        Vec2::new(x, self.rng.next_f32())
    }
}
