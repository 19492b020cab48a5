//! Rendering: camera rays over image tiles in parallel, an integrator per ray, results on a film.

mod film;
pub mod film_block;
pub mod filter;
pub mod integrator;
pub mod optics;
pub mod path;
pub mod progressive;
pub mod sampler;
mod window;

pub use film::{Film, PixelAov, MISS_ID};
pub use integrator::{surface_hit, Integrator, Raycast, SurfaceHit, Whitted};
pub use window::Window;

use crate::accel::bvh::PACKET;
use crate::accel::TraversalStats;
use crate::error::{Error, Result};
use crate::math::Ray;
use crate::math::Vec3;
use crate::scene::description::SamplerName;
use crate::scene::SceneHit;
use crate::scene::{IntegratorKind, Scene};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Side of the square tiles the image is cut into; each tile is one parallel task.
pub const TILE_SIZE: u32 = 16;

/// Rays cast, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub camera: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.reflection + self.refraction
    }

    fn merge(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
    }
}

/// Per-thread tallies carried along every ray.
#[derive(Clone, Copy, Debug, Default)]
pub struct TraceContext {
    pub rays: RayCounts,
    pub traversal: TraversalStats,
    /// Monte Carlo samples whose value was not finite (counted as zero).
    pub invalid_samples: u64,
}

/// What a render did.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderStats {
    pub time: Duration,
    pub rays: RayCounts,
    pub traversal: TraversalStats,
    /// Samples per pixel taken (fewer than asked when a time limit stopped the render).
    pub spp: u32,
    pub invalid_samples: u64,
}

impl RenderStats {
    pub(crate) fn merge(&mut self, ctx: &TraceContext) {
        self.rays.merge(&ctx.rays);
        self.traversal.merge(&ctx.traversal);
        self.invalid_samples += ctx.invalid_samples;
    }

    pub fn mrays_per_second(&self) -> f64 {
        self.rays.total() as f64 / self.time.as_secs_f64().max(1e-9) / 1e6
    }
}

/// How to render, beyond what the scene says.
#[derive(Default)]
pub struct RenderOptions<'a> {
    /// Called with the number of pixels finished so far, after each tile.
    pub progress: Option<&'a (dyn Fn(u64) + Sync)>,
    /// When set (Ctrl-C), the render stops after the tiles in flight and returns [`Error::Cancelled`].
    pub cancel: Option<&'a AtomicBool>,
    /// Monte Carlo integrators: stop after the pass during which this much time has passed.
    pub time_limit: Option<Duration>,
    /// Render only these pixels of the image (the film is the window's size): each is bit for
    /// bit the full render's, so windows rendered apart reassemble into it.
    pub window: Option<Window>,
}

/// Sub-pixel positions: sample 0 is the pixel centre (so `spp = 1` is exactly the convention's
/// centre ray, and AOVs describe the centre); the rest follow the R2 low-discrepancy sequence
/// (Roberts 2018), the same in every pixel, so the image is a pure function of the scene.
fn sample_offset(s: u32) -> (f32, f32) {
    const A1: f64 = 0.754_877_666_246_692_7;
    const A2: f64 = 0.569_840_290_998_053_2;
    let s = s as f64;
    ((0.5 + A1 * s).fract() as f32, (0.5 + A2 * s).fract() as f32)
}

/// Renders the scene with its own integrator on the current rayon thread pool. The result does not
/// depend on the number of threads: every pixel is computed alone, from the scene only.
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
    match scene.settings.integrator {
        IntegratorKind::Raycast => render_with(scene, &Raycast, options),
        IntegratorKind::Path => render_monte_carlo(
            scene,
            &path::PathTracer::new(
                scene.settings.max_depth,
                scene.settings.rr_depth,
                scene.settings.hide_emitters,
            ),
            options,
        ),
        IntegratorKind::Direct => render_monte_carlo(
            scene,
            &path::PathTracer::direct(scene.settings.hide_emitters),
            options,
        ),
        IntegratorKind::Whitted => render_with(
            scene,
            &Whitted {
                max_depth: scene.settings.max_depth.max(0) as u32,
            },
            options,
        ),
    }
}

/// A Monte Carlo integrator over the scene's sampler and filter, monomorphized for each.
fn render_monte_carlo<I: progressive::SampleIntegrator>(
    scene: &Scene,
    integrator: &I,
    options: &RenderOptions,
) -> Result<(Film, RenderStats)> {
    let s = &scene.settings;
    let p = progressive::Progressive {
        filter: filter::Filter::new(&s.filter),
        spp: s.spp,
        // With a time limit, passes of 1/16 of the samples (at least one) let the render stop
        // near the limit; without one, a single pass.
        pass_spp: if options.time_limit.is_some() {
            (s.spp / 16).max(1)
        } else {
            s.spp
        },
    };
    match s.sampler {
        SamplerName::Independent => progressive::render_progressive(
            scene,
            integrator,
            &sampler::IndependentSampler::new(s.seed),
            &p,
            options,
        ),
        SamplerName::Sobol => progressive::render_progressive(
            scene,
            integrator,
            &sampler::SobolSampler::new(s.seed, s.spp),
            &p,
            options,
        ),
    }
}

/// A finished tile: its pixels in row order, and what tracing them cost.
type TileResult = (Vec<(Vec3, PixelAov)>, TraceContext);

struct Tile {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
}

pub fn render_with<I: Integrator>(
    scene: &Scene,
    integrator: &I,
    options: &RenderOptions,
) -> Result<(Film, RenderStats)> {
    let start = Instant::now();
    // Pixels are independent here, so a window is tiled from its own corner.
    let win = Window::resolve(options.window, scene.camera.width, scene.camera.height)?;
    let (w, h) = (win.width(), win.height());
    let tiles: Vec<Tile> = (0..h.div_ceil(TILE_SIZE))
        .flat_map(|ty| {
            (0..w.div_ceil(TILE_SIZE)).map(move |tx| Tile {
                x0: win.x0 + tx * TILE_SIZE,
                y0: win.y0 + ty * TILE_SIZE,
                x1: win.x0 + ((tx + 1) * TILE_SIZE).min(w),
                y1: win.y0 + ((ty + 1) * TILE_SIZE).min(h),
            })
        })
        .collect();
    let done = std::sync::atomic::AtomicU64::new(0);
    let spp = scene.settings.spp.max(1);
    // The same sub-pixel offsets in every pixel: computed once, not twice per pixel (`fract` is a
    // library call on x86_64 without SSE4.1).
    let offsets: Vec<(f32, f32)> = (0..spp).map(sample_offset).collect();
    // Camera rays in packets where the structure has a packet path (the 8-wide BVH over more than
    // one leaf: a scene of one leaf, such as Whitted's, has nothing for a packet to share).
    let packets = scene.accel.has_packets();
    let results: Vec<Option<TileResult>> = tiles
        .par_iter()
        .map(|tile| {
            if options.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return None;
            }
            let mut ctx = TraceContext::default();
            let mut pixels =
                Vec::with_capacity(((tile.x1 - tile.x0) * (tile.y1 - tile.y0)) as usize);
            // The AOVs of sample 0 and its radiance.
            let shade = |ray: &Ray, hit: Option<SceneHit>, ctx: &mut TraceContext| {
                let hit = hit.map(|h| surface_hit(scene, ray, h));
                let aov = hit.as_ref().map_or(PixelAov::MISS, |h| {
                    let (shape_id, prim_id) = scene.geometry.source_ids(&h.hit);
                    PixelAov {
                        depth: h.hit.t,
                        normal: h.si.ns,
                        shape_id,
                        prim_id,
                        instance_id: h.hit.instance,
                    }
                });
                (integrator.radiance(scene, ray, hit.as_ref(), ctx), aov)
            };
            for y in tile.y0..tile.y1 {
                if spp == 1 && packets {
                    // One sample per pixel: the camera rays of up to eight neighbouring pixels
                    // traced as one packet (the same hits as one by one).
                    let (dx, dy) = offsets[0];
                    let mut x = tile.x0;
                    while x < tile.x1 {
                        let n = (tile.x1 - x).min(PACKET as u32) as usize;
                        let rays: [Ray; PACKET] = std::array::from_fn(|i| {
                            scene
                                .camera
                                .ray((x + i.min(n - 1) as u32) as f32 + dx, y as f32 + dy)
                        });
                        let mut hits = [None; PACKET];
                        scene.intersect_packet(
                            &rays[..n],
                            f32::INFINITY,
                            &mut hits,
                            &mut ctx.traversal,
                        );
                        ctx.rays.camera += n as u64;
                        for (ray, hit) in rays[..n].iter().zip(hits) {
                            pixels.push(shade(ray, hit, &mut ctx));
                        }
                        x += n as u32;
                    }
                    continue;
                }
                for x in tile.x0..tile.x1 {
                    let mut sum = Vec3::ZERO;
                    let mut aov = PixelAov::MISS;
                    for (s, &(dx, dy)) in offsets.iter().enumerate() {
                        let ray = scene.camera.ray(x as f32 + dx, y as f32 + dy);
                        ctx.rays.camera += 1;
                        let hit = scene.intersect(&ray, f32::INFINITY, &mut ctx.traversal);
                        let (radiance, sample_aov) = shade(&ray, hit, &mut ctx);
                        if s == 0 {
                            aov = sample_aov;
                        }
                        sum += radiance;
                    }
                    pixels.push((sum / spp as f32, aov));
                }
            }
            let n = pixels.len() as u64;
            let finished = done.fetch_add(n, Ordering::Relaxed) + n;
            if let Some(p) = options.progress {
                p(finished);
            }
            Some((pixels, ctx))
        })
        .collect();
    let mut stats = RenderStats::default();
    let mut done_tiles = Vec::with_capacity(results.len());
    for result in results {
        let Some((pixels, ctx)) = result else {
            return Err(Error::Cancelled);
        };
        stats.rays.merge(&ctx.rays);
        stats.traversal.merge(&ctx.traversal);
        done_tiles.push(pixels);
    }
    // The film is filled in row order from the tiles of each band of rows: one pass, no clearing.
    let mut film = Film::with_capacity(w, h);
    let tiles_per_row = w.div_ceil(TILE_SIZE).max(1) as usize;
    for (band, pixels) in tiles
        .chunks(tiles_per_row)
        .zip(done_tiles.chunks(tiles_per_row))
    {
        for row in 0..(band[0].y1 - band[0].y0) as usize {
            for (tile, pixels) in band.iter().zip(pixels) {
                let tw = (tile.x1 - tile.x0) as usize;
                film.extend(&pixels[row * tw..(row + 1) * tw]);
            }
        }
    }
    debug_assert_eq!(film.rgb.len(), w as usize * h as usize);
    stats.time = start.elapsed();
    Ok((film, stats))
}
