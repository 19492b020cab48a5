//! The film of estimates traced from the lights (light tracing, the light-image strategies of
//! bidirectional path tracing): contributions land anywhere on the image, so they are not
//! weighted means of a pixel's own samples but sums.
//!
//! Light paths come in batches of `W x H` (one "sample per pixel" each, as Mitsuba's `ptracer`
//! counts them). A batch's splats make one image, `S_j = sum f(p - c_j) v / F_j`, where `F_j` is
//! the filter's integral over the film around pixel `j`'s centre: the film is then the average of
//! the radiance weighted by the filter, `∫ f(p - c_j) L(p) dp / ∫ f(p - c_j) dp`, the quantity the
//! camera-side render loop's weighted means estimate (including at the image's borders, where
//! part of the filter lies outside). Each batch image is an independent, unbiased estimate of
//! the film, so the film is their mean and the variance of each pixel's mean is estimated from
//! their spread (the batch images are the samples of `PixelSums`, each of weight 1): honest
//! per-pixel variances, which a single sum of splats could not give.

use super::film_block::FilmBlock;
use super::filter::Filter;
use super::{Film, PixelAov};
use crate::math::{Vec2, Vec3};

/// A contribution at a film position (in pixels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    pub pos: Vec2,
    pub value: Vec3,
    /// 0: the image; `i > 0`: the film's further image `i - 1` (see [`SplatFilm::new`]).
    pub image: u16,
}

impl Splat {
    /// A contribution to the image.
    pub fn new(pos: Vec2, value: Vec3) -> Self {
        Splat {
            pos,
            value,
            image: 0,
        }
    }
}

/// The batches so far, and the image of the batch being added.
pub struct SplatFilm {
    filter: Filter,
    width: u32,
    height: u32,
    /// `∫₀^W f(x - c_i) dx` for each column `i`, and the same over rows: `F_j` is their product
    /// (the filter is separable).
    columns: Vec<f64>,
    rows: Vec<f64>,
    batch: Vec<[f64; 3]>,
    sums: FilmBlock,
    batches: u32,
    /// The further images' sums over all batches (means only: they are debugging images).
    further: Vec<Vec<[f64; 3]>>,
    /// The filter's weights over the columns a splat covers, evaluated once per splat rather
    /// than once per row.
    column_weights: Vec<f32>,
}

/// `∫ f(x - c) dx` over `[0, n]` for `c = i + 1/2`: the midpoint rule on the pieces between the
/// filter's kinks (its centre and the ends of its support), exact for the box and the tent,
/// within 1e-6 for the Gaussian.
fn filter_integrals(filter: &Filter, n: u32) -> Vec<f64> {
    let r = filter.radius() as f64;
    (0..n)
        .map(|i| {
            let c = i as f64 + 0.5;
            let (a, b) = ((c - r).max(0.0), (c + r).min(n as f64));
            let mut total = 0.0;
            for (lo, hi) in [(a, c.min(b)), (c.max(a), b)] {
                if hi <= lo {
                    continue;
                }
                let steps = 256;
                let h = (hi - lo) / steps as f64;
                for k in 0..steps {
                    let x = lo + (k as f64 + 0.5) * h;
                    total += filter.eval((x - c) as f32) as f64 * h;
                }
            }
            total
        })
        .collect()
}

impl SplatFilm {
    /// A film of the image and of `further` images beside it.
    pub fn new(filter: Filter, width: u32, height: u32, further: usize) -> Self {
        let pixels = width as usize * height as usize;
        SplatFilm {
            filter,
            width,
            height,
            columns: filter_integrals(&filter, width),
            rows: filter_integrals(&filter, height),
            batch: vec![[0.0; 3]; pixels],
            sums: FilmBlock::new(0, 0, width, height),
            batches: 0,
            further: vec![vec![[0.0; 3]; pixels]; further],
            column_weights: Vec::new(),
        }
    }

    /// How many batches the film holds.
    pub fn batches(&self) -> u32 {
        self.batches
    }

    /// Adds one batch: its splats in the order given (a fixed order, so that the sums do not
    /// depend on which thread traced which path).
    #[cfg(test)]
    pub fn add_batch<'a>(&mut self, splats: impl IntoIterator<Item = &'a Splat>) {
        self.begin_batch();
        self.add_splats(splats);
        self.end_batch();
    }

    /// Starts a batch, whose splats [`Self::add_splats`] adds in as many parts as it takes.
    pub fn begin_batch(&mut self) {
        self.batch.fill([0.0; 3]);
    }

    /// Adds splats of the batch under way, in the order given.
    pub fn add_splats<'a>(&mut self, splats: impl IntoIterator<Item = &'a Splat>) {
        for s in splats {
            self.splat(s);
        }
    }

    /// Ends the batch under way: its image is one more sample of each pixel.
    pub fn end_batch(&mut self) {
        for (sums, v) in self.sums.sums.iter_mut().zip(&self.batch) {
            sums.add(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32), 1.0);
        }
        self.batches += 1;
    }

    fn splat(&mut self, s: &Splat) {
        if !s.value.is_finite() || !s.pos.is_finite() {
            return;
        }
        let r = self.filter.radius();
        let (w, h) = (self.width as i64, self.height as i64);
        // Pixel centres c = i + 0.5 with |p - c| < r.
        let lo = |x: f32| (((x - 0.5 - r).floor() as i64) + 1).max(0);
        let hi = |x: f32, n: i64| (((x - 0.5 + r).ceil() as i64) - 1).min(n - 1);
        let v = s.value.as_dvec3();
        let (i0, i1) = (lo(s.pos.x), hi(s.pos.x, w));
        self.column_weights.clear();
        self.column_weights
            .extend((i0..=i1).map(|i| self.filter.eval(s.pos.x - (i as f32 + 0.5))));
        for j in lo(s.pos.y)..=hi(s.pos.y, h) {
            let wy = self.filter.eval(s.pos.y - (j as f32 + 0.5));
            if wy == 0.0 {
                continue;
            }
            let wy = wy as f64 / self.rows[j as usize];
            for (i, &wx) in (i0..=i1).zip(&self.column_weights) {
                if wx == 0.0 {
                    continue;
                }
                let wgt = wy * wx as f64 / self.columns[i as usize];
                let image = match s.image {
                    0 => &mut self.batch,
                    k => &mut self.further[k as usize - 1],
                };
                let px = &mut image[(j * w + i) as usize];
                px[0] += wgt * v.x;
                px[1] += wgt * v.y;
                px[2] += wgt * v.z;
            }
        }
    }

    /// The mean of the batches and its variance, with `aovs` (in row order, or empty).
    pub fn film(&self, aovs: &[PixelAov]) -> Film {
        Film::from_sums(&self.sums, aovs)
    }

    /// The mean of the batches of each further image, in row order.
    pub fn further_images(&self) -> Vec<Vec<Vec3>> {
        let n = self.batches.max(1) as f64;
        self.further
            .iter()
            .map(|image| {
                image
                    .iter()
                    .map(|v| Vec3::new((v[0] / n) as f32, (v[1] / n) as f32, (v[2] / n) as f32))
                    .collect()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A splat's weights over the pixels sum to one in the image's interior for filters whose
    /// copies at the pixel centres sum to their integral (the pixel box, the tent of radius one;
    /// the Gaussian to 1e-4); at a border each pixel's weight is divided by the part of
    /// the filter's integral inside the film (for the tent of radius 1 about the first column's
    /// centre, 7/8).
    #[test]
    fn splats_conserve_their_value_inside_the_film() {
        for filter in [
            Filter::Box { radius: 0.5 },
            Filter::Tent { radius: 1.0 },
            Filter::Gaussian { stddev: 0.5 },
        ] {
            let mut f = SplatFilm::new(filter, 12, 10, 0);
            let p = Splat::new(Vec2::new(5.3, 4.8), Vec3::new(1.0, 2.0, 3.0));
            f.add_batch([&p]);
            let total: f64 = f.batch.iter().map(|v| v[0]).sum();
            assert!((total - 1.0).abs() < 1e-4, "{filter:?}: {total}");
            let edge = Splat::new(Vec2::new(0.1, 4.8), Vec3::ONE);
            f.add_batch([&edge]);
            let expected = filter.eval(0.1 - 0.5) as f64 * filter.eval(4.8 - 4.5) as f64
                / (f.columns[0] * f.rows[4]);
            let got = f.batch[4 * 12][0];
            assert!(
                (got - expected).abs() < 1e-6,
                "{filter:?}: {got} vs {expected}"
            );
            if filter == (Filter::Tent { radius: 1.0 }) {
                assert!((f.columns[0] - 0.875).abs() < 1e-9, "{}", f.columns[0]);
            }
        }
    }

    /// The film is the mean of the batch images and its variance their spread over the count.
    #[test]
    fn batches_are_the_samples_of_each_pixel() {
        let mut f = SplatFilm::new(Filter::Box { radius: 0.5 }, 2, 1, 0);
        for v in [1.0f32, 2.0, 3.0, 6.0] {
            f.add_batch([&Splat::new(Vec2::new(0.5, 0.5), Vec3::splat(v))]);
        }
        let film = f.film(&[]);
        assert_eq!(film.rgb[0], Vec3::splat(3.0));
        // Population variance 3.5 over 4 batches; the empty pixel is exactly zero.
        assert!((film.variance[0].x - 3.5 / 4.0).abs() < 1e-6);
        assert_eq!((film.rgb[1], film.variance[1]), (Vec3::ZERO, Vec3::ZERO));
    }
}
