//! The one render loop of every integrator: passes of samples over image tiles in parallel, each
//! sample asked of the integrator (which traces its own camera ray from the sampler's film
//! position) and splatted through the reconstruction filter into the tile's block of weighted
//! sums; AOVs come with sample 0.
//!
//! When no sample reaches past its own pixel (the pixel box) and the render is one pass, each
//! tile finishes its own pixels instead (see `tile_film`): the same bits, without the window's
//! block of sums.
//!
//! Determinism: a sample's random numbers depend only on (pixel, sample index, dimension, seed)
//! (see `sampler`); the tile grid is anchored at the image's top-left corner whatever window is
//! rendered; each tile accumulates its samples in a fixed order into a block of its own; and the
//! blocks are added to the film in tile order after each parallel pass. So every pixel is the
//! same sequence of floating-point operations for any number of threads, for any assignment of
//! tiles to threads, and for a window of the image as for the whole.

use super::film_block::FilmBlock;
use super::filter::Filter;
use super::integrator::{FilmSample, PixelIntegrator, PixelRow};
use super::sampler::Sampler;
use super::tile_film::{TileFilm, TileRect, TileSamples};
use super::{Film, PixelAov, RenderOptions, RenderStats, TraceContext, Window, TILE_SIZE};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// What the loop needs beyond the scene and the integrator.
pub struct Passes {
    pub filter: Filter,
    /// Samples per pixel to reach.
    pub spp: u32,
}

/// Samples per pixel of the next pass. Without a time limit, all that remain in one pass. With
/// one, a first pass of one sample measures the cost of a sample, and each later pass takes what
/// the remaining time allows at that cost, at most twice the samples done so far, so the render
/// stops near the limit whatever a sample costs.
pub(super) fn next_pass(spp: u32, done: u32, elapsed: Duration, limit: Option<Duration>) -> u32 {
    let remaining = spp - done;
    let Some(limit) = limit else {
        return remaining;
    };
    if done == 0 {
        return 1;
    }
    let per_sample = elapsed.as_secs_f64() / done as f64;
    let affordable = (limit.saturating_sub(elapsed).as_secs_f64() / per_sample.max(1e-9)) as u64;
    (affordable.clamp(1, 2 * done as u64) as u32).min(remaining)
}

/// Pixels `x0..x1` by `y0..y1` of one tile, clipped to what is sampled.
#[derive(Clone, Copy, Debug)]
struct Tile {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
}

impl Tile {
    fn pixels(&self) -> usize {
        ((self.x1 - self.x0) * (self.y1 - self.y0)) as usize
    }

    fn rect(&self) -> TileRect {
        TileRect {
            x0: self.x0,
            y0: self.y0,
            width: self.x1 - self.x0,
            height: self.y1 - self.y0,
        }
    }
}

/// A tile's share of one pass.
struct TileResult {
    film: TileFilm,
    /// The tile's AOVs in row order (in the pass that holds sample 0; empty otherwise).
    aovs: Vec<PixelAov>,
    ctx: TraceContext,
}

/// The tiles of the image's fixed grid that meet `region`, clipped to it, in row order.
fn tiles_over(region: Window) -> Vec<Tile> {
    let (tx0, tx1) = (region.x0 / TILE_SIZE, region.x1.div_ceil(TILE_SIZE));
    let (ty0, ty1) = (region.y0 / TILE_SIZE, region.y1.div_ceil(TILE_SIZE));
    (ty0..ty1)
        .flat_map(|ty| {
            (tx0..tx1).map(move |tx| Tile {
                x0: (tx * TILE_SIZE).max(region.x0),
                y0: (ty * TILE_SIZE).max(region.y0),
                x1: ((tx + 1) * TILE_SIZE).min(region.x1),
                y1: ((ty + 1) * TILE_SIZE).min(region.y1),
            })
        })
        .filter(|t| t.x0 < t.x1 && t.y0 < t.y1)
        .collect()
}

pub fn render_loop<I: PixelIntegrator, S: Sampler>(
    scene: &Scene,
    integrator: &I,
    sampler: &S,
    p: &Passes,
    options: &RenderOptions,
) -> Result<(Film, RenderStats)> {
    // Tiles finish their own pixels when a sample reaches only its own pixel and there is one
    // pass (several would add to the same pixels).
    let spp = p.spp.max(1);
    let own_pixels = p.filter.is_pixel_box() && (spp == 1 || options.time_limit.is_none());
    render_loop_as(scene, integrator, sampler, p, options, own_pixels)
}

/// [`render_loop`], the tiles finishing their own pixels or not as `own_pixels` says (which needs
/// the pixel box and one pass).
fn render_loop_as<I: PixelIntegrator, S: Sampler>(
    scene: &Scene,
    integrator: &I,
    sampler: &S,
    p: &Passes,
    options: &RenderOptions,
    own_pixels: bool,
) -> Result<(Film, RenderStats)> {
    let start = Instant::now();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let window = options.window.unwrap_or(Window::full(w, h));
    window.check(w, h)?;
    // Pixels a sample can reach beyond its own: the filter's radius less the half pixel. The
    // window's pixels are the sums of the samples of the window grown by this much.
    let margin = (p.filter.radius() - 0.5).max(0.0).ceil() as u32;
    debug_assert!(!own_pixels || margin == 0);
    let sampled = Window {
        x0: window.x0.saturating_sub(margin),
        y0: window.y0.saturating_sub(margin),
        x1: (window.x1 + margin).min(w),
        y1: (window.y1 + margin).min(h),
    };
    let tiles = tiles_over(sampled);
    let (ww, wh) = (window.x1 - window.x0, window.y1 - window.y0);
    let spp = p.spp.max(1);
    let mut film = if own_pixels {
        let n = ww as usize * wh as usize;
        WindowFilm::Pixels {
            rgb: vec![Vec3::ZERO; n],
            variance: vec![Vec3::ZERO; n],
        }
    } else {
        WindowFilm::Sums(FilmBlock::new(window.x0 as i32, window.y0 as i32, ww, wh))
    };
    let mut aovs = if options.skip_aovs {
        Vec::new()
    } else {
        vec![PixelAov::MISS; ww as usize * wh as usize]
    };
    let mut stats = RenderStats::default();
    let samples_done = AtomicU64::new(0);
    let sampled_pixels = tiles.iter().map(|t| t.pixels() as u64).sum::<u64>();
    let window_pixels = ww as u64 * wh as u64;
    let mut first = 0;
    while first < spp {
        let count = next_pass(spp, first, start.elapsed(), options.time_limit);
        let results: Vec<Option<TileResult>> = tiles
            .par_iter()
            .map(|t| {
                if options.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                    return None;
                }
                let aovs = first == 0 && !options.skip_aovs;
                let r = render_tile(
                    scene, integrator, sampler, &p.filter, margin, own_pixels, t, first, count,
                    aovs,
                );
                let n = t.pixels() as u64 * count as u64;
                let done = samples_done.fetch_add(n, Ordering::Relaxed) + n;
                if let Some(progress) = options.progress {
                    // Progress in window pixels: the margin's samples count in proportion.
                    progress(done * window_pixels / (sampled_pixels * spp as u64).max(1));
                }
                Some(r)
            })
            .collect();
        for (t, r) in tiles.iter().zip(results) {
            let Some(r) = r else {
                return Err(Error::Cancelled);
            };
            film.add(window, t, &r.film);
            stats.merge(&r.ctx);
            if !r.aovs.is_empty() {
                copy_tile_rows(&mut aovs, window, t, &r.aovs);
            }
        }
        first += count;
        stats.spp = first;
        if options
            .time_limit
            .is_some_and(|limit| start.elapsed() >= limit)
        {
            break;
        }
    }
    if let Some(progress) = options.progress {
        progress(window_pixels);
    }
    let film = match film {
        WindowFilm::Sums(sums) => Film::from_sums(&sums, &aovs),
        WindowFilm::Pixels { rgb, variance } => Film::from_pixels(ww, wh, rgb, variance, &aovs),
    };
    stats.time = start.elapsed();
    Ok((film, stats))
}

/// The window's film while the tiles come in.
enum WindowFilm {
    /// Weighted sums, to which each tile's are added.
    Sums(FilmBlock),
    /// Final pixels, which each tile's are copied into.
    Pixels { rgb: Vec<Vec3>, variance: Vec<Vec3> },
}

impl WindowFilm {
    fn add(&mut self, window: Window, t: &Tile, tile: &TileFilm) {
        match (self, tile) {
            (WindowFilm::Sums(sums), TileFilm::Sums(block)) => sums.merge(block),
            (
                WindowFilm::Pixels { rgb, variance },
                TileFilm::Pixels {
                    rgb: r,
                    variance: v,
                },
            ) => {
                copy_tile_rows(rgb, window, t, r);
                if let Some(v) = v {
                    copy_tile_rows(variance, window, t, v);
                }
            }
            _ => unreachable!("tiles finish their pixels exactly when the window takes pixels"),
        }
    }
}

/// Samples `first..first + count` of every pixel of tile `t`, in a fixed order: rows from the
/// top, in each row the sample indices in turn, each over the row's pixels from the left; the
/// AOVs with sample 0 if `with_aovs` (which needs `first == 0`).
#[allow(clippy::too_many_arguments)]
fn render_tile<I: PixelIntegrator, S: Sampler>(
    scene: &Scene,
    integrator: &I,
    sampler: &S,
    filter: &Filter,
    margin: u32,
    own_pixels: bool,
    t: &Tile,
    first: u32,
    count: u32,
    with_aovs: bool,
) -> TileResult {
    let mut tile_samples = TileSamples::new(t.rect(), own_pixels, count, margin);
    let tw = (t.x1 - t.x0) as usize;
    let mut aovs = if with_aovs {
        vec![PixelAov::MISS; t.pixels()]
    } else {
        Vec::new()
    };
    let mut ctx = TraceContext::default();
    let mut sampler = sampler.clone();
    let mut samples = [FilmSample::default(); TILE_SIZE as usize];
    let samples = &mut samples[..tw];
    for y in t.y0..t.y1 {
        let row_aovs = (y - t.y0) as usize * tw;
        for index in first..first + count {
            let aov = (with_aovs && index == 0).then(|| &mut aovs[row_aovs..row_aovs + tw]);
            let row = PixelRow { x0: t.x0, y, index };
            integrator.sample_row(scene, row, &mut sampler, samples, aov, &mut ctx);
            for s in samples.iter() {
                if !s.radiance.is_finite() {
                    ctx.invalid_samples += 1;
                }
                tile_samples.add(filter, s);
            }
        }
    }
    TileResult {
        film: tile_samples.finish(t.rect(), own_pixels, filter),
        aovs,
        ctx,
    }
}

/// Copies the values of tile `t` (in its row order) that lie in the window into the window's
/// row-order list.
fn copy_tile_rows<T: Copy>(out: &mut [T], window: Window, t: &Tile, tile_values: &[T]) {
    let tw = (t.x1 - t.x0) as usize;
    let ww = (window.x1 - window.x0) as usize;
    let (x0, x1) = (t.x0.max(window.x0), t.x1.min(window.x1));
    if x0 >= x1 {
        return;
    }
    for y in t.y0.max(window.y0)..t.y1.min(window.y1) {
        let src = (y - t.y0) as usize * tw + (x0 - t.x0) as usize;
        let dst = (y - window.y0) as usize * ww + (x0 - window.x0) as usize;
        let n = (x1 - x0) as usize;
        out[dst..dst + n].copy_from_slice(&tile_values[src..src + n]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::description_from_str;
    use crate::description::parse::Syntax;
    use crate::render::sampler::{IndependentSampler, PixelPatternSampler};
    use crate::render::Whitted;
    use crate::scene::builtin::builtin_scene;
    use std::path::Path;
    use std::time::Duration;

    fn bits(v: &[Vec3]) -> Vec<[u32; 3]> {
        v.iter().map(|c| c.to_array().map(f32::to_bits)).collect()
    }

    /// Tiles that finish their own pixels make the film that the window's sums make, bit for bit:
    /// at one sample per pixel (the independent sampler's film positions near a pixel's far edge
    /// round into the next pixel about once in 30,000 at this width), at several, and in a window.
    #[test]
    fn tiles_finishing_their_pixels_make_the_film_of_the_sums() {
        let text = builtin_scene("whitted").unwrap();
        let mut d = description_from_str(text, Syntax::Toml, Path::new("whitted")).unwrap();
        d.camera.width = 1500;
        d.camera.height = 120;
        let scene = Scene::new(&d, Path::new(".")).unwrap();
        let whitted = Whitted { max_depth: 5 };
        let window = RenderOptions {
            window: Some(Window {
                x0: 7,
                y0: 9,
                x1: 1400,
                y1: 101,
            }),
            ..Default::default()
        };
        let mut strays = 0;
        for (spp, options) in [(1, RenderOptions::default()), (3, window)] {
            let p = Passes {
                filter: Filter::Box { radius: 0.5 },
                spp,
            };
            let independent = IndependentSampler::new(spp as u64 + 11);
            let pattern = PixelPatternSampler::new(3, spp);
            let films = [false, true].map(|own| {
                let a = render_loop_as(&scene, &whitted, &independent, &p, &options, own);
                let b = render_loop_as(&scene, &whitted, &pattern, &p, &options, own);
                (a.unwrap().0, b.unwrap().0)
            });
            for (sums, own) in [(&films[0].0, &films[1].0), (&films[0].1, &films[1].1)] {
                assert_eq!(bits(&sums.rgb), bits(&own.rgb));
                assert_eq!(bits(&sums.variance), bits(&own.variance));
                assert_eq!(sums.shape_id, own.shape_id);
                if spp == 1 {
                    strays += sums.rgb.iter().filter(|c| **c == Vec3::ZERO).count();
                }
            }
        }
        // The one-sample films had pixels left empty by a sample rounded into its neighbour.
        assert!(strays > 0);
    }

    /// Skipping the AOVs leaves them empty and changes no pixel, in both kinds of film.
    #[test]
    fn skipping_the_aovs_keeps_the_image() {
        let text = builtin_scene("whitted").unwrap();
        let mut d = description_from_str(text, Syntax::Toml, Path::new("whitted")).unwrap();
        d.camera.width = 90;
        d.camera.height = 70;
        let scene = Scene::new(&d, Path::new(".")).unwrap();
        let whitted = Whitted { max_depth: 5 };
        let p = Passes {
            filter: Filter::Box { radius: 0.5 },
            spp: 2,
        };
        let sampler = IndependentSampler::new(5);
        for own in [false, true] {
            let with = render_loop_as(
                &scene,
                &whitted,
                &sampler,
                &p,
                &RenderOptions::default(),
                own,
            )
            .unwrap()
            .0;
            let skip = RenderOptions {
                skip_aovs: true,
                ..Default::default()
            };
            let without = render_loop_as(&scene, &whitted, &sampler, &p, &skip, own)
                .unwrap()
                .0;
            assert_eq!(bits(&with.rgb), bits(&without.rgb));
            assert_eq!(bits(&with.variance), bits(&without.variance));
            assert_eq!(with.shape_id.len(), 90 * 70);
            assert!(with.shape_id.iter().any(|&id| id != crate::render::MISS_ID));
            assert!(without.depth.is_empty() && without.normal.is_empty());
            assert!(without.shape_id.is_empty() && without.prim_id.is_empty());
            assert!(without.instance_id.is_empty());
        }
    }

    const MS: Duration = Duration::from_millis(1);

    #[test]
    fn passes_fit_the_time_limit() {
        // No limit: everything at once.
        assert_eq!(next_pass(1000, 0, MS, None), 1000);
        assert_eq!(next_pass(1000, 10, MS, None), 990);
        let limit = Some(1000 * MS);
        // One sample first, to measure.
        assert_eq!(next_pass(1000, 0, Duration::ZERO, limit), 1);
        // 100 ms a sample with 900 ms left: doubling allows 2.
        assert_eq!(next_pass(1000, 1, 100 * MS, limit), 2);
        // 100 ms a sample with 200 ms left: 2, though doubling would allow 16.
        assert_eq!(next_pass(1000, 8, 800 * MS, limit), 2);
        // Cheap samples: doubling bounds the pass, and it never passes the count asked for.
        assert_eq!(next_pass(1000, 64, 64 * MS, limit), 128);
        assert_eq!(next_pass(100, 64, 64 * MS, limit), 36);
        // Little time left: still one sample, the loop stops after it.
        assert_eq!(next_pass(1000, 10, 999 * MS, limit), 1);
    }
}
