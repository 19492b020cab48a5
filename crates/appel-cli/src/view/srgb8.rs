//! Linear radiance to 8-bit sRGB for the viewer's frames, exactly as `srgb_encode` but without a
//! `powf` per channel: that costs about as much as encoding the frame as JPEG (a 640x480 frame has
//! 921,600 channels). A 65,536-entry table over [0, 1] gives the code near a value: the steepest
//! part of the sRGB curve (12.92 x 255 codes per unit, near 0) moves by 0.05 codes per entry, so
//! the true code is the table's or the next one, which one comparison with the least value of
//! the next code decides.

use appel::output::image::srgb_encode;
use std::sync::OnceLock;

const STEPS: usize = 1 << 16;

pub struct Table {
    /// `coarse[i]`: the code of the value one step below `i / (STEPS - 1)` (the step below, so
    /// that a product `x * (STEPS - 1)` rounded up still starts at or below the true code).
    coarse: Vec<u8>,
    /// `first[k]`: the least f32 whose code is `k` or more (`first[256]` is past every value).
    first: [f32; 257],
}

pub fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| {
        let scale = (STEPS - 1) as f32;
        let coarse = (0..STEPS)
            .map(|i| srgb_encode((i as f32 - 1.0).max(0.0) / scale))
            .collect();
        let mut first = [f32::INFINITY; 257];
        first[0] = f32::NEG_INFINITY;
        for (k, slot) in first.iter_mut().enumerate().take(256).skip(1) {
            // Bisection on the bit patterns of the floats in [0, 1], ordered as their bits are.
            let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if srgb_encode(f32::from_bits(mid)) as usize >= k {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            *slot = f32::from_bits(lo);
        }
        Table { coarse, first }
    })
}

impl Table {
    /// The sRGB code of linear value `x`, equal to `srgb_encode(x)` (NaN gives 0: it fails every
    /// comparison and its cast to an index is 0).
    #[inline]
    pub fn encode(&self, x: f32) -> u8 {
        let c = x.clamp(0.0, 1.0);
        let k = self.coarse[(c * (STEPS - 1) as f32) as usize];
        k + (c >= self.first[k as usize + 1]) as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_srgb_encode_everywhere_it_changes() {
        let t = table();
        // Around every code's least value, and on a dense sweep, negatives, beyond 1 and NaN.
        let mut values: Vec<f32> = vec![f32::NAN, -1.0, -0.0, 0.0, 1.0, 2.0, f32::INFINITY];
        for &x in &t.first[1..256] {
            let b = x.to_bits();
            values.extend([b - 1, b, b + 1].map(f32::from_bits));
        }
        values.extend((0..=200_000).map(|i| i as f32 / 200_000.0));
        for x in values {
            assert_eq!(t.encode(x), srgb_encode(x), "{x:e}");
        }
        // Every code is reached.
        let reached: std::collections::BTreeSet<u8> =
            t.first[..256].iter().map(|&x| t.encode(x)).collect();
        assert_eq!(reached.len(), 256);
    }
}
