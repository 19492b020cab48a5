//! The render of integrators that trace from the lights: light paths in batches of `W x H`
//! (see `splat_film`), each batch cut into fixed chunks of consecutive path indices that are
//! traced in parallel, each into a list of its own splats; the lists are added to the film in
//! chunk order after each parallel pass.
//!
//! Determinism, as the camera-side render loop's: light path `k` of batch `b` draws its numbers
//! from the scene's sampler started at "pixel" `(k mod W, k div W)` and sample index `b` (a pure
//! function of path, dimension and seed); the chunks do not depend on the number of threads; and
//! the splats are summed in a fixed order. So the image is bit-identical for any thread count.

use super::integrator::centre_aov;
use super::render_loop::next_pass;
use super::sampler::{IndependentSampler, PixelPatternSampler, Sampler, SobolSampler};
use super::splat_film::{Splat, SplatFilm};
use super::{filter, Film, PixelAov, RenderOptions, RenderStats, TraceContext, Window};
use crate::description::SamplerName;
use crate::error::{Error, Result};
use crate::math::{offset_ray_origin, Ray, Vec3};
use crate::scene::Scene;
use crate::shading::emitter::EmitterRay;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Light paths per parallel work item: enough to outweigh the scheduling, few enough that a
/// batch of a small image still spreads over the threads.
const CHUNK: u32 = 256;

/// The most light paths of one parallel pass, whose splats are all held until the pass ends
/// (a few tens of bytes a path): without a time limit the render loop's pass is every sample.
const PATHS_PER_PASS: u64 = 1 << 20;

/// What traces one light path.
pub trait LightPathTracer: Sync {
    /// Working memory reused from one path to the next within a chunk (subpath vertices), so
    /// that tracing a path allocates nothing once the chunk is under way.
    type Scratch: Default;

    /// Traces the light path the sampler is started at, pushing its contributions to the film.
    fn trace<S: Sampler>(
        &self,
        scene: &Scene,
        sampler: &mut S,
        splats: &mut Vec<Splat>,
        scratch: &mut Self::Scratch,
        ctx: &mut TraceContext,
    );
}

/// The first segment of a light path: the emitter the scene's light picker chose (with
/// probability `pmf`), the ray its `sample_ray` drew (`emitted`, its weight not yet divided by
/// `pmf`) and that ray leaving the emitter's surface.
pub(super) struct LightPathStart {
    pub emitter: usize,
    pub pmf: f32,
    pub emitted: EmitterRay,
    pub ray: Ray,
}

/// Starts a light path from the sampler's next dimensions (one for the light, two for the point,
/// two for the direction, drawn whatever the outcome); `None` where the light has no chance or no
/// ray there. The start of `ptracer`'s paths and of `bdpt`'s light subpaths.
pub(super) fn start_light_path<S: Sampler>(
    scene: &Scene,
    sampler: &mut S,
) -> Option<LightPathStart> {
    let emitters = &scene.emitters;
    let (emitter, pmf) = emitters.picker.pick(sampler.get_1d());
    let (u_pos, u_dir) = (sampler.get_2d(), sampler.get_2d());
    if pmf <= 0.0 {
        return None;
    }
    let emitted = emitters.emitters[emitter].sample_ray(u_pos, u_dir, emitters.sphere)?;
    // Off the emitting surface by the point's error bound (lights that are no surface have none).
    let origin = if emitted.origin_error == Vec3::ZERO {
        emitted.origin
    } else {
        offset_ray_origin(
            emitted.origin,
            emitted.origin_error,
            emitted.normal,
            emitted.dir,
        )
    };
    Some(LightPathStart {
        emitter,
        pmf,
        ray: Ray::new(origin, emitted.dir),
        emitted,
    })
}

/// Renders the scene's `spp` batches of light paths (fewer if the time limit stops it first),
/// `batches_per_pass` at most in each parallel pass (0: no bound); the film holds the window's
/// pixels and AOVs, as the render loop's.
pub fn render_light_paths<T: LightPathTracer>(
    scene: &Scene,
    tracer: &T,
    batches_per_pass: u32,
    options: &RenderOptions,
) -> Result<(Film, RenderStats)> {
    let s = &scene.settings;
    match s.sampler {
        SamplerName::Independent => run(
            scene,
            tracer,
            &IndependentSampler::new(s.seed),
            batches_per_pass,
            options,
        ),
        SamplerName::Sobol => run(
            scene,
            tracer,
            &SobolSampler::new(s.seed, s.spp),
            batches_per_pass,
            options,
        ),
        SamplerName::PixelPattern => run(
            scene,
            tracer,
            &PixelPatternSampler::new(s.seed, s.spp),
            batches_per_pass,
            options,
        ),
    }
}

fn run<T: LightPathTracer, S: Sampler>(
    scene: &Scene,
    tracer: &T,
    sampler: &S,
    batches_per_pass: u32,
    options: &RenderOptions,
) -> Result<(Film, RenderStats)> {
    let start = Instant::now();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let window = options.window.unwrap_or(Window::full(w, h));
    window.check(w, h)?;
    let spp = scene.settings.spp.max(1);
    let mut film = SplatFilm::new(filter::Filter::new(&scene.settings.filter), w, h);
    let paths = w as u64 * h as u64;
    let chunks = paths.div_ceil(CHUNK as u64) as u32;
    let mut stats = RenderStats::default();
    let window_pixels = window.pixel_count();
    let done_paths = AtomicU64::new(0);
    let mut first = 0;
    while first < spp {
        let mut count = next_pass(spp, first, start.elapsed(), options.time_limit);
        if batches_per_pass > 0 {
            count = count.min(batches_per_pass);
        }
        count = count.min((PATHS_PER_PASS / paths).max(1) as u32);
        let results: Vec<Option<(Vec<Splat>, TraceContext)>> = (0..count * chunks)
            .into_par_iter()
            .map(|item| {
                if options.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                    return None;
                }
                let (batch, chunk) = (first + item / chunks, item % chunks);
                let mut sampler = sampler.clone();
                let mut ctx = TraceContext::default();
                let mut splats = Vec::new();
                let mut scratch = T::Scratch::default();
                let k0 = chunk as u64 * CHUNK as u64;
                let k1 = (k0 + CHUNK as u64).min(paths);
                for k in k0..k1 {
                    let (x, y) = ((k % w as u64) as u32, (k / w as u64) as u32);
                    sampler.start_pixel_sample(x, y, batch);
                    tracer.trace(scene, &mut sampler, &mut splats, &mut scratch, &mut ctx);
                }
                ctx.invalid_samples +=
                    splats.iter().filter(|s| !s.value.is_finite()).count() as u64;
                let n = k1 - k0;
                let done = done_paths.fetch_add(n, Ordering::Relaxed) + n;
                if let Some(progress) = options.progress {
                    progress(done * window_pixels / (paths * spp as u64).max(1));
                }
                Some((splats, ctx))
            })
            .collect();
        let mut results = results.into_iter();
        for _ in 0..count {
            let batch: Vec<(Vec<Splat>, TraceContext)> = results
                .by_ref()
                .take(chunks as usize)
                .collect::<Option<_>>()
                .ok_or(Error::Cancelled)?;
            for (_, ctx) in &batch {
                stats.merge(ctx);
            }
            film.add_batch(batch.iter().flat_map(|(s, _)| s));
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
    let aovs = if options.skip_aovs {
        Vec::new()
    } else {
        window_aovs(scene, window, &mut stats)
    };
    let film = film.film(&[]).crop(window, &aovs);
    if let Some(progress) = options.progress {
        progress(window_pixels);
    }
    stats.time = start.elapsed();
    Ok((film, stats))
}

/// What the ray through each pixel centre of the window sees first, in row order.
fn window_aovs(scene: &Scene, window: Window, stats: &mut RenderStats) -> Vec<PixelAov> {
    let rows: Vec<(Vec<PixelAov>, TraceContext)> = (window.y0..window.y1)
        .into_par_iter()
        .map(|y| {
            let mut ctx = TraceContext::default();
            let row = (window.x0..window.x1)
                .map(|x| centre_aov(scene, x, y, &mut ctx))
                .collect();
            (row, ctx)
        })
        .collect();
    let mut aovs = Vec::with_capacity(window.pixel_count() as usize);
    for (row, ctx) in rows {
        aovs.extend(row);
        stats.merge(&ctx);
    }
    aovs
}
