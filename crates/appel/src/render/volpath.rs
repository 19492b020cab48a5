//! Volumetric path tracing: Mitsuba 3's `volpath` (its `max_depth`, `rr_depth`, `hide_emitters`),
//! the path tracer of `path.rs` with participating media between its surfaces.
//!
//! - Free flights are sampled by delta tracking with null collisions (Woodcock et al. 1965;
//!   pbrt-v4 section 14.2.2; Novák et al. 2018): tentative collisions at the rate of the medium's
//!   majorant, each a real scattering with probability `sigma_t / majorant` or a null collision
//!   that continues the flight (the choice weighed by all three channels: see
//!   [`scatter_probability`]).
//! - Extinction that differs between the RGB channels is handled as Mitsuba's `volpath` does in
//!   its RGB variants: each path picks one channel uniformly, samples distances with that
//!   channel's majorant, and weights all three channels by their transmittance over that
//!   channel's density (so a channel whose extinction is zero where another's is not is never
//!   sampled to scatter: Mitsuba's `volpathmis`, spectral MIS, is what removes that limit, and
//!   Appel does not have it).
//! - Shadow rays estimate transmittance through every medium they cross, switching media at the
//!   surfaces that bound them and passing through `null` surfaces: exactly (`exp(-sigma_t d)`)
//!   in homogeneous media, by ratio tracking (Cramer 1978; Novák et al. 2014) in heterogeneous
//!   ones.
//! - Next-event estimation is combined with BSDF and phase-function sampling by the power
//!   heuristic (Veach 1997); a `null` surface is no bounce: the depth, the last scattering
//!   vertex and its density stay as they were.

use super::integrator::{
    camera_ray, centre_aov, CameraRay, FilmSample, Integrator, PixelIntegrator,
};
use super::path::{intersect_through_masks, mis_weight, surface_emitter};
use super::sampler::Sampler;
use super::{with_sampler, Film, PixelAov, RenderOptions, RenderStats, TraceContext};
use crate::error::Result;
use crate::math::{offset_ray_origin, Ray, Vec3};
use crate::scene::{RenderSettings, Scene, NO_EMITTER};
use crate::shading::bsdf::BsdfFlags;
use crate::shading::frame::ShadingFrame;
use crate::shading::material::{Material, SurfacePoint};
use crate::shading::medium::Medium;

/// Shadow rays stop this fraction short of the sampled light point (as in `path.rs`).
const SHADOW_EPSILON: f32 = 1e-4;

/// Russian roulette keeps a path with at most this probability (Mitsuba's 0.95).
const RR_MAX_PROBABILITY: f32 = 0.95;

/// Surfaces a ray crosses without a bounce (null boundaries) before it is taken as lost; a
/// bound, not a tuning knob.
const MAX_CROSSINGS: u32 = 256;

#[derive(Clone, Copy, Debug)]
pub struct VolPath {
    /// The most scattering events of a path (surface or medium); `u32::MAX` for unlimited.
    pub max_depth: u32,
    pub rr_depth: u32,
    pub hide_emitters: bool,
}

impl VolPath {
    pub fn new(max_depth: i32, rr_depth: u32, hide_emitters: bool) -> Self {
        Self {
            max_depth: u32::try_from(max_depth).unwrap_or(u32::MAX),
            rr_depth,
            hide_emitters,
        }
    }
}

impl Integrator for VolPath {
    const NAME: &'static str = "volpath";

    fn from_settings(s: &RenderSettings) -> Result<Self> {
        Ok(Self::new(s.max_depth, s.rr_depth, s.hide_emitters))
    }

    fn render(&self, scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        with_sampler(scene, self, options)
    }
}

impl PixelIntegrator for VolPath {
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
        if let Some(aov) = aov {
            *aov = centre_aov(scene, x, y, ctx);
        }
        FilmSample {
            pos,
            radiance: self.li(scene, &ray, sampler, ctx),
        }
    }
}

/// The end of a free flight: a real scattering at `scatter`, or the end of the segment; `weight`
/// is what the flight multiplies the throughput by.
struct Flight {
    scatter: Option<Vec3>,
    weight: Vec3,
}

impl VolPath {
    /// The radiance arriving along `camera_ray`, estimated from the sampler's numbers.
    pub fn li<S: Sampler>(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        sampler: &mut S,
        ctx: &mut TraceContext,
    ) -> Vec3 {
        if self.max_depth == 0 {
            return Vec3::ZERO;
        }
        let emitters = &scene.emitters;
        // The channel whose majorant samples distances (Mitsuba's RGB volpath).
        let channel = ((sampler.get_1d() * 3.0) as usize).min(2);
        let mut medium = scene.media.camera;
        let mut ray = *camera_ray;
        let mut throughput = Vec3::ONE;
        let mut result = Vec3::ZERO;
        let mut eta = 1.0f32;
        let mut depth = 0u32;
        let mut crossings = 0u32;
        // The last scattering vertex (not a null crossing), for the MIS weight of emitters that
        // later hits find.
        let mut prev_p = ray.origin;
        let mut prev_pdf = 1.0f32;
        let mut prev_delta = true;
        while depth < self.max_depth && crossings < MAX_CROSSINGS {
            let hit = intersect_through_masks(scene, &ray, sampler, ctx);
            let t_surface = hit.as_ref().map_or(f32::INFINITY, |h| h.hit.t);
            if let Some(m) = scene.media.get(medium) {
                let flight = sample_flight(m, &ray, t_surface, channel, sampler);
                throughput *= flight.weight;
                if throughput.max_element() <= 0.0 || !throughput.is_finite() {
                    break;
                }
                if let Some(p) = flight.scatter {
                    depth += 1;
                    if depth >= self.max_depth {
                        break;
                    }
                    let d = ray.dir;
                    let phase = m.phase();
                    // Next-event estimation from the medium point.
                    let u_light = sampler.get_1d();
                    let u_dir = sampler.get_2d();
                    if !emitters.picker.is_empty() {
                        let (e, pmf) = emitters.picker.pick(u_light);
                        if let Some(ls) = emitters.emitters[e].sample_li(p, u_dir) {
                            let value = phase.eval(d, ls.wi);
                            if value > 0.0 && pmf > 0.0 {
                                let shadow = Ray::new(p, ls.wi);
                                let tr = transmittance(
                                    scene,
                                    shadow,
                                    shadow_length(ls.dist),
                                    medium,
                                    channel,
                                    sampler,
                                    ctx,
                                );
                                if tr != Vec3::ZERO {
                                    let w = if ls.delta {
                                        1.0
                                    } else {
                                        mis_weight(ls.pdf * pmf, phase.pdf(d, ls.wi))
                                    };
                                    result += throughput * tr * ls.weight * (value * w / pmf);
                                }
                            }
                        }
                    }
                    // Phase-function sampling continues the path.
                    let u1 = sampler.get_1d();
                    let u2 = sampler.get_2d();
                    let Some(ps) = phase.sample(d, u1, u2) else {
                        break;
                    };
                    ctx.rays.reflection += 1;
                    throughput *= ps.weight;
                    prev_p = p;
                    prev_pdf = ps.pdf;
                    prev_delta = false;
                    ray = Ray::new(p, ps.wo);
                    if !self.roulette(&mut throughput, eta, depth, sampler) {
                        break;
                    }
                    continue;
                }
            }
            // The flight reached the surface, or left the scene.
            let Some(h) = hit else {
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
            let interface = scene.media.interface(&h.hit);
            let frame = ShadingFrame::from_normal_tangent(si.ns, si.shading_tangent());
            let at = SurfacePoint::new(&si, &frame, wo_world, scene.geometry.attributes_at(&h.hit));
            let wo = at.wo;
            let material = scene.geometry.material(&h.hit);
            let bsdf = Material::bsdf(&scene.shading_materials, material, &at);
            // Next-event estimation, unless the next vertex would be beyond max_depth.
            let u_light = sampler.get_1d();
            let u_dir = sampler.get_2d();
            if bsdf.flags().has_smooth()
                && depth + 1 < self.max_depth
                && !emitters.picker.is_empty()
            {
                let (e, pmf) = emitters.picker.pick(u_light);
                if let Some(ls) = emitters.emitters[e].sample_li(si.p, u_dir) {
                    let (f, bsdf_pdf) = bsdf.eval_pdf(wo, frame.to_local(ls.wi));
                    if f != Vec3::ZERO && pmf > 0.0 {
                        let start = if interface.is_transition() {
                            interface.target(ls.wi, si.n)
                        } else {
                            medium
                        };
                        let shadow =
                            Ray::new(offset_ray_origin(si.p, si.p_error, si.n, ls.wi), ls.wi);
                        let tr = transmittance(
                            scene,
                            shadow,
                            shadow_length(ls.dist),
                            start,
                            channel,
                            sampler,
                            ctx,
                        );
                        if tr != Vec3::ZERO {
                            let w = if ls.delta {
                                1.0
                            } else {
                                mis_weight(ls.pdf * pmf, bsdf_pdf)
                            };
                            result += throughput * f * tr * ls.weight * (w / pmf);
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
            throughput *= bs.weight;
            eta *= bs.eta;
            if interface.is_transition() {
                medium = interface.target(wi_world, si.n);
            }
            ray = Ray::new(
                offset_ray_origin(si.p, si.p_error, si.n, wi_world),
                wi_world,
            );
            if bs.lobe.contains(BsdfFlags::NULL) {
                // An index-matched boundary: the same path, in the next medium.
                crossings += 1;
                continue;
            }
            if bs.lobe.contains(BsdfFlags::DELTA_TRANSMISSION)
                || bs.lobe.contains(BsdfFlags::GLOSSY_TRANSMISSION)
                || bs.lobe.contains(BsdfFlags::DIFFUSE_TRANSMISSION)
            {
                ctx.rays.refraction += 1;
            } else {
                ctx.rays.reflection += 1;
            }
            depth += 1;
            crossings = 0;
            prev_p = si.p;
            prev_pdf = bs.pdf;
            prev_delta = bs.lobe.is_delta();
            if !self.roulette(&mut throughput, eta, depth, sampler) {
                break;
            }
        }
        result
    }

    /// Russian roulette after a scattering event, from Mitsuba's volpath's depth (`depth >
    /// rr_depth`) on the throughput with refraction's radiance scaling undone; `false` ends the
    /// path.
    #[inline]
    fn roulette<S: Sampler>(
        &self,
        throughput: &mut Vec3,
        eta: f32,
        depth: u32,
        sampler: &mut S,
    ) -> bool {
        let t_max = throughput.max_element() * eta * eta;
        if t_max <= 0.0 || !t_max.is_finite() {
            return false;
        }
        if depth > self.rr_depth {
            let q = t_max.min(RR_MAX_PROBABILITY);
            if sampler.get_1d() >= q {
                return false;
            }
            *throughput /= q;
        }
        true
    }
}

/// How far a shadow ray toward a light `dist` away goes.
#[inline]
fn shadow_length(dist: f32) -> f32 {
    if dist.is_finite() {
        dist * (1.0 - SHADOW_EPSILON)
    } else {
        f32::INFINITY
    }
}

/// `exp(-sigma * d)` per channel (`sigma` may be negative: a ratio of two exponentials), 1 where
/// `sigma` is 0, even for an infinite `d`.
#[inline]
fn beer_lambert(sigma: Vec3, d: f32) -> Vec3 {
    Vec3::from_array(
        sigma
            .to_array()
            .map(|s| if s == 0.0 { 1.0 } else { (-s * d).exp() }),
    )
}

/// A free flight along `ray` through medium `m` up to `t_surface` by delta tracking over the
/// medium's majorant segments (pbrt-v4's `SampleT_maj`), distances drawn with the segment's
/// majorant of `channel`. A tentative collision at distance `dt` has density `m_c exp(-m_c dt)`
/// and the majorant's transmittance `exp(-majorant dt)` per channel; it scatters with
/// [`scatter_probability`] (weight `sigma_s` over that probability), or is null (weight
/// `majorant - sigma_t` over its probability); passing a segment's end has probability
/// `exp(-m_c d)`, and the exponential's memorylessness lets the next segment draw afresh at its
/// own rate.
fn sample_flight<S: Sampler>(
    m: &Medium,
    ray: &Ray,
    t_surface: f32,
    channel: usize,
    sampler: &mut S,
) -> Flight {
    let mut weight = Vec3::ONE;
    for segment in m.majorants(ray, t_surface) {
        let majorant = segment.majorant;
        let m_c = majorant[channel];
        if m_c <= 0.0 || !m_c.is_finite() {
            // This channel sees nothing to collide with here: the others' transmittance.
            weight *= beer_lambert(majorant, segment.t1 - segment.t0);
            continue;
        }
        let mut t = segment.t0;
        loop {
            let dt = -(1.0 - sampler.get_1d()).ln() / m_c;
            if t + dt >= segment.t1 {
                // exp(-majorant d) / exp(-m_c d).
                weight *= beer_lambert(majorant - m_c, segment.t1 - t);
                break;
            }
            t += dt;
            let p = ray.at(t);
            let (sigma_t, sigma_s) = m.coefficients(p);
            // The majorant's transmittance over the collision's density.
            let ratio = beer_lambert(majorant - m_c, dt) / m_c;
            let p_scatter = scatter_probability(sigma_t, majorant);
            if sampler.get_1d() < p_scatter {
                return Flight {
                    scatter: Some(p),
                    weight: weight * ratio * sigma_s / p_scatter,
                };
            }
            weight *= ratio * (majorant - sigma_t).max(Vec3::ZERO) / (1.0 - p_scatter);
            if weight.max_element() <= 0.0 || !weight.is_finite() {
                return Flight {
                    scatter: None,
                    weight: Vec3::ZERO,
                };
            }
        }
    }
    Flight {
        scatter: None,
        weight,
    }
}

/// The probability that a tentative collision is real: the mean over the channels of
/// `sigma_t / majorant`. Mitsuba's volpath takes the sampling channel's ratio alone, which is 0
/// or 1 where another channel's is not (an RGB grid, whose one majorant is its largest channel's
/// value), and then misses that channel's null collisions or its scattering: a bias. The mean is
/// zero only where no channel scatters and one only where no channel has null collisions, so
/// every channel's estimate stays unbiased.
#[inline]
fn scatter_probability(sigma_t: Vec3, majorant: Vec3) -> f32 {
    let (mut sum, mut n) = (0.0f32, 0.0f32);
    for k in 0..3 {
        if majorant[k] > 0.0 {
            sum += (sigma_t[k] / majorant[k]).clamp(0.0, 1.0);
            n += 1.0;
        }
    }
    if n > 0.0 {
        sum / n
    } else {
        0.0
    }
}

/// The transmittance of medium `m` along `ray` up to `t_end`: exact in a homogeneous medium,
/// else ratio tracking over the medium's majorant segments with `channel`'s majorant (each
/// tentative collision weighs `(majorant - sigma_t)` over the majorant, with the channels'
/// transmittance ratio).
fn medium_transmittance<S: Sampler>(
    m: &Medium,
    ray: &Ray,
    t_end: f32,
    channel: usize,
    sampler: &mut S,
) -> Vec3 {
    let mut tr = Vec3::ONE;
    for segment in m.majorants(ray, t_end) {
        let majorant = segment.majorant;
        let m_c = majorant[channel];
        if m.is_homogeneous() || m_c <= 0.0 || !m_c.is_finite() {
            tr *= beer_lambert(majorant, segment.t1 - segment.t0);
            continue;
        }
        let mut t = segment.t0;
        loop {
            let dt = -(1.0 - sampler.get_1d()).ln() / m_c;
            if t + dt >= segment.t1 {
                tr *= beer_lambert(majorant - m_c, segment.t1 - t);
                break;
            }
            t += dt;
            let (sigma_t, _) = m.coefficients(ray.at(t));
            tr *= beer_lambert(majorant - m_c, dt) * (majorant - sigma_t).max(Vec3::ZERO) / m_c;
            if tr.max_element() <= 0.0 || !tr.is_finite() {
                return Vec3::ZERO;
            }
        }
    }
    tr
}

/// The transmittance from `ray`'s origin to distance `t_max` along it, starting in `medium`:
/// through the media it crosses and the surfaces with a null lobe (the `null` BSDF, a thin
/// dielectric's straight transmission; cut-outs too) on the way, each by its
/// `null_transmission`; zero at the first other surface.
fn transmittance<S: Sampler>(
    scene: &Scene,
    mut ray: Ray,
    t_max: f32,
    mut medium: u32,
    channel: usize,
    sampler: &mut S,
    ctx: &mut TraceContext,
) -> Vec3 {
    ctx.rays.shadow += 1;
    let mut tr = Vec3::ONE;
    let mut t_left = t_max;
    for _ in 0..MAX_CROSSINGS {
        let hit = scene.intersect(&ray, t_left, &mut ctx.traversal);
        if let Some(m) = scene.media.get(medium) {
            let end = hit.as_ref().map_or(t_left, |h| h.t);
            tr *= medium_transmittance(m, &ray, end, channel, sampler);
            if tr == Vec3::ZERO {
                return tr;
            }
        }
        let Some(hit) = hit else {
            return tr;
        };
        let si = scene.geometry.interaction_with(&ray, &hit, true);
        let material = scene.geometry.material(&hit);
        let opacity = if scene.has_masks {
            Material::opacity(&scene.shading_materials, material, si.uv)
        } else {
            1.0
        };
        // A cut-out is passed with its transparency's probability, as path rays pass it.
        if opacity >= 1.0 || sampler.get_1d() < opacity {
            let frame = ShadingFrame::from_normal_tangent(si.ns, si.shading_tangent());
            let at = SurfacePoint::new(&si, &frame, -ray.dir, scene.geometry.attributes_at(&hit));
            let bsdf = Material::bsdf(&scene.shading_materials, material, &at);
            tr *= bsdf.null_transmission(at.wo);
            if tr == Vec3::ZERO {
                return tr;
            }
        }
        let interface = scene.media.interface(&hit);
        if interface.is_transition() {
            medium = interface.target(ray.dir, si.n);
        }
        t_left -= hit.t;
        ray = Ray::new(offset_ray_origin(si.p, si.p_error, si.n, ray.dir), ray.dir);
    }
    Vec3::ZERO
}

#[cfg(test)]
mod tracking_tests;
