//! Unidirectional path tracing with next-event estimation, multiple importance sampling of BSDF
//! and emitter samples by the power heuristic (Veach and Guibas 1995), and Russian roulette: the
//! estimator of Mitsuba 3's `path` integrator, with its meaning of `max_depth` (1: emitters seen
//! directly; 2: direct light; -1: unlimited) and of `rr_depth`. The `direct` integrator is the same
//! estimator stopped after direct light.

use super::integrator::{camera_ray, centre_aov, CameraRay, FilmSample, Integrator, SurfaceHit};
use super::sampler::Sampler;
use super::{PixelAov, TraceContext};
use crate::error::Result;
use crate::geometry::SurfaceInteraction;
use crate::math::{offset_ray_origin, Ray, Vec3};
use crate::scene::{RenderSettings, Scene, NO_EMITTER, NO_INSTANCE};
use crate::shading::bsdf::BsdfFlags;
use crate::shading::frame::ShadingFrame;
use crate::shading::material::{Material, SurfacePoint};

/// Shadow rays stop this fraction short of the sampled light point, so that the light's own
/// surface does not occlude it (relative to the segment: scale-free).
const SHADOW_EPSILON: f32 = 1e-4;

/// Russian roulette keeps a path with at most this probability (Mitsuba's 0.95), so that even
/// bright paths end eventually.
const RR_MAX_PROBABILITY: f32 = 0.95;

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
            max_depth: if max_depth < 0 {
                u32::MAX
            } else {
                max_depth as u32
            },
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
}

impl PathTracer {
    /// The radiance arriving along `camera_ray`, estimated from the sampler's numbers.
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
        let emitters = &scene.emitters;
        let mut ray = *camera_ray;
        let mut throughput = Vec3::ONE;
        let mut result = Vec3::ZERO;
        let mut eta = 1.0f32;
        let mut depth = 0u32;
        // The previous vertex, for the MIS weight of emitters hit by BSDF samples.
        let mut prev_p = ray.origin;
        let mut prev_pdf = 1.0f32;
        let mut prev_delta = true;
        loop {
            let hit = intersect_through_masks(scene, &ray, sampler, ctx);
            let Some(h) = hit else {
                // Leaving the scene: the environment.
                if depth > 0 || !self.hide_emitters {
                    for &e in &emitters.infinite {
                        let em = &emitters.emitters[e as usize];
                        let le = em.radiance_env(ray.dir);
                        let w = if prev_delta {
                            1.0
                        } else {
                            let pdf = emitters.picker.pmf(e as usize)
                                * em.pdf_li(prev_p, ray.dir, Vec3::ZERO, Vec3::ZERO);
                            mis_weight(prev_pdf, pdf)
                        };
                        result += throughput * le * w;
                    }
                }
                break;
            };
            let si = h.si;
            let wo_world = -ray.dir;
            // Emission of the surface hit.
            let emitter = surface_emitter(scene, &h);
            if emitter != NO_EMITTER && (depth > 0 || !self.hide_emitters) {
                let em = &emitters.emitters[emitter as usize];
                let le = em.radiance_area(si.ns, si.uv, wo_world);
                if le != Vec3::ZERO {
                    let w = if prev_delta {
                        1.0
                    } else {
                        let pdf = emitters.picker.pmf(emitter as usize)
                            * em.pdf_li(prev_p, ray.dir, si.p, si.n);
                        mis_weight(prev_pdf, pdf)
                    };
                    result += throughput * le * w;
                }
            }
            if depth + 1 >= self.max_depth {
                break;
            }
            let frame = ShadingFrame::from_normal_tangent(si.ns, si.shading_tangent());
            let at = SurfacePoint::new(&si, &frame, wo_world, scene.geometry.attributes_at(&h.hit));
            let wo = at.wo;
            let material = scene.geometry.material(&h.hit);
            let bsdf = Material::bsdf(&scene.shading_materials, material, &at);
            // Next-event estimation: one emitter, chosen by power.
            let u_light = sampler.get_1d();
            let u_dir = sampler.get_2d();
            if bsdf.flags().has_smooth() && !emitters.picker.is_empty() {
                let (e, pmf) = emitters.picker.pick(u_light);
                let em = &emitters.emitters[e];
                if let Some(ls) = em.sample_li(si.p, u_dir) {
                    let wi = frame.to_local(ls.wi);
                    let (f, bsdf_pdf) = bsdf.eval_pdf(wo, wi);
                    if f != Vec3::ZERO && pmf > 0.0 {
                        let t_max = if ls.dist.is_finite() {
                            ls.dist * (1.0 - SHADOW_EPSILON)
                        } else {
                            f32::INFINITY
                        };
                        if visible(scene, &si, ls.wi, t_max, sampler, ctx) {
                            let w = if ls.delta {
                                1.0
                            } else {
                                mis_weight(ls.pdf * pmf, bsdf_pdf)
                            };
                            result += throughput * f * ls.weight * (w / pmf);
                        }
                    }
                }
            }
            // BSDF sampling continues the path.
            let u_lobe = sampler.get_1d();
            let u_bsdf = sampler.get_2d();
            let Some(bs) = bsdf.sample(wo, u_lobe, u_bsdf) else {
                break;
            };
            let wi_world = frame.to_world(bs.wi);
            if bs.lobe.contains(BsdfFlags::DIFFUSE_TRANSMISSION)
                || bs.lobe.contains(BsdfFlags::GLOSSY_TRANSMISSION)
                || bs.lobe.contains(BsdfFlags::DELTA_TRANSMISSION)
            {
                ctx.rays.refraction += 1;
            } else {
                ctx.rays.reflection += 1;
            }
            throughput *= bs.weight;
            eta *= bs.eta;
            prev_p = si.p;
            prev_pdf = bs.pdf;
            prev_delta = bs.lobe.is_delta();
            ray = Ray::new(
                offset_ray_origin(si.p, si.p_error, si.n, wi_world),
                wi_world,
            );
            depth += 1;
            // Russian roulette on the throughput with the refraction's radiance scaling undone
            // (Mitsuba: max(throughput) eta^2).
            let t_max = throughput.max_element() * eta * eta;
            if t_max <= 0.0 || !t_max.is_finite() {
                break;
            }
            if depth >= self.rr_depth {
                let q = t_max.min(RR_MAX_PROBABILITY);
                if sampler.get_1d() >= q {
                    break;
                }
                throughput /= q;
            }
        }
        result
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
fn visible<S: Sampler>(
    scene: &Scene,
    si: &SurfaceInteraction,
    dir: Vec3,
    t_max: f32,
    sampler: &mut S,
    ctx: &mut TraceContext,
) -> bool {
    ctx.rays.shadow += 1;
    let mut ray = Ray::new(offset_ray_origin(si.p, si.p_error, si.n, dir), dir);
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
