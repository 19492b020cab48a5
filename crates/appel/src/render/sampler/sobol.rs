//! Owen-scrambled Sobol samples, padded: every pair of dimensions is the first two Sobol
//! dimensions (a (0, 2)-sequence in base 2), scrambled and index-shuffled with seeds of its own,
//! so that any 2^k consecutive samples of a pair are stratified in every elementary interval and
//! pairs stay independent of each other (the "padded" construction of Kollig and Keller 2002,
//! as pbrt-v4's PaddedSobolSampler uses it).

use super::hash::{hash_words, mix64};
use super::{unit_f32, Sampler};
use crate::math::Vec2;

#[derive(Clone, Debug)]
pub struct SobolSampler {
    seed: u64,
    /// Sample indices are shuffled within blocks of this power of two (at least the sample
    /// count): each block is one full (0, 2)-net.
    block: u32,
    spp: u32,
    pixel: u64,
    index: u32,
    dimension: u32,
}

impl SobolSampler {
    /// A sampler for `spp` samples per pixel (which sets the shuffle's block size: indices past
    /// `spp` remain valid and start new blocks).
    pub fn new(seed: u64, spp: u32) -> Self {
        Self {
            seed,
            block: spp.max(1).next_power_of_two(),
            spp: spp.max(1),
            pixel: 0,
            index: 0,
            dimension: 0,
        }
    }

    /// The hash of this pixel, dimension and seed, from which one dimension's scrambles come.
    #[inline]
    fn dimension_hash(&mut self) -> u64 {
        let h = hash_words(&[self.pixel, self.dimension as u64, self.seed]);
        self.dimension += 1;
        h
    }

    /// The sample index of the current sample in this dimension: a pseudo-random permutation of
    /// the indices inside each block, so that dimensions are not correlated through the order of
    /// the samples. Within one block the permutation is a nested (Owen) scramble of the index's
    /// bits, with cycle walking onto `[0, spp)` when `spp` is no power of two.
    #[inline]
    fn shuffled_index(&self, h: u64) -> u32 {
        let bits = self.block.trailing_zeros();
        if bits == 0 {
            return self.index;
        }
        let block = self.index / self.block;
        let seed = mix64(h ^ block as u64) as u32;
        let mut i = self.index % self.block;
        let scramble = |i: u32| nested_scramble(i << (32 - bits), seed) >> (32 - bits);
        // The first block holds the sample count's samples: cycle walking maps `[0, spp)` onto
        // itself. Indices past the count (more passes) are scrambled over their whole block.
        let walk = block == 0 && i < self.spp;
        i = scramble(i);
        while walk && i >= self.spp {
            i = scramble(i);
        }
        block * self.block + i
    }
}

impl Sampler for SobolSampler {
    #[inline]
    fn start_pixel_sample(&mut self, x: u32, y: u32, index: u32) {
        self.pixel = ((y as u64) << 32) | x as u64;
        self.index = index;
        self.dimension = 0;
    }

    #[inline]
    fn get_1d(&mut self) -> f32 {
        let h = self.dimension_hash();
        let i = self.shuffled_index(h);
        unit_f32(nested_scramble(i.reverse_bits(), (h >> 32) as u32))
    }

    #[inline]
    fn get_2d(&mut self) -> Vec2 {
        let h = self.dimension_hash();
        self.dimension += 1;
        let i = self.shuffled_index(h);
        let h2 = mix64(h);
        Vec2::new(
            unit_f32(nested_scramble(i.reverse_bits(), (h >> 32) as u32)),
            unit_f32(nested_scramble(sobol_dimension_1(i), h2 as u32)),
        )
    }
}

/// The second Sobol dimension: the generator matrix of the primitive polynomial `x + 1`, whose
/// column k is `v_k = v_{k-1} ^ (v_{k-1} >> 1)` from `v_0 = 2^31` (Pascal's triangle mod 2).
#[inline]
fn sobol_dimension_1(mut i: u32) -> u32 {
    let mut v = 1u32 << 31;
    let mut out = 0;
    while i != 0 {
        if i & 1 != 0 {
            out ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    out
}

/// A nested uniform scramble of the bits of `x` (most significant first) by a hash in which each
/// bit is flipped by a function of the bits above it only: the hash-based Owen scramble of Laine
/// and Karras 2011 ("Stratified sampling for stochastic transparency"), applied to the reversed
/// bits, with their multiplication constants. A true Owen scramble hashes each prefix separately
/// (24 hashes for an f32); this is one hash and keeps the nets' stratification, which is what the
/// render's convergence needs.
#[inline]
fn nested_scramble(x: u32, seed: u32) -> u32 {
    let mut v = x.reverse_bits();
    v = v.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v ^= v.wrapping_mul(0xc7af_e638);
    v ^= v.wrapping_mul(0x8d22_f6e6);
    v.reverse_bits()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scramble_is_nested_and_a_permutation_of_each_prefix_length() {
        // Bits above position k decide only the bits above position k: scrambling 2^k values that
        // differ in their top k bits gives 2^k distinct top-k prefixes.
        for seed in [0u32, 1, 0xdead_beef] {
            for k in 1..=8 {
                let mut seen = vec![false; 1 << k];
                for i in 0..(1u32 << k) {
                    let top = nested_scramble(i << (32 - k), seed) >> (32 - k);
                    assert!(!seen[top as usize]);
                    seen[top as usize] = true;
                }
            }
        }
    }

    #[test]
    fn shuffled_indices_are_permutations_of_the_samples() {
        for spp in [1u32, 5, 16, 48, 100] {
            let mut s = SobolSampler::new(9, spp);
            s.start_pixel_sample(1, 2, 0);
            let h = 12345;
            let mut seen = vec![false; spp as usize];
            for i in 0..spp {
                s.index = i;
                let j = s.shuffled_index(h);
                assert!(j < spp, "spp {spp}: {i} -> {j}");
                assert!(!seen[j as usize]);
                seen[j as usize] = true;
            }
        }
    }

    #[test]
    fn dimension_1_is_sobols_second_dimension() {
        // The first points of the second Sobol dimension in index (not Gray-code) order.
        let expect = [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875];
        for (i, e) in expect.iter().enumerate() {
            assert_eq!(sobol_dimension_1(i as u32) as f64 / 2f64.powi(32), *e);
        }
    }
}
