//! Stochastic progressive photon mapping (Hachisuka and Jensen 2009; pbrt-v4's `SPPMIntegrator`):
//! for the light that a path tracer cannot find, such as caustics seen through glass or water
//! (light -> specular -> diffuse -> specular -> camera), which no connection of subpaths can make
//! either.
//!
//! Each iteration (one of `spp`):
//! 1. a camera path per pixel through specular and glossy vertices to the first diffuse one, its
//!    *visible point* (or a glossy one at the last depth); the light it sees on the way and the
//!    direct light at the visible point (light sampling alone: the photons carry the rest) are
//!    added to the pixel;
//! 2. photons from the lights, each vertex after the first (direct light is the camera side's)
//!    adding `throughput * f(visible point)` to every visible point within that pixel's radius;
//! 3. each pixel's radius shrinks by Hachisuka and Jensen's update with alpha = 2/3, keeping the
//!    flux found so far in proportion to the smaller disc.
//!
//! The pixel's value is the direct part's mean plus the flux over `photons * pi * r^2`; it is
//! consistent (the radius goes to zero) but biased at any finite count: a blur of the photons'
//! light over the radius. The film has no reconstruction filter: each pixel is the mean over its
//! own area (a box), as pbrt-v4's SPPM keeps one visible point per pixel.
//!
//! Determinism: camera paths draw from the scene's sampler at their pixel and the iteration's
//! index; photon `k` from an independent sampler at "pixel" `(k mod W, k div W)`; photons are
//! traced in fixed chunks in parallel into lists of contributions that are added in chunk order.
//! So the image is bit-identical for any thread count.

use super::integrator::{camera_ray, vertex_limit, CameraRay, Integrator};
use super::light_pass::{start_light_path, window_aovs, LightPath};
use super::path::{intersect_through_masks, light_sample_weighted, visible, PathState, PathTracer};
use super::ptracer::check_camera;
use super::sampler::{mix64, IndependentSampler, PixelPatternSampler, Sampler, SobolSampler};
use super::{Film, RenderOptions, RenderStats, TraceContext, Window};
use crate::description::SamplerName;
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::scene::{RenderSettings, Scene};
use crate::shading::bsdf::BsdfFlags;
use crate::shading::frame::ShadingFrame;
use crate::shading::material::SurfaceBsdf;
use rayon::prelude::*;
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Hachisuka and Jensen's alpha: the share of each iteration's new photons kept in the count as
/// the radius shrinks (2/3, their and pbrt's choice).
const ALPHA: f32 = 2.0 / 3.0;

/// Photons per parallel work item.
const CHUNK: u32 = 1024;

/// Photons traced between two additions of their contributions: bounds the memory of the
/// contribution lists (about 16 bytes per photon, vertex and visible point found).
const PHOTONS_PER_PASS: u32 = 1 << 16;

#[derive(Clone, Copy, Debug)]
pub struct Sppm {
    /// The most vertices of a camera path and of a photon path; `u32::MAX` for unlimited.
    pub max_depth: u32,
    pub rr_depth: u32,
    pub hide_emitters: bool,
    pub initial_radius: f32,
    /// 0: one per pixel.
    pub photons_per_iteration: u32,
}

impl Integrator for Sppm {
    const NAME: &'static str = "sppm";

    fn from_settings(s: &RenderSettings) -> Result<Self> {
        let p = s.integrator_params.sppm;
        Ok(Sppm {
            max_depth: vertex_limit(s.max_depth),
            rr_depth: s.rr_depth,
            hide_emitters: s.hide_emitters,
            initial_radius: p.radius,
            photons_per_iteration: p.photons_per_iteration,
        })
    }

    fn render(&self, scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        check_camera(scene)?;
        let s = &scene.settings;
        match s.sampler {
            SamplerName::Independent => self.run(scene, &IndependentSampler::new(s.seed), options),
            SamplerName::Sobol => self.run(scene, &SobolSampler::new(s.seed, s.spp), options),
            SamplerName::PixelPattern => {
                self.run(scene, &PixelPatternSampler::new(s.seed, s.spp), options)
            }
        }
    }
}

/// Where a camera path stopped to gather photons.
#[derive(Clone, Copy, Debug)]
struct VisiblePoint {
    p: Vec3,
    frame: ShadingFrame,
    /// Toward the camera, in `frame`.
    wo: Vec3,
    bsdf: SurfaceBsdf,
    /// The camera path's throughput up to the point.
    beta: Vec3,
}

/// One pixel's state across iterations (pbrt-v4's `SPPMPixel`).
#[derive(Clone, Copy, Debug)]
struct Pixel {
    radius: f32,
    /// The sum of the direct parts (emitters seen, direct light at the visible point), and of
    /// their squares for the film's variance.
    direct: Vec3,
    direct_sq: Vec3,
    /// Photons counted so far (Hachisuka and Jensen's N) and the flux they brought, scaled to
    /// the current radius (tau).
    photons: f32,
    tau: Vec3,
    /// This iteration's visible point and the photons it gathered.
    vp: Option<VisiblePoint>,
    phi: Vec3,
    found: u32,
}

impl Sppm {
    fn run<S: Sampler>(
        &self,
        scene: &Scene,
        sampler: &S,
        options: &RenderOptions,
    ) -> Result<(Film, RenderStats)> {
        let start = Instant::now();
        let (w, h) = (scene.camera.width, scene.camera.height);
        let window = options.window.unwrap_or(Window::full(w, h));
        window.check(w, h)?;
        let spp = scene.settings.spp.max(1);
        let photons = if self.photons_per_iteration == 0 {
            w * h
        } else {
            self.photons_per_iteration
        };
        let photon_sampler = IndependentSampler::new(mix64(scene.settings.seed ^ 0x5350_504d));
        let mut pixels = vec![
            Pixel {
                radius: self.initial_radius,
                direct: Vec3::ZERO,
                direct_sq: Vec3::ZERO,
                photons: 0.0,
                tau: Vec3::ZERO,
                vp: None,
                phi: Vec3::ZERO,
                found: 0,
            };
            (w * h) as usize
        ];
        let mut stats = RenderStats::default();
        let window_pixels = window.pixel_count();
        let mut done = 0;
        while done < spp {
            if options.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return Err(Error::Cancelled);
            }
            let ctx = self.camera_pass(scene, sampler, done, &mut pixels);
            stats.merge(&ctx);
            let grid = PointGrid::new(&pixels);
            let mut first = 0;
            while first < photons {
                let count = PHOTONS_PER_PASS.min(photons - first);
                let (deposits, ctx) = self.photon_pass(
                    scene,
                    &photon_sampler,
                    done,
                    first..first + count,
                    w,
                    &grid,
                    &pixels,
                );
                stats.merge(&ctx);
                for (pixel, value) in deposits {
                    let px = &mut pixels[pixel as usize];
                    px.phi += value;
                    px.found += 1;
                }
                first += count;
            }
            pixels.par_iter_mut().for_each(shrink);
            done += 1;
            stats.spp = done;
            if let Some(progress) = options.progress {
                progress(done as u64 * window_pixels / spp as u64);
            }
            // One iteration at a time (the next needs this one's radii), the first always.
            if options
                .time_limit
                .is_some_and(|limit| start.elapsed() >= limit)
            {
                break;
            }
        }
        let n = done.max(1) as f32;
        let emitted = photons as f32 * n;
        let (rgb, variance): (Vec<Vec3>, Vec<Vec3>) = pixels
            .iter()
            .map(|px| {
                let mean = px.direct / n;
                let gathered = px.tau / (emitted * std::f32::consts::PI * px.radius * px.radius);
                // The variance of the direct part's mean alone: the photons' error is mostly
                // the bias of their disc, which no spread of samples shows.
                let var = (px.direct_sq / n - mean * mean).max(Vec3::ZERO) / n;
                (mean + gathered, var)
            })
            .unzip();
        let aovs = if options.skip_aovs {
            Vec::new()
        } else {
            window_aovs(scene, window, &mut stats)
        };
        let film = Film::from_pixels(w, h, rgb, variance, &[]).crop(window, &aovs);
        if let Some(progress) = options.progress {
            progress(window_pixels);
        }
        stats.time = start.elapsed();
        Ok((film, stats))
    }

    /// Traces every pixel's camera path of iteration `index`, adding its direct part and
    /// leaving its visible point.
    fn camera_pass<S: Sampler>(
        &self,
        scene: &Scene,
        sampler: &S,
        index: u32,
        pixels: &mut [Pixel],
    ) -> TraceContext {
        let w = scene.camera.width as usize;
        pixels
            .par_chunks_mut(w)
            .enumerate()
            .map(|(y, row)| {
                let mut sampler = sampler.clone();
                let mut ctx = TraceContext::default();
                for (x, px) in row.iter_mut().enumerate() {
                    sampler.start_pixel_sample(x as u32, y as u32, index);
                    let (direct, vp) =
                        self.camera_path(scene, x as u32, y as u32, &mut sampler, &mut ctx);
                    let direct = if direct.is_finite() {
                        direct
                    } else {
                        ctx.invalid_samples += 1;
                        Vec3::ZERO
                    };
                    px.direct += direct;
                    px.direct_sq += direct * direct;
                    px.vp = vp;
                }
                ctx
            })
            .reduce(TraceContext::default, |mut a, b| {
                a.rays.merge(&b.rays);
                a.traversal.merge(&b.traversal);
                a.invalid_samples += b.invalid_samples;
                a
            })
    }

    /// A camera path: the light it finds by the path tracer's vertices (emission with MIS, and
    /// next-event estimation at glossy vertices), and its visible point.
    fn camera_path<S: Sampler>(
        &self,
        scene: &Scene,
        x: u32,
        y: u32,
        sampler: &mut S,
        ctx: &mut TraceContext,
    ) -> (Vec3, Option<VisiblePoint>) {
        let CameraRay { ray, .. } = camera_ray(scene, x, y, sampler);
        ctx.rays.camera += 1;
        if self.max_depth == 0 {
            return (Vec3::ZERO, None);
        }
        // No Russian roulette on the camera side, as pbrt's SPPM, unless the depth is unlimited:
        // then roulette is what ends a path caught between mirrors.
        let tracer = PathTracer {
            max_depth: self.max_depth,
            rr_depth: if self.max_depth == u32::MAX {
                self.rr_depth
            } else {
                u32::MAX
            },
            hide_emitters: self.hide_emitters,
        };
        let mut st = PathState::new(&ray);
        loop {
            let hit = intersect_through_masks(scene, &st.ray, sampler, ctx);
            let Some(v) = tracer.vertex(scene, &mut st, hit.as_ref()) else {
                return (st.result, None);
            };
            let flags = v.bsdf.flags();
            let diffuse = flags.contains(BsdfFlags::DIFFUSE_REFLECTION)
                || flags.contains(BsdfFlags::DIFFUSE_TRANSMISSION);
            let glossy = flags.contains(BsdfFlags::GLOSSY_REFLECTION)
                || flags.contains(BsdfFlags::GLOSSY_TRANSMISSION);
            // The last vertex the depth allows scatters no further: a glossy one gathers too.
            let last = st.depth + 2 >= self.max_depth;
            let gathers = diffuse || (glossy && last);
            if let Some(test) = light_sample_weighted(scene, &st, &v, sampler, !gathers) {
                if visible(scene, &v.si, test.dir, test.t_max, sampler, ctx) {
                    st.result += test.contribution;
                }
            }
            if gathers {
                let vp = VisiblePoint {
                    p: v.si.p,
                    frame: v.frame,
                    wo: v.wo,
                    bsdf: v.bsdf,
                    beta: st.throughput,
                };
                return (st.result, Some(vp));
            }
            if !tracer.scatter(&mut st, &v, sampler, ctx) {
                return (st.result, None);
            }
        }
    }

    /// Traces photons `range` of iteration `index`, in chunks in parallel; their contributions
    /// to the visible points, in photon order.
    #[allow(clippy::too_many_arguments)]
    fn photon_pass(
        &self,
        scene: &Scene,
        sampler: &IndependentSampler,
        index: u32,
        range: std::ops::Range<u32>,
        width: u32,
        grid: &PointGrid,
        pixels: &[Pixel],
    ) -> (Vec<(u32, Vec3)>, TraceContext) {
        let chunks = (range.end - range.start).div_ceil(CHUNK);
        let results: Vec<(Vec<(u32, Vec3)>, TraceContext)> = (0..chunks)
            .into_par_iter()
            .map(|c| {
                let mut sampler = sampler.clone();
                let mut ctx = TraceContext::default();
                let mut deposits = Vec::new();
                let k0 = range.start + c * CHUNK;
                let k1 = (k0 + CHUNK).min(range.end);
                for k in k0..k1 {
                    sampler.start_pixel_sample(k % width, k / width, index);
                    self.photon(scene, &mut sampler, grid, pixels, &mut deposits, &mut ctx);
                }
                (deposits, ctx)
            })
            .collect();
        let mut ctx = TraceContext::default();
        let mut all = Vec::with_capacity(results.iter().map(|(d, _)| d.len()).sum());
        for (d, c) in results {
            all.extend(d);
            ctx.rays.merge(&c.rays);
            ctx.traversal.merge(&c.traversal);
        }
        (all, ctx)
    }

    /// One photon: from a light, each surface after the first adding to the visible points
    /// around it, continued by BSDF sampling as importance is (`LightPath::scatter`).
    fn photon<S: Sampler>(
        &self,
        scene: &Scene,
        sampler: &mut S,
        grid: &PointGrid,
        pixels: &[Pixel],
        deposits: &mut Vec<(u32, Vec3)>,
        ctx: &mut TraceContext,
    ) {
        if scene.emitters.picker.is_empty() {
            return;
        }
        let Some(start) = start_light_path(scene, sampler) else {
            return;
        };
        let mut path = LightPath::new(&start);
        // A camera path of `max_depth` vertices gathers at most at its last one but one; the
        // photon's vertices, the light's included, are counted the same way.
        while path.depth < self.max_depth {
            let Some(v) = path.next_vertex(scene, sampler, ctx) else {
                return;
            };
            // The light's own point is vertex 1: from vertex 3 on, the light is indirect.
            if path.depth >= 2 {
                grid.gather(v.si.p, pixels, |pixel, vp| {
                    let wi = vp.frame.to_local(v.w_prev);
                    if wi.z == 0.0 {
                        return;
                    }
                    // The BSDF without its cosine: the photons' density over the disc already
                    // is one of projected area.
                    let f = vp.bsdf.eval_pdf(vp.wo, wi).0 / wi.z.abs();
                    let value = path.throughput * f;
                    if value != Vec3::ZERO {
                        deposits.push((pixel, value));
                    }
                });
            }
            if v.leaks() || !path.scatter(&v, self.rr_depth, sampler, ctx) {
                return;
            }
        }
    }
}

/// Hachisuka and Jensen's update after an iteration (pbrt-v4's, per pixel): the photons found
/// count by `ALPHA`, the radius shrinks so that the count's density stays, and the flux is
/// scaled to the smaller disc.
fn shrink(px: &mut Pixel) {
    if px.found > 0 {
        let m = px.found as f32;
        let n_new = px.photons + ALPHA * m;
        let r_new = px.radius * (n_new / (px.photons + m)).sqrt();
        let beta = px.vp.map_or(Vec3::ZERO, |vp| vp.beta);
        px.tau = (px.tau + beta * px.phi) * ((r_new * r_new) / (px.radius * px.radius));
        px.photons = n_new;
        px.radius = r_new;
    }
    px.phi = Vec3::ZERO;
    px.found = 0;
    px.vp = None;
}

/// The visible points in a hashed uniform grid of cells as large as the largest radius: each
/// point is listed in every cell its disc's bounding box touches, so a photon looks in its own
/// cell only (pbrt-v4's SPPM grid).
struct PointGrid {
    cell: f32,
    /// `start[h]..start[h + 1]` indexes `points` for hash bucket `h`.
    start: Vec<u32>,
    points: Vec<u32>,
}

impl PointGrid {
    fn new(pixels: &[Pixel]) -> Self {
        let max_radius = pixels
            .iter()
            .filter(|p| p.vp.is_some())
            .map(|p| p.radius)
            .fold(0.0f32, f32::max);
        let buckets = pixels.len().next_power_of_two().max(1);
        let cell = max_radius.max(f32::MIN_POSITIVE);
        let mut grid = PointGrid {
            cell,
            start: vec![0; buckets + 1],
            points: Vec::new(),
        };
        // Counting sort: how many entries each bucket gets, then where they go.
        let mut counts = vec![0u32; buckets];
        for (_, h) in grid.entries(pixels) {
            counts[h] += 1;
        }
        let mut sum = 0;
        for (s, c) in grid.start.iter_mut().zip(&counts) {
            *s = sum;
            sum += c;
        }
        grid.start[buckets] = sum;
        let mut next = grid.start.clone();
        grid.points = vec![0; sum as usize];
        let entries: Vec<(u32, usize)> = grid.entries(pixels).collect();
        for (i, h) in entries {
            grid.points[next[h] as usize] = i;
            next[h] += 1;
        }
        grid
    }

    /// Every (visible point, bucket) pair: a point's disc in each cell it may reach.
    fn entries<'a>(&'a self, pixels: &'a [Pixel]) -> impl Iterator<Item = (u32, usize)> + 'a {
        pixels.iter().enumerate().flat_map(move |(i, px)| {
            let (lo, hi) = match px.vp {
                Some(vp) => (
                    self.cell_of(vp.p - Vec3::splat(px.radius)),
                    self.cell_of(vp.p + Vec3::splat(px.radius)),
                ),
                None => ([0; 3], [-1; 3]),
            };
            (lo[2]..=hi[2]).flat_map(move |z| {
                (lo[1]..=hi[1]).flat_map(move |y| {
                    (lo[0]..=hi[0]).map(move |x| (i as u32, self.bucket([x, y, z])))
                })
            })
        })
    }

    fn cell_of(&self, p: Vec3) -> [i32; 3] {
        [p.x, p.y, p.z].map(|c| (c / self.cell).floor() as i32)
    }

    /// Teschner et al.'s spatial hash (2003), as pbrt's.
    fn bucket(&self, c: [i32; 3]) -> usize {
        let h = (c[0] as u32).wrapping_mul(73_856_093)
            ^ (c[1] as u32).wrapping_mul(19_349_663)
            ^ (c[2] as u32).wrapping_mul(83_492_791);
        h as usize & (self.start.len() - 2)
    }

    /// Calls `found(pixel, visible point)` for each visible point whose disc holds `p`.
    fn gather(&self, p: Vec3, pixels: &[Pixel], mut found: impl FnMut(u32, &VisiblePoint)) {
        let h = self.bucket(self.cell_of(p));
        for &i in &self.points[self.start[h] as usize..self.start[h + 1] as usize] {
            let px = &pixels[i as usize];
            if let Some(vp) = &px.vp {
                if (vp.p - p).length_squared() <= px.radius * px.radius {
                    found(i, vp);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pixel_at(p: Vec3, radius: f32) -> Pixel {
        let frame = ShadingFrame::from_normal_tangent(Vec3::Z, Vec3::X);
        Pixel {
            radius,
            direct: Vec3::ZERO,
            direct_sq: Vec3::ZERO,
            photons: 0.0,
            tau: Vec3::ZERO,
            vp: Some(VisiblePoint {
                p,
                frame,
                wo: Vec3::Z,
                bsdf: SurfaceBsdf::plain(crate::shading::bsdf::AnyBsdf::Diffuse(
                    crate::shading::bsdf::Diffuse::new(Vec3::splat(0.5)),
                )),
                beta: Vec3::ONE,
            }),
            phi: Vec3::ZERO,
            found: 0,
        }
    }

    /// The grid finds exactly the discs that hold a point (against a scan of all of them),
    /// across cells, hash collisions and negative coordinates.
    #[test]
    fn the_grid_finds_every_disc_holding_a_point() {
        let mut rng = crate::render::sampler::Pcg32::new(5, 1);
        let mut u = || rng.next_f32() * 4.0 - 2.0;
        let pixels: Vec<Pixel> = (0..300)
            .map(|i| pixel_at(Vec3::new(u(), u(), u()), 0.05 + 0.002 * (i % 50) as f32))
            .collect();
        let grid = PointGrid::new(&pixels);
        for _ in 0..2000 {
            let p = Vec3::new(u(), u(), u());
            let mut found = Vec::new();
            grid.gather(p, &pixels, |i, _| found.push(i));
            found.sort_unstable();
            found.dedup();
            let expected: Vec<u32> = (0..pixels.len() as u32)
                .filter(|&i| {
                    let px = &pixels[i as usize];
                    (px.vp.unwrap().p - p).length_squared() <= px.radius * px.radius
                })
                .collect();
            assert_eq!(found, expected, "at {p:?}");
        }
    }

    /// The radius update keeps the photon density: after an iteration that finds `m` photons,
    /// N' = N + alpha m and r'^2 = r^2 N' / (N + m); the flux scales with the disc's area.
    #[test]
    fn the_radius_shrinks_as_hachisuka_and_jensen_s_update() {
        let mut px = pixel_at(Vec3::ZERO, 0.5);
        px.photons = 30.0;
        px.found = 10;
        px.phi = Vec3::splat(2.0);
        px.tau = Vec3::splat(4.0);
        shrink(&mut px);
        let n_new = 30.0 + ALPHA * 10.0;
        assert!((px.photons - n_new).abs() < 1e-5);
        let r2 = 0.25 * n_new / 40.0;
        assert!((px.radius * px.radius - r2).abs() < 1e-6);
        let tau = (4.0 + 2.0) * r2 / 0.25;
        assert!((px.tau.x - tau).abs() < 1e-5, "{:?}", px.tau);
        assert_eq!((px.found, px.phi), (0, Vec3::ZERO));
        // An iteration without photons changes nothing but the visible point.
        let before = (px.radius, px.photons, px.tau);
        shrink(&mut px);
        assert_eq!(before, (px.radius, px.photons, px.tau));
    }
}
