//! What one tile hands to the film. In general a block of weighted sums (with a margin for the
//! filter's reach) that the loop adds to the window's sums; but when no sample reaches outside its
//! tile (the pixel box) and the render is one pass, each pixel's sums are its tile's alone, so the
//! tile finishes its pixels itself: the same means and variances, without a window-sized block of
//! f64 sums to clear, add into and read back (64 bytes a pixel).
//!
//! At one sample per pixel the tile keeps its samples as they come and, when every one lies in its
//! own pixel, takes each as its pixel's value (variance zero) without summing: the weighted sums'
//! arithmetic gives the same bits (see [`one_sample_value`]).

use super::film_block::FilmBlock;
use super::filter::Filter;
use super::integrator::FilmSample;
use crate::math::Vec3;

/// Pixels `x0..x0 + width` by `y0..y0 + height` of a tile, as the tile accumulates them.
#[derive(Clone, Copy, Debug)]
pub struct TileRect {
    pub x0: u32,
    pub y0: u32,
    pub width: u32,
    pub height: u32,
}

/// A tile's samples while it is rendered.
pub enum TileSamples {
    /// Splatted through the filter into sums, as they come.
    Sums(FilmBlock),
    /// One sample per pixel, in the order the pixels were sampled (rows from the top, each from
    /// the left), kept for [`TileSamples::finish`].
    One(Vec<FilmSample>),
}

/// A finished tile.
pub enum TileFilm {
    /// Sums to add to the window's.
    Sums(FilmBlock),
    /// The mean of each of the tile's pixels and the variance of that mean, in row order
    /// (`variance` `None`: zero everywhere).
    Pixels {
        rgb: Vec<Vec3>,
        variance: Option<Vec<Vec3>>,
    },
}

impl TileSamples {
    /// `own_pixels`: the tile's pixels take no samples from other tiles (see the module
    /// documentation); `count`: samples per pixel in this pass; `margin`: the filter's reach past
    /// the tile, in pixels.
    pub fn new(tile: TileRect, own_pixels: bool, count: u32, margin: u32) -> Self {
        if own_pixels && count == 1 {
            return TileSamples::One(Vec::with_capacity((tile.width * tile.height) as usize));
        }
        TileSamples::Sums(FilmBlock::new(
            tile.x0 as i32 - margin as i32,
            tile.y0 as i32 - margin as i32,
            tile.width + 2 * margin,
            tile.height + 2 * margin,
        ))
    }

    #[inline]
    pub fn add(&mut self, filter: &Filter, s: &FilmSample) {
        match self {
            TileSamples::Sums(block) => block.add_sample(filter, s.pos, s.radiance),
            TileSamples::One(samples) => samples.push(*s),
        }
    }

    /// The tile as the film takes it: final pixels when `own_pixels` (as given to [`Self::new`]),
    /// sums otherwise.
    pub fn finish(self, tile: TileRect, own_pixels: bool, filter: &Filter) -> TileFilm {
        let block = match self {
            TileSamples::One(samples) => {
                if let Some(rgb) = one_sample_pixels(tile, &samples) {
                    return TileFilm::Pixels {
                        rgb,
                        variance: None,
                    };
                }
                // A sample rounded into a neighbouring pixel (a film position x + u with u just
                // below 1 can round to x + 1): the sums decide, as they would have.
                let mut block =
                    FilmBlock::new(tile.x0 as i32, tile.y0 as i32, tile.width, tile.height);
                for s in &samples {
                    block.add_sample(filter, s.pos, s.radiance);
                }
                block
            }
            TileSamples::Sums(block) => block,
        };
        if !own_pixels {
            return TileFilm::Sums(block);
        }
        TileFilm::Pixels {
            rgb: block.sums.iter().map(|s| s.mean()).collect(),
            variance: Some(block.sums.iter().map(|s| s.variance_of_mean()).collect()),
        }
    }
}

/// The pixels of a tile whose samples (one per pixel, in row order) each lie in their own pixel,
/// or `None` if one does not.
fn one_sample_pixels(tile: TileRect, samples: &[FilmSample]) -> Option<Vec<Vec3>> {
    let mut rgb = Vec::with_capacity(samples.len());
    let mut s = samples.iter();
    for y in tile.y0..tile.y0 + tile.height {
        let (y_lo, y_hi) = (y as f32, (y + 1) as f32);
        for x in tile.x0..tile.x0 + tile.width {
            let sample = s.next()?;
            let p = sample.pos;
            // `floor(p) == (x, y)`, exactly (x, y < 2^24 are floats), false for NaN.
            let own = x as f32 <= p.x && p.x < (x + 1) as f32 && y_lo <= p.y && p.y < y_hi;
            if !own {
                return None;
            }
            rgb.push(one_sample_value(sample.radiance));
        }
    }
    Some(rgb)
}

/// The mean of a pixel's weighted sums after one sample `v` of weight 1, without them: a
/// non-finite `v` counts as zero (as [`FilmBlock::add_sample`] takes it), and `(0 + 1 v) / 1` in
/// f64 is `v` exactly but for the sign of a zero (`0 + -0 = +0`), which adding `+0` reproduces.
/// The variance is zero: `v^2` is exact in f64, so `v^2 / 1 - v^2 = 0`.
#[inline]
pub fn one_sample_value(v: Vec3) -> Vec3 {
    if v.is_finite() {
        v + Vec3::ZERO
    } else {
        Vec3::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec2;

    const TILE: TileRect = TileRect {
        x0: 3,
        y0: 5,
        width: 4,
        height: 2,
    };

    /// One sample in the middle of each of the tile's pixels, of value `value(i)`.
    fn centred(value: impl Fn(usize) -> Vec3) -> Vec<FilmSample> {
        (0..8)
            .map(|i| FilmSample {
                pos: Vec2::new(
                    (TILE.x0 + i as u32 % 4) as f32 + 0.5,
                    (TILE.y0 + i as u32 / 4) as f32 + 0.5,
                ),
                radiance: value(i),
            })
            .collect()
    }

    /// The tile's pixels as the window's sums would make them: a block over the tile, added to a
    /// zeroed block, then the means and variances.
    fn through_sums(samples: &[FilmSample]) -> (Vec<Vec3>, Vec<Vec3>) {
        let pixel_box = Filter::Box { radius: 0.5 };
        let mut tile = FilmBlock::new(TILE.x0 as i32, TILE.y0 as i32, TILE.width, TILE.height);
        for s in samples {
            tile.add_sample(&pixel_box, s.pos, s.radiance);
        }
        let mut window = FilmBlock::new(0, 0, 16, 16);
        window.merge(&tile);
        let mut rgb = vec![];
        let mut var = vec![];
        for y in TILE.y0..TILE.y0 + TILE.height {
            for x in TILE.x0..TILE.x0 + TILE.width {
                let s = &window.sums[(y * 16 + x) as usize];
                rgb.push(s.mean());
                var.push(s.variance_of_mean());
            }
        }
        (rgb, var)
    }

    fn finished(samples: Vec<FilmSample>) -> (Vec<Vec3>, Vec<Vec3>) {
        let pixel_box = Filter::Box { radius: 0.5 };
        match TileSamples::One(samples).finish(TILE, true, &pixel_box) {
            TileFilm::Pixels { rgb, variance } => {
                let n = rgb.len();
                (rgb, variance.unwrap_or(vec![Vec3::ZERO; n]))
            }
            TileFilm::Sums(_) => panic!("a tile of its own pixels finishes them"),
        }
    }

    fn bits(v: &[Vec3]) -> Vec<[u32; 3]> {
        v.iter().map(|c| c.to_array().map(f32::to_bits)).collect()
    }

    #[test]
    fn one_sample_pixels_are_the_sums_bit_for_bit() {
        let awkward = [
            -0.0,
            0.0,
            1e-45,
            -3.3e38,
            3.4e38,
            0.1,
            f32::NAN,
            f32::INFINITY,
            -f32::INFINITY,
            16777217.0,
            -2.5,
            7.0e-39,
        ];
        let samples = centred(|i| {
            Vec3::new(
                awkward[i],
                awkward[(i + 3) % awkward.len()],
                awkward[(i + 7) % awkward.len()],
            )
        });
        let fast = finished(samples.clone());
        let sums = through_sums(&samples);
        assert_eq!(bits(&fast.0), bits(&sums.0));
        assert_eq!(bits(&fast.1), bits(&sums.1));
        // Minus zero came out as plus zero, as the sums make it.
        assert_eq!(fast.0[0].x.to_bits(), 0);
    }

    #[test]
    fn a_sample_rounded_into_its_neighbour_goes_through_the_sums() {
        let mut samples = centred(|i| Vec3::splat(i as f32 + 1.0));
        // Pixel (3, 5)'s sample lands in (4, 5), which then holds two samples (a variance) and
        // leaves (3, 5) empty (black); pixel (6, 6)'s leaves the tile and is lost.
        samples[0].pos.x = 4.0;
        samples[7].pos.y = 7.0;
        assert!(one_sample_pixels(TILE, &samples).is_none());
        let (rgb, var) = finished(samples.clone());
        let sums = through_sums(&samples);
        assert_eq!(bits(&rgb), bits(&sums.0));
        assert_eq!(bits(&var), bits(&sums.1));
        assert_eq!(rgb[0], Vec3::ZERO);
        assert_eq!(rgb[1], Vec3::splat(1.5));
        assert!(var[1].x > 0.0);
        assert_eq!(rgb[7], Vec3::ZERO);
    }

    #[test]
    fn pixel_edges_belong_to_the_pixel_they_start() {
        let mut samples = centred(|_| Vec3::ONE);
        samples[1].pos = Vec2::new(4.0, 5.0);
        assert!(one_sample_pixels(TILE, &samples).is_some());
        samples[1].pos = Vec2::new(4.0, 6.0);
        assert!(one_sample_pixels(TILE, &samples).is_none());
        samples[1].pos = Vec2::new(f32::NAN, 5.5);
        assert!(one_sample_pixels(TILE, &samples).is_none());
    }
}
