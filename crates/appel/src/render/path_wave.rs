//! The path tracer as a wavefront over a run of pixel samples (Laine, Karras and Aila 2013,
//! "Megakernels considered harmful"): the camera rays of the run are traced together, then each
//! bounce shades all live paths stage by stage (emission with its MIS weight, the light sample,
//! the BSDF sample and Russian roulette; [`PathTracer::vertex`], [`PathTracer::light_sample`],
//! [`PathTracer::scatter`]), answers all their shadow rays as one stream and intersects all
//! continuation rays as the next one; paths that ended leave the list of live paths between
//! bounces.
//!
//! Each path keeps its own sampler, positioned at its pixel sample and drawing its dimensions in
//! the scalar loop's order, and each stage runs the scalar loop's operations on it, so a sample
//! is bit for bit [`PathTracer::li`]'s: the wavefront changes only which rays are traced
//! together. That holds where no stage draws a number out of the scalar order, which a mask's
//! stochastic crossing of a shadow ray would (see [`PathTracer::wave_applies`]).

use super::integrator::{camera_ray, centre_aov, FilmSample, PixelRow, SurfaceHit};
use super::path::{PathState, PathTracer};
use super::sampler::Sampler;
use super::{PixelAov, TraceContext};
use crate::math::{offset_ray_origin, Ray, Vec2, Vec3};
use crate::scene::{Scene, SceneHit};

/// Paths per wave: a tile's row (`TILE_SIZE`), two camera packets of eight.
pub(super) const WAVE: usize = 16;

/// The shadow rays of one bounce of a wave, and what each adds to its path if unblocked.
struct ShadowStream {
    rays: [Ray; WAVE],
    t_max: [f32; WAVE],
    path: [u8; WAVE],
    contribution: [Vec3; WAVE],
    len: usize,
}

impl PathTracer {
    /// Whether the wavefront computes this scene's samples: every BSDF and emitter runs in its
    /// stages (they are the scalar loop's), but a mask's stochastic crossing draws numbers while
    /// a shadow ray is traced, between the light sample and the BSDF sample, which a stream of
    /// shadow rays answered after the bounce's shading cannot reproduce.
    #[inline]
    pub(super) fn wave_applies(scene: &Scene) -> bool {
        !scene.has_masks
    }

    /// Sample `row.index` of the pixels of a row run (`out[i]` for pixel `row.x0 + i`), in waves
    /// of [`WAVE`] paths: the samples of [`PathTracer::li`], bit for bit.
    pub(super) fn sample_row_wave<S: Sampler>(
        &self,
        scene: &Scene,
        row: PixelRow,
        sampler: &S,
        out: &mut [FilmSample],
        mut aovs: Option<&mut [PixelAov]>,
        ctx: &mut TraceContext,
    ) {
        for (c, out) in out.chunks_mut(WAVE).enumerate() {
            let x0 = row.x0 + (c * WAVE) as u32;
            if let Some(aovs) = aovs.as_deref_mut() {
                // The AOVs describe the pixel centre (as opaque surfaces): one more camera ray
                // per pixel, as in the scalar `sample`.
                for (i, a) in aovs[c * WAVE..][..out.len()].iter_mut().enumerate() {
                    *a = centre_aov(scene, x0 + i as u32, row.y, ctx);
                }
            }
            self.wave(scene, x0, row, sampler, out, ctx);
        }
    }

    /// One wave: the paths of pixels `x0..x0 + out.len()` of `row`.
    fn wave<S: Sampler>(
        &self,
        scene: &Scene,
        x0: u32,
        row: PixelRow,
        sampler: &S,
        out: &mut [FilmSample],
        ctx: &mut TraceContext,
    ) {
        let n = out.len();
        debug_assert!(n <= WAVE);
        let mut samplers: [S; WAVE] = std::array::from_fn(|_| sampler.clone());
        let mut pos = [Vec2::ZERO; WAVE];
        let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); WAVE];
        for k in 0..n {
            let x = x0 + k as u32;
            samplers[k].start_pixel_sample(x, row.y, row.index);
            let c = camera_ray(scene, x, row.y, &mut samplers[k]);
            (pos[k], rays[k]) = (c.pos, c.ray);
        }
        ctx.rays.camera += n as u64;
        let mut paths: [PathState; WAVE] = std::array::from_fn(|k| PathState::new(&rays[k]));
        // Mitsuba's max_depth 0: no light at all.
        let mut live = if self.max_depth == 0 { 0 } else { n };
        // The live paths, by index; `rays[i]` and `hits[i]` belong to path `alive[i]`.
        let mut alive: [u8; WAVE] = std::array::from_fn(|k| k as u8);
        let mut hits: [Option<SceneHit>; WAVE] = [None; WAVE];
        let mut shadow = ShadowStream {
            rays: [Ray::new(Vec3::ZERO, Vec3::Z); WAVE],
            t_max: [0.0; WAVE],
            path: [0; WAVE],
            contribution: [Vec3::ZERO; WAVE],
            len: 0,
        };
        let mut blocked = [false; WAVE];
        let mut bounce = 0;
        while live > 0 {
            // Camera rays share an origin and neighbouring directions: packets where the
            // structure has them. Later bounces scatter.
            if bounce == 0 {
                scene.intersect_coherent(
                    &rays[..live],
                    f32::INFINITY,
                    &mut hits[..live],
                    &mut ctx.traversal,
                );
            } else {
                scene.intersect_stream(
                    &rays[..live],
                    f32::INFINITY,
                    &mut hits[..live],
                    &mut ctx.traversal,
                );
            }
            shadow.len = 0;
            let mut next = 0;
            for i in 0..live {
                let k = alive[i] as usize;
                let path = &mut paths[k];
                // Always with texture coordinates, as the scalar loop.
                let h = hits[i].map(|hit| SurfaceHit {
                    hit,
                    si: scene.geometry.interaction_with(&rays[i], &hit, true),
                });
                let Some(v) = self.vertex(scene, path, h.as_ref()) else {
                    continue;
                };
                if let Some(test) = self.light_sample(scene, path, &v, &mut samplers[k]) {
                    let j = shadow.len;
                    let origin = offset_ray_origin(v.si.p, v.si.p_error, v.si.n, test.dir);
                    shadow.rays[j] = Ray::new(origin, test.dir);
                    shadow.t_max[j] = test.t_max;
                    shadow.path[j] = k as u8;
                    shadow.contribution[j] = test.contribution;
                    shadow.len += 1;
                }
                if self.scatter(path, &v, &mut samplers[k], ctx) {
                    // Compaction in place: `next <= i`, so no live entry is overwritten unread.
                    alive[next] = k as u8;
                    rays[next] = path.ray;
                    next += 1;
                }
            }
            let ns = shadow.len;
            ctx.rays.shadow += ns as u64;
            scene.occluded_stream(
                &shadow.rays[..ns],
                &shadow.t_max[..ns],
                &mut blocked[..ns],
                &mut ctx.traversal,
            );
            // After the vertex's emission and before the next vertex's, as the scalar loop adds.
            for j in 0..ns {
                if !blocked[j] {
                    paths[shadow.path[j] as usize].result += shadow.contribution[j];
                }
            }
            live = next;
            bounce += 1;
        }
        for (k, o) in out.iter_mut().enumerate() {
            *o = FilmSample {
                pos: pos[k],
                radiance: paths[k].result,
            };
        }
    }
}
