//! Weighted sums of the samples that reach a rectangle of pixels through the reconstruction
//! filter: the image is their ratio, the variance comes from the second moments. Tiles fill
//! blocks of their own (with a margin for the filter's reach) that are added to the whole film's
//! block in tile order after the parallel loop, so the sums, and the image, do not depend on the
//! number of threads.

use super::filter::Filter;
use crate::math::{Vec2, Vec3};

/// Film positions at most this far from the origin take [`FilmBlock::add_within_one`]'s path,
/// whose integer floor is exact there (and whose pixel indices fit an `i32`); NaN never does.
const PIXEL_LIMIT: f32 = (1 << 30) as f32;

/// `floor(x)` as an integer, for `|x| < 2^30`: truncation, one less for negative fractions.
#[inline]
fn floor_to_int(x: f32) -> i32 {
    let t = x as i32;
    t - ((t as f32) > x) as i32
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelSums {
    /// Sum of weight times value, per channel.
    pub wv: [f64; 3],
    /// Sum of weight times squared value, per channel.
    pub wv2: [f64; 3],
    pub w: f64,
    /// Sum of squared weights: the effective sample count is `w^2 / w2`.
    pub w2: f64,
}

impl PixelSums {
    #[inline]
    pub(crate) fn add(&mut self, v: Vec3, w: f32) {
        let (w, v) = (w as f64, v.as_dvec3());
        for (c, x) in v.to_array().into_iter().enumerate() {
            self.wv[c] += w * x;
            self.wv2[c] += w * x * x;
        }
        self.w += w;
        self.w2 += w * w;
    }

    fn merge(&mut self, o: &PixelSums) {
        for c in 0..3 {
            self.wv[c] += o.wv[c];
            self.wv2[c] += o.wv2[c];
        }
        self.w += o.w;
        self.w2 += o.w2;
    }

    /// The weighted mean of the samples.
    pub fn mean(&self) -> Vec3 {
        if self.w <= 0.0 {
            return Vec3::ZERO;
        }
        Vec3::new(
            (self.wv[0] / self.w) as f32,
            (self.wv[1] / self.w) as f32,
            (self.wv[2] / self.w) as f32,
        )
    }

    /// The variance of [`Self::mean`] as an estimate: the samples' weighted variance times
    /// `sum w^2 / (sum w)^2` (the variance of a weighted mean of independent samples).
    pub fn variance_of_mean(&self) -> Vec3 {
        if self.w <= 0.0 {
            return Vec3::ZERO;
        }
        let scale = self.w2 / (self.w * self.w);
        let var = |c: usize| {
            let m = self.wv[c] / self.w;
            ((self.wv2[c] / self.w - m * m).max(0.0) * scale) as f32
        };
        Vec3::new(var(0), var(1), var(2))
    }
}

/// The sums of pixels `x0..x0 + width` by `y0..y0 + height` (which may reach outside the image by
/// the filter's margin; the film ignores those).
#[derive(Clone, Debug)]
pub struct FilmBlock {
    pub x0: i32,
    pub y0: i32,
    pub width: u32,
    pub height: u32,
    pub sums: Vec<PixelSums>,
}

impl FilmBlock {
    pub fn new(x0: i32, y0: i32, width: u32, height: u32) -> Self {
        Self {
            x0,
            y0,
            width,
            height,
            sums: vec![PixelSums::default(); width as usize * height as usize],
        }
    }

    /// Adds a sample of value `v` at film position `p` (pixel `(i, j)` spans `[i, i+1) x [j,
    /// j+1)`) to every pixel of the block the filter reaches. A non-finite value (a numerical
    /// failure upstream) is counted as zero rather than poisoning the pixel; the caller counts it.
    #[inline]
    pub fn add_sample(&mut self, filter: &Filter, p: Vec2, v: Vec3) {
        let v = if v.is_finite() { v } else { Vec3::ZERO };
        if filter.is_pixel_box() {
            let (i, j) = (p.x.floor() as i32 - self.x0, p.y.floor() as i32 - self.y0);
            if i >= 0 && j >= 0 && (i as u32) < self.width && (j as u32) < self.height {
                self.sums[j as usize * self.width as usize + i as usize].add(v, 1.0);
            }
            return;
        }
        let r = filter.radius();
        if r <= 1.0 && p.x.abs() < PIXEL_LIMIT && p.y.abs() < PIXEL_LIMIT {
            self.add_within_one(filter, p, v);
            return;
        }
        // Pixel centres c = i + 0.5 with |p - c| < r.
        let lo = |x: f32, o: i32| ((x - 0.5 - r).floor() as i32 + 1 - o).max(0);
        let hi = |x: f32, o: i32, n: u32| ((x - 0.5 + r).ceil() as i32 - 1 - o).min(n as i32 - 1);
        let (i0, i1) = (lo(p.x, self.x0), hi(p.x, self.x0, self.width));
        let (j0, j1) = (lo(p.y, self.y0), hi(p.y, self.y0, self.height));
        for j in j0..=j1 {
            let wy = filter.eval(p.y - ((j + self.y0) as f32 + 0.5));
            if wy == 0.0 {
                continue;
            }
            for i in i0..=i1 {
                let w = wy * filter.eval(p.x - ((i + self.x0) as f32 + 0.5));
                if w != 0.0 {
                    self.sums[j as usize * self.width as usize + i as usize].add(v, w);
                }
            }
        }
    }

    /// [`Self::add_sample`] for a filter of radius at most 1 (Mitsuba's default tent, the box of
    /// radius 1/2): the only pixel centres nearer than 1 on an axis are the one at or left of
    /// `p` and the next, so the splat is these 2x2 pixels' weights, without the general loop's
    /// bounds (a floor and a ceiling each, library calls without SSE4.1) and index arithmetic.
    /// Every filter's weight is zero at and beyond its radius, so the pixels left out weighed
    /// nothing; the weights are computed as the loop computes them, and zeros skipped as there.
    #[inline]
    fn add_within_one(&mut self, filter: &Filter, p: Vec2, v: Vec3) {
        let (ix, iy) = (floor_to_int(p.x - 0.5), floor_to_int(p.y - 0.5));
        let wx = [0, 1].map(|k| filter.eval(p.x - ((ix + k) as f32 + 0.5)));
        for dy in 0..2 {
            let j = iy + dy - self.y0;
            if j < 0 || j >= self.height as i32 {
                continue;
            }
            let wy = filter.eval(p.y - ((iy + dy) as f32 + 0.5));
            if wy == 0.0 {
                continue;
            }
            for (dx, wx) in (0..2).zip(wx) {
                let i = ix + dx - self.x0;
                let w = wy * wx;
                if i >= 0 && i < self.width as i32 && w != 0.0 {
                    self.sums[j as usize * self.width as usize + i as usize].add(v, w);
                }
            }
        }
    }

    /// Adds `other`'s sums where the blocks overlap.
    pub fn merge(&mut self, other: &FilmBlock) {
        for oj in 0..other.height as i32 {
            let j = oj + other.y0 - self.y0;
            if j < 0 || j >= self.height as i32 {
                continue;
            }
            for oi in 0..other.width as i32 {
                let i = oi + other.x0 - self.x0;
                if i < 0 || i >= self.width as i32 {
                    continue;
                }
                let o = &other.sums[(oj as u32 * other.width + oi as u32) as usize];
                self.sums[(j as u32 * self.width + i as u32) as usize].merge(o);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tent_splat_reaches_neighbours_with_its_weights() {
        let mut b = FilmBlock::new(0, 0, 3, 3);
        let tent = Filter::Tent { radius: 1.0 };
        b.add_sample(&tent, Vec2::new(1.5, 1.75), Vec3::ONE);
        let w = |i: usize, j: usize| b.sums[j * 3 + i].w;
        assert!((w(1, 1) - 0.75).abs() < 1e-6);
        assert!((w(1, 2) - 0.25).abs() < 1e-6);
        assert_eq!(w(0, 1), 0.0);
        assert_eq!(w(1, 0), 0.0);
    }

    /// The 2x2 splat of the filters of radius at most 1 adds what the general loop adds, bit for
    /// bit, at positions on and next to pixel edges and centres, inside and at the block's borders.
    #[test]
    fn the_splat_within_one_pixel_is_the_general_loop() {
        fn general(b: &mut FilmBlock, filter: &Filter, p: Vec2, v: Vec3) {
            let r = filter.radius();
            for j in 0..b.height as i32 {
                let wy = filter.eval(p.y - ((j + b.y0) as f32 + 0.5));
                for i in 0..b.width as i32 {
                    let w = wy * filter.eval(p.x - ((i + b.x0) as f32 + 0.5));
                    let near = (p.x - ((i + b.x0) as f32 + 0.5)).abs() < r
                        && (p.y - ((j + b.y0) as f32 + 0.5)).abs() < r;
                    if near && w != 0.0 {
                        b.sums[j as usize * b.width as usize + i as usize].add(v, w);
                    }
                }
            }
        }
        let filters = [
            Filter::Tent { radius: 1.0 },
            Filter::Tent { radius: 0.7 },
            Filter::Box { radius: 1.0 },
            Filter::Box { radius: 0.75 },
            Filter::Gaussian { stddev: 0.25 },
        ];
        let coords = [
            -1.5f32,
            -1.0,
            -0.5,
            -0.25,
            0.0,
            0.3,
            0.5,
            0.999_999_9,
            1.0,
            2.5,
            3.75,
            4.0,
            4.5,
        ];
        for filter in &filters {
            for &x in &coords {
                for &y in &coords {
                    let (p, v) = (Vec2::new(x, y), Vec3::new(1.0, 0.25, 3.0));
                    let mut fast = FilmBlock::new(-1, 0, 5, 4);
                    let mut slow = fast.clone();
                    fast.add_sample(filter, p, v);
                    general(&mut slow, filter, p, v);
                    assert_eq!(fast.sums, slow.sums, "{filter:?} at {p:?}");
                }
            }
        }
    }

    #[test]
    fn floor_to_int_is_floor() {
        for x in [
            -3.5f32,
            -3.0,
            -0.5,
            -1e-7,
            0.0,
            -0.0,
            1e-7,
            0.5,
            2.0,
            2.999_999_8,
            1e9,
            -1e9,
        ] {
            assert_eq!(floor_to_int(x), x.floor() as i32, "{x}");
        }
    }

    #[test]
    fn merged_tiles_equal_one_block() {
        let g = Filter::Gaussian { stddev: 0.5 };
        let mut whole = FilmBlock::new(0, 0, 8, 8);
        let mut left = FilmBlock::new(-2, -2, 8, 12);
        let mut right = FilmBlock::new(2, -2, 8, 12);
        for k in 0..200 {
            let p = Vec2::new((k * 37 % 800) as f32 / 100.0, (k * 53 % 800) as f32 / 100.0);
            let v = Vec3::splat(k as f32);
            whole.add_sample(&g, p, v);
            if p.x < 4.0 {
                left.add_sample(&g, p, v);
            } else {
                right.add_sample(&g, p, v);
            }
        }
        let mut merged = FilmBlock::new(0, 0, 8, 8);
        merged.merge(&left);
        merged.merge(&right);
        for (a, b) in whole.sums.iter().zip(&merged.sums) {
            assert!((a.w - b.w).abs() < 1e-9 && (a.wv[0] - b.wv[0]).abs() < 1e-6);
        }
    }

    #[test]
    fn variance_of_the_mean_of_equal_weights_is_sample_variance_over_n() {
        let mut s = PixelSums::default();
        for x in [1.0f32, 2.0, 3.0, 4.0] {
            s.add(Vec3::splat(x), 1.0);
        }
        assert_eq!(s.mean(), Vec3::splat(2.5));
        // Population variance 1.25, over 4 samples.
        assert!((s.variance_of_mean().x - 1.25 / 4.0).abs() < 1e-6);
    }
}
