//! The render loop of Monte Carlo integrators: passes of samples over image tiles, each sample a
//! camera ray through a sampled film position, splatted through the reconstruction filter.
//!
//! Determinism: a sample's random numbers depend only on (pixel, sample index, dimension, seed)
//! (see `sampler`), each tile accumulates into its own block, and the blocks are added to the
//! film in tile order after each parallel pass, so the image is bit-identical for any number of
//! threads, and for any split into passes that covers the same sample indices in the same order.

use super::film_block::FilmBlock;
use super::filter::Filter;
use super::sampler::Sampler;
use super::{
    surface_hit, Film, PixelAov, RenderOptions, RenderStats, TraceContext, Window, TILE_SIZE,
};
use crate::error::{Error, Result};
use crate::math::{Ray, Vec2, Vec3};
use crate::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// An integrator that estimates the radiance along a camera ray from the sampler's numbers.
/// Monomorphized per sampler: no dynamic dispatch per ray.
pub trait SampleIntegrator: Sync {
    fn li<S: Sampler>(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut S,
        ctx: &mut TraceContext,
    ) -> Vec3;
}

/// What the progressive loop needs beyond the scene.
pub struct Progressive {
    pub filter: Filter,
    /// Samples per pixel to reach.
    pub spp: u32,
    /// Samples per pixel in one pass: the granularity at which a time limit is checked.
    pub pass_spp: u32,
}

struct Tile {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
}

pub fn render_progressive<I: SampleIntegrator, S: Sampler>(
    scene: &Scene,
    integrator: &I,
    sampler: &S,
    p: &Progressive,
    options: &RenderOptions,
) -> Result<(Film, RenderStats)> {
    let start = Instant::now();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let tiles: Vec<Tile> = (0..h.div_ceil(TILE_SIZE))
        .flat_map(|ty| {
            (0..w.div_ceil(TILE_SIZE)).map(move |tx| Tile {
                x0: tx * TILE_SIZE,
                y0: ty * TILE_SIZE,
                x1: ((tx + 1) * TILE_SIZE).min(w),
                y1: ((ty + 1) * TILE_SIZE).min(h),
            })
        })
        .collect();
    // Pixels a sample can reach beyond its own: the filter's radius less the half pixel.
    let margin = (p.filter.radius() - 0.5).max(0.0).ceil() as i32;
    // A window keeps the full image's tiles whose samples reach it, added in the same order, so
    // its pixels' sums are the full render's bit for bit.
    let win = Window::resolve(options.window, w, h)?;
    let tiles: Vec<Tile> = tiles
        .into_iter()
        .filter(|t| {
            win.overlaps(
                t.x0 as i32 - margin,
                t.y0 as i32 - margin,
                t.x1 as i32 + margin,
                t.y1 as i32 + margin,
            )
        })
        .collect();
    let (w, h) = (win.width(), win.height());
    let mut film_sums = FilmBlock::new(win.x0 as i32, win.y0 as i32, w, h);
    let mut stats = RenderStats::default();
    let aovs = centre_aovs(scene, win, options, &mut stats)?;
    let samples_done = AtomicU64::new(0);
    let pixel_count = w as u64 * h as u64;
    let spp = p.spp.max(1);
    let pass_spp = p.pass_spp.clamp(1, spp);
    let mut first = 0;
    while first < spp {
        let count = pass_spp.min(spp - first);
        let results: Vec<Option<(FilmBlock, TraceContext)>> = tiles
            .par_iter()
            .map(|t| {
                if options.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                    return None;
                }
                let mut block = FilmBlock::new(
                    t.x0 as i32 - margin,
                    t.y0 as i32 - margin,
                    t.x1 - t.x0 + 2 * margin as u32,
                    t.y1 - t.y0 + 2 * margin as u32,
                );
                let mut ctx = TraceContext::default();
                let mut sampler = sampler.clone();
                for y in t.y0..t.y1 {
                    for x in t.x0..t.x1 {
                        for index in first..first + count {
                            sampler.start_pixel_sample(x, y, index);
                            let film_pos = Vec2::new(x as f32, y as f32) + sampler.get_2d();
                            let ray = scene.camera.ray(film_pos.x, film_pos.y);
                            ctx.rays.camera += 1;
                            let li = integrator.li(scene, &ray, &mut sampler, &mut ctx);
                            if !li.is_finite() {
                                ctx.invalid_samples += 1;
                            }
                            block.add_sample(&p.filter, film_pos, li);
                        }
                    }
                }
                let n = ((t.x1 - t.x0) * (t.y1 - t.y0)) as u64 * count as u64;
                let done = samples_done.fetch_add(n, Ordering::Relaxed) + n;
                if let Some(progress) = options.progress {
                    progress(done / spp as u64);
                }
                Some((block, ctx))
            })
            .collect();
        for r in results {
            let Some((block, ctx)) = r else {
                return Err(Error::Cancelled);
            };
            film_sums.merge(&block);
            stats.merge(&ctx);
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
        progress(pixel_count);
    }
    let mut film = Film::with_capacity(w, h);
    let pixels: Vec<(Vec3, PixelAov)> = film_sums
        .sums
        .iter()
        .zip(aovs)
        .map(|(s, a)| (s.mean(), a))
        .collect();
    film.extend(&pixels);
    film.variance = film_sums
        .sums
        .iter()
        .map(|s| s.variance_of_mean())
        .collect();
    stats.time = start.elapsed();
    Ok((film, stats))
}

/// The AOVs of each pixel's centre ray (depth, normal, ids), in row order: the Monte Carlo
/// samples are jittered, and the AOVs describe the pixel's centre as raycast's do.
fn centre_aovs(
    scene: &Scene,
    win: Window,
    options: &RenderOptions,
    stats: &mut RenderStats,
) -> Result<Vec<PixelAov>> {
    let (w, h) = (win.x0..win.x1, win.y0..win.y1);
    let rows: Vec<Option<(Vec<PixelAov>, TraceContext)>> = h
        .into_par_iter()
        .map(|y| {
            if options.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return None;
            }
            let mut ctx = TraceContext::default();
            let row = w
                .clone()
                .map(|x| {
                    let ray = scene.camera.pixel_ray(x, y);
                    ctx.rays.camera += 1;
                    let hit = scene.intersect(&ray, f32::INFINITY, &mut ctx.traversal);
                    hit.map_or(PixelAov::MISS, |hit| {
                        let sh = surface_hit(scene, &ray, hit);
                        let (shape_id, prim_id) = scene.geometry.source_ids(&sh.hit);
                        PixelAov {
                            depth: sh.hit.t,
                            normal: sh.si.ns,
                            shape_id,
                            prim_id,
                            instance_id: sh.hit.instance,
                        }
                    })
                })
                .collect();
            Some((row, ctx))
        })
        .collect();
    let mut out = Vec::with_capacity(win.width() as usize * win.height() as usize);
    for r in rows {
        let Some((row, ctx)) = r else {
            return Err(Error::Cancelled);
        };
        out.extend(row);
        stats.merge(&ctx);
    }
    Ok(out)
}
