//! Value noise summed over octaves (fractional Brownian motion; Musgrave's "fBm" in Ebert et al.,
//! "Texturing and Modeling", 1994): smooth, seedable, and the same on every platform because it
//! uses only integer hashing and f32 arithmetic in a fixed order.

/// A hash of a lattice point and the seed to `[0, 1)` (SplitMix64's finalizer).
fn lattice(ix: i32, iz: i32, seed: u64) -> f32 {
    let mut z = seed
        ^ (ix as u32 as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)
        ^ (iz as u32 as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32
}

/// Smooth value noise in `[0, 1)`: the lattice values blended with the quintic fade.
pub fn value_noise(x: f32, z: f32, seed: u64) -> f32 {
    let (fx, fz) = (x.floor(), z.floor());
    let (ix, iz) = (fx as i32, fz as i32);
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v) = (fade(x - fx), fade(z - fz));
    let a = lattice(ix, iz, seed);
    let b = lattice(ix + 1, iz, seed);
    let c = lattice(ix, iz + 1, seed);
    let d = lattice(ix + 1, iz + 1, seed);
    let ab = a + (b - a) * u;
    let cd = c + (d - c) * u;
    ab + (cd - ab) * v
}

/// `octaves` of value noise, each twice the frequency and half the amplitude of the last,
/// normalized to `[0, 1)`.
pub fn fbm(x: f32, z: f32, octaves: u32, seed: u64) -> f32 {
    let (mut sum, mut amplitude, mut total, mut f) = (0.0, 1.0, 0.0, 1.0);
    for o in 0..octaves {
        sum += amplitude * value_noise(x * f, z * f, seed.wrapping_add(o as u64));
        total += amplitude;
        amplitude *= 0.5;
        f *= 2.0;
    }
    sum / total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_continuous_bounded_and_seeded() {
        let mut differs = false;
        for i in 0..1000 {
            let x = i as f32 * 0.0137 - 3.0;
            let n = fbm(x, 0.5 * x, 5, 9);
            assert!((0.0..1.0).contains(&n));
            assert!((fbm(x + 1e-4, 0.5 * x, 5, 9) - n).abs() < 1e-2);
            differs |= fbm(x, 0.5 * x, 5, 10) != n;
        }
        assert!(differs, "the seed changes the field");
    }
}
