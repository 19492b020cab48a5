//! Unidirectional path tracing with next-event estimation, multiple importance sampling of BSDF
//! and emitter samples by the power heuristic (Veach and Guibas 1995), and Russian roulette: the
//! estimator of Mitsuba 3's `path` integrator, with its meaning of `max_depth` (1: emitters seen
//! directly; 2: direct light; -1: unlimited) and of `rr_depth`. The `direct` integrator is the same
//! estimator stopped after direct light.

use super::integrator::{
    camera_ray, centre_aov, sample_row_one_by_one, vertex_limit, CameraRay, FilmSample, Integrator,
    PixelIntegrator, PixelRow, SurfaceHit,
};
use super::sampler::Sampler;
use super::{with_sampler, Film, PixelAov, RenderOptions, RenderStats, TraceContext};
use crate::error::Result;
use crate::geometry::SurfaceInteraction;
use crate::math::{offset_ray_origin, Ray, Vec3};
use crate::scene::{RenderSettings, Scene, NO_EMITTER, NO_INSTANCE};
use crate::shading::bsdf::BsdfFlags;
use crate::shading::frame::ShadingFrame;
use crate::shading::material::{Material, SurfaceBsdf, SurfacePoint};

/// Shadow rays stop this fraction short of the sampled light point, so that the light's own
/// surface does not occlude it (relative to the segment: scale-free).
pub(super) const SHADOW_EPSILON: f32 = 1e-4;

/// Russian roulette keeps a path with at most this probability (Mitsuba's 0.95), so that even
/// bright paths end eventually.
pub(super) const RR_MAX_PROBABILITY: f32 = 0.95;

/// Masks passed through by one ray before it is taken as blocked (a bound, not a tuning knob: a
/// ray crossing this many cut-outs carries nothing visible).
const MAX_MASK_CROSSINGS: u32 = 64;

#[derive(Clone, Copy, Debug)]
pub struct PathTracer {
    /// The most vertices of a path; `u32::MAX` for unlimited.
    pub max_depth: u32,
    pub rr_depth: u32,
    pub hide_emitters: bool,
}

impl PathTracer {
    pub fn new(max_depth: i32, rr_depth: u32, hide_emitters: bool) -> Self {
        Self {
            max_depth: vertex_limit(max_depth),
            rr_depth,
            hide_emitters,
        }
    }

    /// Mitsuba's `direct`: emitters seen by the camera, and direct light by MIS of one emitter and
    /// one BSDF sample.
    pub fn direct(hide_emitters: bool) -> Self {
        Self {
            max_depth: 2,
            rr_depth: u32::MAX,
            hide_emitters,
        }
    }
}

/// The power heuristic with exponent 2.
#[inline]
pub(super) fn mis_weight(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

impl Integrator for PathTracer {
    const NAME: &'static str = "path";

    fn from_settings(s: &RenderSettings) -> Result<Self> {
        Ok(Self::new(s.max_depth, s.rr_depth, s.hide_emitters))
    }

    fn render(&self, scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        with_sampler(scene, self, options)
    }
}

impl PixelIntegrator for PathTracer {
    fn sample<S: Sampler>(
        &self,
        scene: &Scene,
        x: u32,
        y: u32,
        sampler: &mut S,
        aov: Option<&mut PixelAov>,
        ctx: &mut TraceContext,
    ) -> FilmSample {
        let CameraRay { pos, ray, .. } = camera_ray(scene, x, y, sampler);
        ctx.rays.camera += 1;
        // The AOVs describe the pixel centre (as opaque surfaces): one more camera ray per pixel.
        if let Some(aov) = aov {
            *aov = centre_aov(scene, x, y, ctx);
        }
        FilmSample {
            pos,
            radiance: self.li(scene, &ray, sampler, ctx),
        }
    }

    /// The row's samples as a wavefront (`path_wave`) where it applies, the same samples bit
    /// for bit; otherwise one by one.
    fn sample_row<S: Sampler>(
        &self,
        scene: &Scene,
        row: PixelRow,
        sampler: &mut S,
        out: &mut [FilmSample],
        aovs: Option<&mut [PixelAov]>,
        ctx: &mut TraceContext,
    ) {
        if Self::wave_applies(scene) {
            self.sample_row_wave(scene, row, sampler, out, aovs, ctx)
        } else {
            sample_row_one_by_one(self, scene, row, sampler, out, aovs, ctx)
        }
    }
}

/// The state a path carries from vertex to vertex.
#[derive(Clone, Copy, Debug)]
pub(super) struct PathState {
    /// The ray leaving the last vertex (the camera ray at first).
    pub ray: Ray,
    pub throughput: Vec3,
    pub result: Vec3,
    /// The product of the crossings' relative IORs, undone in Russian roulette.
    pub eta: f32,
    /// Vertices so far (0 until the camera ray's hit is shaded).
    pub depth: u32,
    /// The previous vertex, for the MIS weight of emitters hit by BSDF samples.
    pub prev_p: Vec3,
    pub prev_pdf: f32,
    pub prev_delta: bool,
}

impl PathState {
    pub fn new(camera_ray: &Ray) -> Self {
        PathState {
            ray: *camera_ray,
            throughput: Vec3::ONE,
            result: Vec3::ZERO,
            eta: 1.0,
            depth: 0,
            prev_p: camera_ray.origin,
            prev_pdf: 1.0,
            prev_delta: true,
        }
    }
}

/// A surface vertex about to scatter: its interaction, shading frame, the direction toward the
/// previous vertex in that frame, and its BSDF.
#[derive(Clone, Copy, Debug)]
pub(super) struct Vertex {
    pub si: SurfaceInteraction,
    pub frame: ShadingFrame,
    pub wo: Vec3,
    pub bsdf: SurfaceBsdf,
}

/// A light sample waiting for its shadow ray: what it adds to the path's radiance if the light
/// at distance `t_max` along `dir` is seen from the vertex.
#[derive(Clone, Copy, Debug)]
pub(super) struct ShadowTest {
    pub dir: Vec3,
    pub t_max: f32,
    pub contribution: Vec3,
}

impl PathTracer {
    /// The radiance arriving along `camera_ray`, estimated from the sampler's numbers: each
    /// vertex is [`Self::vertex`], [`Self::light_sample`] with its shadow ray, then
    /// [`Self::scatter`] (the stages the wavefront runs over many paths at once).
    pub fn li<S: Sampler>(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        sampler: &mut S,
        ctx: &mut TraceContext,
    ) -> Vec3 {
        // Mitsuba's max_depth 0: no light at all.
        if self.max_depth == 0 {
            return Vec3::ZERO;
        }
        let mut st = PathState::new(camera_ray);
        loop {
            let hit = intersect_through_masks(scene, &st.ray, sampler, ctx);
            let Some(v) = self.vertex(scene, &mut st, hit.as_ref()) else {
                break;
            };
            if let Some(test) = self.light_sample(scene, &st, &v, sampler) {
                if visible(scene, &v.si, test.dir, test.t_max, sampler, ctx) {
                    st.result += test.contribution;
                }
            }
            if !self.scatter(&mut st, &v, sampler, ctx) {
                break;
            }
        }
        st.result
    }

    /// The light `st.ray` brings from what it hit (`hit`, or the environment on a miss), added
    /// to the path's radiance with its MIS weight; then the vertex that scatters, or `None` where
    /// the path ends (a miss, or the depth reached).
    #[inline(always)]
    pub(super) fn vertex(
        &self,
        scene: &Scene,
        st: &mut PathState,
        hit: Option<&SurfaceHit>,
    ) -> Option<Vertex> {
        let emitters = &scene.emitters;
        let Some(h) = hit else {
            // Leaving the scene: the environment.
            if st.depth > 0 || !self.hide_emitters {
                for &e in &emitters.infinite {
                    let em = &emitters.emitters[e as usize];
                    let le = em.radiance_env(st.ray.dir);
                    let w = if st.prev_delta {
                        1.0
                    } else {
                        let pdf = emitters.picker.pmf(e as usize)
                            * em.pdf_li(st.prev_p, st.ray.dir, Vec3::ZERO, Vec3::ZERO);
                        mis_weight(st.prev_pdf, pdf)
                    };
                    st.result += st.throughput * le * w;
                }
            }
            return None;
        };
        let si = h.si;
        let wo_world = -st.ray.dir;
        // Emission of the surface hit.
        let emitter = surface_emitter(scene, h);
        if emitter != NO_EMITTER && (st.depth > 0 || !self.hide_emitters) {
            let em = &emitters.emitters[emitter as usize];
            let le = em.radiance_area(si.ns, si.uv, wo_world);
            if le != Vec3::ZERO {
                let w = if st.prev_delta {
                    1.0
                } else {
                    let pdf = emitters.picker.pmf(emitter as usize)
                        * em.pdf_li(st.prev_p, st.ray.dir, si.p, si.n);
                    mis_weight(st.prev_pdf, pdf)
                };
                st.result += st.throughput * le * w;
            }
        }
        if st.depth + 1 >= self.max_depth {
            return None;
        }
        let frame = ShadingFrame::from_normal_tangent(si.ns, si.shading_tangent());
        let at = SurfacePoint::new(&si, &frame, wo_world, scene.geometry.attributes_at(&h.hit));
        let material = scene.geometry.material(&h.hit);
        Some(Vertex {
            si,
            frame,
            wo: at.wo,
            bsdf: Material::bsdf(&scene.shading_materials, material, &at),
        })
    }

    /// Next-event estimation at `v`: one emitter chosen by power, a point on it, and what it adds
    /// if visible (the shadow ray is the caller's). Draws three dimensions whatever happens.
    #[inline(always)]
    pub(super) fn light_sample<S: Sampler>(
        &self,
        scene: &Scene,
        st: &PathState,
        v: &Vertex,
        sampler: &mut S,
    ) -> Option<ShadowTest> {
        light_sample_weighted(scene, st, v, sampler, true)
    }

    /// BSDF sampling at `v` continues the path: the next ray, the throughput, and Russian
    /// roulette. `false` where the path ends.
    #[inline(always)]
    pub(super) fn scatter<S: Sampler>(
        &self,
        st: &mut PathState,
        v: &Vertex,
        sampler: &mut S,
        ctx: &mut TraceContext,
    ) -> bool {
        let u_lobe = sampler.get_1d();
        let u_bsdf = sampler.get_2d();
        let Some(bs) = v.bsdf.sample(v.wo, u_lobe, u_bsdf) else {
            return false;
        };
        let wi_world = v.frame.to_world(bs.wi);
        if bs.lobe.contains(BsdfFlags::DIFFUSE_TRANSMISSION)
            || bs.lobe.contains(BsdfFlags::GLOSSY_TRANSMISSION)
            || bs.lobe.contains(BsdfFlags::DELTA_TRANSMISSION)
        {
            ctx.rays.refraction += 1;
        } else {
            ctx.rays.reflection += 1;
        }
        st.throughput *= bs.weight;
        st.eta *= bs.eta;
        st.prev_p = v.si.p;
        st.prev_pdf = bs.pdf;
        st.prev_delta = bs.lobe.is_delta();
        st.ray = Ray::new(
            offset_ray_origin(v.si.p, v.si.p_error, v.si.n, wi_world),
            wi_world,
        );
        st.depth += 1;
        // Russian roulette on the throughput with the refraction's radiance scaling undone
        // (Mitsuba: max(throughput) eta^2).
        let t_max = st.throughput.max_element() * st.eta * st.eta;
        if t_max <= 0.0 || !t_max.is_finite() {
            return false;
        }
        if st.depth >= self.rr_depth {
            let q = t_max.min(RR_MAX_PROBABILITY);
            if sampler.get_1d() >= q {
                return false;
            }
            st.throughput /= q;
        }
        true
    }
}

/// The emitter of the surface hit, or [`NO_EMITTER`] (instanced surfaces never emit).
#[inline]
pub(super) fn surface_emitter(scene: &Scene, h: &SurfaceHit) -> u32 {
    if h.hit.instance != NO_INSTANCE {
        return NO_EMITTER;
    }
    scene
        .emitters
        .of_shape
        .get(h.hit.shape as usize)
        .copied()
        .unwrap_or(NO_EMITTER)
}

/// The closest surface along `ray` that is there: a masked surface is passed through with the
/// probability of its transparency.
#[inline]
pub(super) fn intersect_through_masks<S: Sampler>(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut S,
    ctx: &mut TraceContext,
) -> Option<SurfaceHit> {
    let mut ray = *ray;
    for _ in 0..MAX_MASK_CROSSINGS {
        let hit = scene.intersect(&ray, f32::INFINITY, &mut ctx.traversal)?;
        // Always with texture coordinates: `surface_hit` computes them only where the material
        // reads them, and an emitting surface's radiance may read them too.
        let h = SurfaceHit {
            hit,
            si: scene.geometry.interaction_with(&ray, &hit, true),
        };
        if !scene.has_masks {
            return Some(h);
        }
        let opacity = Material::opacity(
            &scene.shading_materials,
            scene.geometry.material(&h.hit),
            h.si.uv,
        );
        if opacity >= 1.0 || sampler.get_1d() < opacity {
            return Some(h);
        }
        ray = Ray::new(
            offset_ray_origin(h.si.p, h.si.p_error, h.si.n, ray.dir),
            ray.dir,
        );
    }
    None
}

/// Whether the light at distance `t_max` along `dir` is seen from `si`.
#[inline]
pub(super) fn visible<S: Sampler>(
    scene: &Scene,
    si: &SurfaceInteraction,
    dir: Vec3,
    t_max: f32,
    sampler: &mut S,
    ctx: &mut TraceContext,
) -> bool {
    let ray = Ray::new(offset_ray_origin(si.p, si.p_error, si.n, dir), dir);
    visible_along(scene, ray, t_max, sampler, ctx)
}

/// Whether nothing blocks `ray` before `t_max` (a shadow ray), through cut-outs stochastically.
#[inline]
pub(super) fn visible_along<S: Sampler>(
    scene: &Scene,
    mut ray: Ray,
    t_max: f32,
    sampler: &mut S,
    ctx: &mut TraceContext,
) -> bool {
    ctx.rays.shadow += 1;
    let dir = ray.dir;
    if !scene.has_masks {
        return !scene.occluded(&ray, t_max, &mut ctx.traversal);
    }
    // Through cut-outs, stochastically, as camera and path rays go.
    let mut t_left = t_max;
    for _ in 0..MAX_MASK_CROSSINGS {
        let Some(hit) = scene.intersect(&ray, t_left, &mut ctx.traversal) else {
            return true;
        };
        let h = SurfaceHit {
            hit,
            si: scene.geometry.interaction_with(&ray, &hit, true),
        };
        let opacity = Material::opacity(
            &scene.shading_materials,
            scene.geometry.material(&h.hit),
            h.si.uv,
        );
        if opacity >= 1.0 || sampler.get_1d() < opacity {
            return false;
        }
        t_left -= hit.t;
        ray = Ray::new(offset_ray_origin(h.si.p, h.si.p_error, h.si.n, dir), dir);
    }
    false
}

/// Next-event estimation at `v` as [`PathTracer::light_sample`], weighted by the power heuristic
/// against BSDF sampling when `mis` is set, or the whole light-sampling estimate when the BSDF
/// side is not estimated by the caller (photon mapping's direct light). Draws three dimensions
/// whatever happens.
#[inline(always)]
pub(super) fn light_sample_weighted<S: Sampler>(
    scene: &Scene,
    st: &PathState,
    v: &Vertex,
    sampler: &mut S,
    mis: bool,
) -> Option<ShadowTest> {
    let emitters = &scene.emitters;
    let u_light = sampler.get_1d();
    let u_dir = sampler.get_2d();
    if !v.bsdf.flags().has_smooth() || emitters.picker.is_empty() {
        return None;
    }
    let (e, pmf) = emitters.picker.pick(u_light);
    let em = &emitters.emitters[e];
    let ls = em.sample_li(v.si.p, u_dir)?;
    let wi = v.frame.to_local(ls.wi);
    let (f, bsdf_pdf) = v.bsdf.eval_pdf(v.wo, wi);
    // As written (not `pmf <= 0.0`) so that a NaN pmf gives no sample.
    if !(f != Vec3::ZERO && pmf > 0.0) {
        return None;
    }
    let t_max = if ls.dist.is_finite() {
        ls.dist * (1.0 - SHADOW_EPSILON)
    } else {
        f32::INFINITY
    };
    let w = if ls.delta || !mis {
        1.0
    } else {
        mis_weight(ls.pdf * pmf, bsdf_pdf)
    };
    Some(ShadowTest {
        dir: ls.wi,
        t_max,
        contribution: st.throughput * f * ls.weight * (w / pmf),
    })
}
