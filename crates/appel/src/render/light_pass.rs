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
use super::path::{intersect_through_masks, RR_MAX_PROBABILITY};
use super::render_loop::next_pass;
use super::sampler::{IndependentSampler, PixelPatternSampler, Sampler, SobolSampler};
use super::splat_film::{Splat, SplatFilm};
use super::{filter, Channel, Film, PixelAov, RenderOptions, RenderStats, TraceContext, Window};
use crate::description::SamplerName;
use crate::error::{Error, Result};
use crate::geometry::SurfaceInteraction;
use crate::math::{offset_ray_origin, Ray, Vec3};
use crate::scene::Scene;
use crate::shading::bsdf::BsdfFlags;
use crate::shading::emitter::EmitterRay;
use crate::shading::frame::ShadingFrame;
use crate::shading::material::{Material, SurfaceBsdf, SurfacePoint};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Light paths per parallel work item: enough to outweigh the scheduling, few enough that a
/// batch of a small image still spreads over the threads.
const CHUNK: u32 = 256;

/// The most light paths of one parallel pass, whose splats are all held until the pass ends
/// (a few tens of bytes a path): without a time limit the render loop's pass is every sample.
/// A batch larger than this goes in several passes.
pub(super) const PATHS_PER_PASS: u64 = 1 << 20;

/// What traces one light path.
pub trait LightPathTracer: Sync {
    /// Working memory reused from one path to the next within a chunk (subpath vertices), so
    /// that tracing a path allocates nothing once the chunk is under way.
    type Scratch: Default;

    /// Traces the light path the sampler is started at (at `pixel`, whose stream of numbers it
    /// draws), pushing its contributions to the film.
    fn trace<S: Sampler>(
        &self,
        scene: &Scene,
        pixel: (u32, u32),
        sampler: &mut S,
        splats: &mut Vec<Splat>,
        scratch: &mut Self::Scratch,
        ctx: &mut TraceContext,
    );

    /// The names of the film's further images (EXR layers, each written as `NAME.R/G/B`) that
    /// splats with `image > 0` land on; none by default.
    fn further_images(&self) -> Vec<String> {
        Vec::new()
    }

    /// The most paths traced in one parallel pass, whose splats are held until it ends.
    fn paths_per_pass(&self) -> u64 {
        PATHS_PER_PASS
    }
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

/// A light path between its vertices: the ray leaving the last one, the importance it carries
/// (the emitted weight over the light's choice, times each scattering's), the product of the
/// crossings' relative IORs and the vertices so far (the light's point is the first).
pub(super) struct LightPath {
    pub ray: Ray,
    pub throughput: Vec3,
    pub eta: f32,
    pub depth: u32,
}

/// A surface a light path reached: its interaction, shading frame and BSDF, and the direction
/// toward the previous vertex (in the world and in the frame) with its geometric cosine.
pub(super) struct LightVertex {
    pub si: SurfaceInteraction,
    pub frame: ShadingFrame,
    pub bsdf: SurfaceBsdf,
    pub w_prev: Vec3,
    pub prev_local: Vec3,
    pub cos_g_prev: f32,
}

impl LightVertex {
    /// Light arriving on the side the shading normal does not see leaks through it: the path
    /// ends there.
    pub fn leaks(&self) -> bool {
        self.cos_g_prev * self.prev_local.z <= 0.0
    }
}

impl LightPath {
    pub fn new(start: &LightPathStart) -> Self {
        LightPath {
            ray: start.ray,
            throughput: start.emitted.weight / start.pmf,
            eta: 1.0,
            depth: 1,
        }
    }

    /// The surface the path's ray reaches next (through masks), with its BSDF; `None` where the
    /// ray leaves the scene.
    pub fn next_vertex<S: Sampler>(
        &self,
        scene: &Scene,
        sampler: &mut S,
        ctx: &mut TraceContext,
    ) -> Option<LightVertex> {
        let h = intersect_through_masks(scene, &self.ray, sampler, ctx)?;
        let si = h.si;
        let w_prev = -self.ray.dir;
        let frame = ShadingFrame::from_normal_tangent(si.ns, si.shading_tangent());
        let at = SurfacePoint::new(&si, &frame, w_prev, scene.geometry.attributes_at(&h.hit));
        let bsdf = Material::bsdf(
            &scene.shading_materials,
            scene.geometry.material(&h.hit),
            &at,
        );
        Some(LightVertex {
            si,
            frame,
            bsdf,
            w_prev,
            prev_local: at.wo,
            cos_g_prev: si.n.dot(w_prev),
        })
    }

    /// BSDF sampling at `v` continues the path, then Russian roulette after `rr_depth`
    /// vertices. `false` where the path ends. Draws three dimensions, and one more for the
    /// roulette.
    pub fn scatter<S: Sampler>(
        &mut self,
        v: &LightVertex,
        rr_depth: u32,
        sampler: &mut S,
        ctx: &mut TraceContext,
    ) -> bool {
        let (si, frame, prev_local) = (&v.si, &v.frame, v.prev_local);
        let u_lobe = sampler.get_1d();
        let u_bsdf = sampler.get_2d();
        let Some(bs) = v.bsdf.sample(prev_local, u_lobe, u_bsdf) else {
            return false;
        };
        let w_new = frame.to_world(bs.wi);
        let cos_g_new = si.n.dot(w_new);
        if cos_g_new * bs.wi.z <= 0.0 {
            return false;
        }
        // Importance is not scaled by refraction as radiance is: `bs.eta²` undoes the radiance
        // BSDF's 1/eta² (Veach 1997 section 5.2); and the adjoint's shading-normal factor
        // |cos_g(new)| |cos_s(prev)| / (|cos_s(new)| |cos_g(prev)|) (section 5.3.2).
        let correction = (prev_local.z * cos_g_new / (bs.wi.z * v.cos_g_prev)).abs();
        self.throughput *= bs.weight * (bs.eta * bs.eta * correction);
        self.eta *= bs.eta;
        if bs.lobe.contains(BsdfFlags::DELTA_TRANSMISSION) || bs.wi.z * prev_local.z < 0.0 {
            ctx.rays.refraction += 1;
        } else {
            ctx.rays.reflection += 1;
        }
        self.ray = Ray::new(offset_ray_origin(si.p, si.p_error, si.n, w_new), w_new);
        self.depth += 1;
        let t = self.throughput.max_element() * self.eta * self.eta;
        if t <= 0.0 || !t.is_finite() {
            return false;
        }
        // Russian roulette on the throughput with refraction's scaling undone (Mitsuba's
        // ptracer: max(throughput) eta²).
        if self.depth > rr_depth {
            let q = t.min(RR_MAX_PROBABILITY);
            if sampler.get_1d() >= q {
                return false;
            }
            self.throughput /= q;
        }
        true
    }
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
    let further = tracer.further_images();
    let filter = filter::Filter::new(&scene.settings.filter);
    let mut film = SplatFilm::new(filter, w, h, further.len());
    let paths = w as u64 * h as u64;
    let chunks = paths.div_ceil(CHUNK as u64) as u32;
    let wave = (tracer.paths_per_pass() / CHUNK as u64).max(1) as u32;
    let mut stats = RenderStats::default();
    let window_pixels = window.pixel_count();
    let done_paths = AtomicU64::new(0);
    let mut first = 0;
    while first < spp {
        let mut count = next_pass(spp, first, start.elapsed(), options.time_limit);
        if batches_per_pass > 0 {
            count = count.min(batches_per_pass);
        }
        count = count.min((tracer.paths_per_pass() / paths).max(1) as u32);
        let items = count * chunks;
        // A batch too large for one pass goes in waves of chunks.
        let wave_items = if count as u64 * paths <= tracer.paths_per_pass() {
            items
        } else {
            wave
        };
        let mut item0 = 0;
        while item0 < items {
            let item1 = items.min(item0 + wave_items);
            let results: Vec<Option<(Vec<Splat>, TraceContext)>> = (item0..item1)
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
                        tracer.trace(
                            scene,
                            (x, y),
                            &mut sampler,
                            &mut splats,
                            &mut scratch,
                            &mut ctx,
                        );
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
            // In item order: batch by batch, each batch's chunks in order.
            for (item, result) in (item0..item1).zip(results) {
                let (splats, ctx) = result.ok_or(Error::Cancelled)?;
                let chunk = item % chunks;
                if chunk == 0 {
                    film.begin_batch();
                }
                film.add_splats(&splats);
                stats.merge(&ctx);
                if chunk == chunks - 1 {
                    film.end_batch();
                }
            }
            item0 = item1;
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
    let mut image = film.film(&[]).crop(window, &aovs);
    for (name, values) in further.iter().zip(film.further_images()) {
        let values = Film::from_pixels(w, h, values, vec![Vec3::ZERO; paths as usize], &[])
            .crop(window, &[])
            .rgb;
        for (c, channel) in ["R", "G", "B"].into_iter().enumerate() {
            image.channels.push(Channel {
                name: format!("{name}.{channel}"),
                values: values.iter().map(|v| v[c]).collect(),
            });
        }
    }
    if let Some(progress) = options.progress {
        progress(window_pixels);
    }
    stats.time = start.elapsed();
    Ok((image, stats))
}

/// What the ray through each pixel centre of the window sees first, in row order.
pub(super) fn window_aovs(scene: &Scene, window: Window, stats: &mut RenderStats) -> Vec<PixelAov> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::description_from_str;
    use crate::description::parse::Syntax;
    use crate::math::Vec2;
    use std::path::Path;

    /// Splats each path's pixel index and a random number at the pixel's centre, to the image
    /// and to a further image, through passes of `paths_per_pass` paths.
    struct PixelTracer {
        paths_per_pass: u64,
    }

    impl LightPathTracer for PixelTracer {
        type Scratch = ();

        fn trace<S: Sampler>(
            &self,
            _: &Scene,
            (x, y): (u32, u32),
            sampler: &mut S,
            splats: &mut Vec<Splat>,
            _: &mut (),
            _: &mut TraceContext,
        ) {
            let pos = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let value = Vec3::new(x as f32, y as f32, sampler.get_1d());
            splats.push(Splat::new(pos, value));
            splats.push(Splat {
                pos,
                value: value * 2.0,
                image: 1,
            });
        }

        fn further_images(&self) -> Vec<String> {
            vec!["twice".into()]
        }

        fn paths_per_pass(&self) -> u64 {
            self.paths_per_pass
        }
    }

    /// A batch larger than a pass goes in waves of chunks: the film (each pixel its own
    /// splats' mean, under the box filter) and its further image are the same as in one pass.
    #[test]
    fn batches_larger_than_a_pass_go_in_waves() {
        let toml = "[camera]\neye = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nwidth = 40\n\
                    height = 30\n[render]\nintegrator = \"ptracer\"\nspp = 3\n\
                    filter = { type = \"box\" }\n";
        let d = description_from_str(toml, Syntax::Toml, Path::new("t.toml")).unwrap();
        let scene = Scene::new(&d, Path::new(".")).unwrap();
        let options = RenderOptions {
            skip_aovs: true,
            ..Default::default()
        };
        let in_one = PixelTracer {
            paths_per_pass: PATHS_PER_PASS,
        };
        let in_waves = PixelTracer {
            paths_per_pass: CHUNK as u64,
        };
        let (one, _) = render_light_paths(&scene, &in_one, 0, &options).unwrap();
        let (waves, stats) = render_light_paths(&scene, &in_waves, 0, &options).unwrap();
        assert_eq!(stats.spp, 3);
        assert_eq!(one.rgb, waves.rgb);
        assert_eq!(one.channels, waves.channels);
        for (k, c) in waves.rgb.iter().enumerate() {
            assert_eq!((c.x, c.y), ((k % 40) as f32, (k / 40) as f32));
            assert_eq!(
                waves.channels[1].values[k],
                2.0 * c.y,
                "{}",
                waves.channels[1].name
            );
        }
    }
}
