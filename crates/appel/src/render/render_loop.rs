//! The one render loop of every integrator: passes of samples over image tiles in parallel, each
//! sample asked of the integrator (which traces its own camera ray from the sampler's film
//! position) and splatted through the reconstruction filter into the tile's block of weighted
//! sums; AOVs come with sample 0.
//!
//! Determinism: a sample's random numbers depend only on (pixel, sample index, dimension, seed)
//! (see `sampler`); the tile grid is anchored at the image's top-left corner whatever window is
//! rendered; each tile accumulates its samples in a fixed order into a block of its own; and the
//! blocks are added to the film in tile order after each parallel pass. So every pixel is the
//! same sequence of floating-point operations for any number of threads, for any assignment of
//! tiles to threads, and for a window of the image as for the whole.

use super::film_block::FilmBlock;
use super::filter::Filter;
use super::integrator::{FilmSample, Integrator, PixelRow};
use super::sampler::Sampler;
use super::{Film, PixelAov, RenderOptions, RenderStats, TraceContext, Window, TILE_SIZE};
use crate::error::{Error, Result};
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
fn next_pass(spp: u32, done: u32, elapsed: Duration, limit: Option<Duration>) -> u32 {
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
}

/// A tile's share of one pass.
struct TileResult {
    block: FilmBlock,
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

pub fn render_loop<I: Integrator, S: Sampler>(
    scene: &Scene,
    integrator: &I,
    sampler: &S,
    p: &Passes,
    options: &RenderOptions,
) -> Result<(Film, RenderStats)> {
    let start = Instant::now();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let window = options.window.unwrap_or(Window::full(w, h));
    window.check(w, h)?;
    // Pixels a sample can reach beyond its own: the filter's radius less the half pixel. The
    // window's pixels are the sums of the samples of the window grown by this much.
    let margin = (p.filter.radius() - 0.5).max(0.0).ceil() as u32;
    let sampled = Window {
        x0: window.x0.saturating_sub(margin),
        y0: window.y0.saturating_sub(margin),
        x1: (window.x1 + margin).min(w),
        y1: (window.y1 + margin).min(h),
    };
    let tiles = tiles_over(sampled);
    let (ww, wh) = (window.x1 - window.x0, window.y1 - window.y0);
    let mut sums = FilmBlock::new(window.x0 as i32, window.y0 as i32, ww, wh);
    let mut aovs = vec![PixelAov::MISS; ww as usize * wh as usize];
    let mut stats = RenderStats::default();
    let samples_done = AtomicU64::new(0);
    let spp = p.spp.max(1);
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
                let r = render_tile(
                    scene, integrator, sampler, &p.filter, margin, t, first, count,
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
            sums.merge(&r.block);
            stats.merge(&r.ctx);
            if !r.aovs.is_empty() {
                copy_aovs(&mut aovs, window, t, &r.aovs);
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
    let film = Film::from_sums(&sums, &aovs);
    stats.time = start.elapsed();
    Ok((film, stats))
}

/// Samples `first..first + count` of every pixel of tile `t`, in a fixed order: rows from the
/// top, in each row the sample indices in turn, each over the row's pixels from the left.
#[allow(clippy::too_many_arguments)]
fn render_tile<I: Integrator, S: Sampler>(
    scene: &Scene,
    integrator: &I,
    sampler: &S,
    filter: &Filter,
    margin: u32,
    t: &Tile,
    first: u32,
    count: u32,
) -> TileResult {
    let mut block = FilmBlock::new(
        t.x0 as i32 - margin as i32,
        t.y0 as i32 - margin as i32,
        t.x1 - t.x0 + 2 * margin,
        t.y1 - t.y0 + 2 * margin,
    );
    let tw = (t.x1 - t.x0) as usize;
    let mut aovs = if first == 0 {
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
            let aov = (index == 0).then(|| &mut aovs[row_aovs..row_aovs + tw]);
            let row = PixelRow { x0: t.x0, y, index };
            integrator.sample_row(scene, row, &mut sampler, samples, aov, &mut ctx);
            for s in samples.iter() {
                if !s.radiance.is_finite() {
                    ctx.invalid_samples += 1;
                }
                block.add_sample(filter, s.pos, s.radiance);
            }
        }
    }
    TileResult { block, aovs, ctx }
}

/// Copies the AOVs of tile `t` that lie in the window into the window's row-order list.
fn copy_aovs(out: &mut [PixelAov], window: Window, t: &Tile, tile_aovs: &[PixelAov]) {
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
        out[dst..dst + n].copy_from_slice(&tile_aovs[src..src + n]);
    }
}

#[cfg(test)]
mod tests {
    use super::next_pass;
    use std::time::Duration;

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
