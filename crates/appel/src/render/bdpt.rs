//! Bidirectional path tracing (Veach 1997 chapter 10; pbrt-v4's `BDPTIntegrator`, section 13.4 of
//! the third edition): a camera subpath and a light subpath, every prefix of one joined to every
//! prefix of the other, each joined path weighted by the balance heuristic over all the ways of
//! sampling it (Veach's `(s, t)` strategies: `s` light vertices, `t` camera vertices).
//!
//! The strategies with `t >= 2` are estimated per pixel sample through the render loop
//! ([`BdptCamera`]); those with `t = 1` (light subpaths connected to the camera) land anywhere on
//! the film and are splatted as light tracing's are, by deterministic batches of light paths
//! ([`BdptLight`], `light_pass`), from light subpaths of their own. The two films are independent
//! estimates of the two parts of the image: their sum is the image, the sum of their variances
//! its variance. Each strategy's weight depends on the path alone, so the weights still sum to
//! one over the strategies, whichever subpaths they came from (Veach 1997 section 9.2).
//!
//! `max_depth` is Mitsuba's (the most segments of a path; -1: unlimited, with Russian roulette
//! after `rr_depth` vertices, as `path`). Shading normals and refraction are handled as
//! `ptracer` handles them on the light side (Veach 1997 sections 5.2, 5.3). Lights at infinity
//! (environments, the sun and sky, directional lights) start their subpaths on a disk of the
//! scene's bounding sphere's radius and are reached by camera subpaths that leave the scene; their
//! vertices keep densities by solid angle (pbrt-v4's treatment). Orthographic cameras are an
//! error.

use super::integrator::{
    camera_ray, centre_aov, vertex_limit, CameraRay, FilmSample, Integrator, PixelIntegrator,
    PixelRow,
};
use super::light_pass::{render_light_paths, start_light_path, LightPathTracer};
use super::path::{
    intersect_through_masks, surface_emitter, visible_along, RR_MAX_PROBABILITY, SHADOW_EPSILON,
};
use super::ptracer::check_camera;
use super::sampler::Sampler;
use super::splat_film::Splat;
use super::{with_sampler, Film, PixelAov, RenderOptions, RenderStats, TraceContext};
use crate::description::StrategyImages;
use crate::error::{Error, Result};
use crate::math::{offset_ray_origin, Ray, Vec2, Vec3};
use crate::scene::{RenderSettings, Scene, NO_EMITTER};
use crate::shading::frame::ShadingFrame;
use crate::shading::material::{Material, SurfaceBsdf, SurfacePoint};

/// Which way a subpath carries light: a camera subpath gathers radiance, a light subpath carries
/// importance's adjoint, light (Veach's transport modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    Radiance,
    Importance,
}

#[derive(Clone, Copy, Debug)]
pub(crate) enum Kind {
    /// The lens point.
    Camera,
    /// A point of an emitter (index), the first vertex of a light subpath.
    Light(u32),
    /// A surface point; its emitter or [`NO_EMITTER`].
    Surface(u32),
    /// A light at infinity: the first vertex of a light subpath from an infinite emitter (its
    /// index), or where a camera subpath leaves the scene ([`NO_EMITTER`]: every infinite light
    /// seen along that direction). Its point only gives directions: the origin of the light's
    /// ray on the disk it enters through, or one unit past the vertex the camera's ray left.
    Infinite(u32),
}

/// A vertex of a subpath.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Vertex {
    pub kind: Kind,
    pub p: Vec3,
    pub p_error: Vec3,
    /// Unit geometric normal; zero for points that are no surface (a pinhole, a point light).
    pub n: Vec3,
    pub frame: ShadingFrame,
    pub bsdf: Option<SurfaceBsdf>,
    pub uv: Vec2,
    /// The subpath's throughput up to this vertex (for a light's vertex, `1 / pdf`: see
    /// [`light_subpath`]).
    pub beta: Vec3,
    /// Whether the direction leaving this vertex was sampled from a delta lobe.
    pub delta: bool,
    /// Density by area of this vertex as its own subpath sampled it, and as the other direction
    /// would have.
    pub pdf_fwd: f32,
    pub pdf_rev: f32,
}

impl Vertex {
    fn emitter(&self) -> u32 {
        match self.kind {
            Kind::Light(e) | Kind::Surface(e) | Kind::Infinite(e) => e,
            Kind::Camera => NO_EMITTER,
        }
    }

    fn is_infinite(&self) -> bool {
        matches!(self.kind, Kind::Infinite(_))
    }

    /// Whether the path can be joined at this vertex (a surface with a smooth lobe, a light, the
    /// camera).
    fn connectible(&self) -> bool {
        match self.kind {
            Kind::Surface(_) => self.bsdf.is_some_and(|b| b.flags().has_smooth()),
            Kind::Infinite(_) => false,
            Kind::Camera | Kind::Light(_) => true,
        }
    }
}

/// `pdf` by solid angle at `from` toward `to`, as a density by area at `to`; a light at
/// infinity keeps densities by solid angle (pbrt-v4's `ConvertDensity`).
fn to_area(pdf: f32, from: &Vertex, to: &Vertex) -> f32 {
    if to.is_infinite() {
        return pdf;
    }
    let w = to.p - from.p;
    let d2 = w.length_squared();
    if d2.is_nan() || d2 <= 0.0 {
        return 0.0;
    }
    let mut pdf = pdf / d2;
    if to.n != Vec3::ZERO {
        pdf *= to.n.dot(w).abs() / d2.sqrt();
    }
    pdf
}

/// The scattering at a surface vertex for light arriving from `toward_light` and leaving toward
/// `toward_eye` (world directions), per unit of geometric cosine on the light's side: the
/// radiance BSDF with its shading cosine at the light's side over the geometric one,
/// `f(ω_E, ω_L) |n_s·ω_L| / |n_g·ω_L|`, which both transport directions share once shading
/// normals are corrected for (Veach 1997 section 5.3): the camera side's BSDF samples and the
/// light side's adjoint ones both reduce to it times the geometric terms.
fn scattering(v: &Vertex, toward_eye: Vec3, toward_light: Vec3) -> Vec3 {
    let Some(bsdf) = &v.bsdf else {
        return Vec3::ZERO;
    };
    let (e, l) = (v.frame.to_local(toward_eye), v.frame.to_local(toward_light));
    // Light leaks: the shading and geometric normals must agree on each side.
    let (cg_e, cg_l) = (v.n.dot(toward_eye), v.n.dot(toward_light));
    if cg_e * e.z <= 0.0 || cg_l * l.z <= 0.0 {
        return Vec3::ZERO;
    }
    bsdf.eval_pdf(e, l).0 / cg_l.abs()
}

/// The density by area at `next` with which `cur` samples it, `prev` the vertex before `cur` on
/// the same subpath (none for a subpath's first vertex).
fn pdf(scene: &Scene, cur: &Vertex, prev: Option<&Vertex>, next: &Vertex) -> f32 {
    let w = next.p - cur.p;
    let len = w.length();
    if len.is_nan() || len <= 0.0 {
        return 0.0;
    }
    let w = w / len;
    let pdf_dir = match cur.kind {
        Kind::Camera => scene.camera.pdf_direction(cur.p, w),
        Kind::Light(_) | Kind::Infinite(_) => return pdf_light(scene, cur, next),
        Kind::Surface(_) => {
            let (Some(bsdf), Some(prev)) = (&cur.bsdf, prev) else {
                return 0.0;
            };
            let wp = (prev.p - cur.p).normalize();
            bsdf.eval_pdf(cur.frame.to_local(wp), cur.frame.to_local(w))
                .1
        }
    };
    to_area(pdf_dir, cur, next)
}

/// The density by area at `next` of a ray leaving the emitting vertex `v`. The rays of a light at
/// infinity cross a disk of the scene's bounding sphere's radius uniformly (see
/// `emission::infinite_ray`): their density at `next` is the disk's, projected.
fn pdf_light(scene: &Scene, v: &Vertex, next: &Vertex) -> f32 {
    let w = (next.p - v.p).normalize();
    if v.is_infinite() {
        let r = scene.emitters.sphere.1;
        let pdf = 1.0 / (std::f32::consts::PI * r * r);
        return if next.n == Vec3::ZERO {
            pdf
        } else {
            pdf * next.n.dot(w).abs()
        };
    }
    let e = v.emitter();
    if e == NO_EMITTER {
        return 0.0;
    }
    let pdf_dir = scene.emitters.emitters[e as usize].pdf_ray_dir(v.n, w);
    to_area(pdf_dir, v, next)
}

/// The density with which a light subpath starts at the emitting vertex `v` joined to `next`:
/// the light's choice times its point's by area; for a light at infinity, the density by solid
/// angle of its direction toward `next` (pbrt-v4's `PdfLightOrigin`).
fn pdf_light_origin(scene: &Scene, v: &Vertex, next: &Vertex) -> f32 {
    if v.is_infinite() {
        return infinite_light_density(scene, next.p, (v.p - next.p).normalize());
    }
    let e = v.emitter();
    if e == NO_EMITTER {
        return 0.0;
    }
    let em = &scene.emitters;
    em.picker.pmf(e as usize) * em.emitters[e as usize].pdf_position()
}

/// The density by solid angle of direction `wi` (toward the lights) over all the infinite lights,
/// each weighted by its choice. A camera subpath that leaves the scene sees them all at once, so
/// they are weighed as one light (pbrt-v4's `InfiniteLightDensity`); exact for one environment.
fn infinite_light_density(scene: &Scene, p: Vec3, wi: Vec3) -> f32 {
    let em = &scene.emitters;
    em.infinite
        .iter()
        .map(|&e| {
            em.picker.pmf(e as usize)
                * em.emitters[e as usize].pdf_li(p, wi, Vec3::ZERO, Vec3::ZERO)
        })
        .sum()
}

fn is_delta_light(scene: &Scene, v: &Vertex) -> bool {
    matches!(v.kind, Kind::Light(e) | Kind::Infinite(e)
        if e != NO_EMITTER && scene.emitters.emitters[e as usize].is_delta())
}

/// The deepest paths whose strategies get images of their own: `d + 2` images a depth `d` past
/// the first, 64 in all at 10, each 24 bytes a pixel.
const MAX_DEPTH_OF_STRATEGY_IMAGES: u32 = 10;

#[derive(Clone, Copy, Debug)]
pub struct Bdpt {
    /// The most segments of a path; `u32::MAX` for unlimited.
    pub max_depth: u32,
    pub rr_depth: u32,
    pub hide_emitters: bool,
    /// The strategies' images written beside the render, if any.
    pub strategy_images: Option<StrategyImages>,
    /// Whether BSDFs past a subpath's first non-delta bounce are roughened (pbrt-v4's
    /// `regularize`, see `BdptParams::regularize`).
    pub regularize: bool,
}

impl Bdpt {
    /// The most vertices of a camera subpath (the camera's among them) and of a light subpath.
    fn camera_vertices(&self) -> usize {
        self.max_depth.saturating_add(1).min(u32::MAX - 1) as usize
    }

    fn light_vertices(&self) -> usize {
        self.max_depth as usize
    }
}

/// Extends `path` (whose last vertex left along `ray` with density `pdf_dir` by solid angle and
/// throughput `beta` so far) by sampling surfaces, up to `max` vertices: pbrt-v4's `RandomWalk`,
/// with Russian roulette after `rr_depth` vertices.
#[allow(clippy::too_many_arguments)]
fn random_walk<S: Sampler>(
    scene: &Scene,
    sampler: &mut S,
    mut ray: Ray,
    mut beta: Vec3,
    mut pdf_dir: f32,
    max: usize,
    integrator: &Bdpt,
    mode: Mode,
    path: &mut Vec<Vertex>,
    ctx: &mut TraceContext,
) {
    let mut eta = 1.0f32;
    let mut any_non_delta = false;
    while path.len() < max {
        let Some(h) = intersect_through_masks(scene, &ray, sampler, ctx) else {
            // A camera subpath that leaves the scene ends on the infinite lights.
            if mode == Mode::Radiance && !scene.emitters.infinite.is_empty() {
                let last = path.last().expect("a subpath starts with its endpoint");
                path.push(Vertex {
                    kind: Kind::Infinite(NO_EMITTER),
                    p: last.p + ray.dir,
                    p_error: Vec3::ZERO,
                    n: Vec3::ZERO,
                    frame: ShadingFrame::from_normal(-ray.dir),
                    bsdf: None,
                    uv: Vec2::ZERO,
                    beta,
                    delta: false,
                    pdf_fwd: pdf_dir,
                    pdf_rev: 0.0,
                });
            }
            break;
        };
        let si = h.si;
        let w_prev = -ray.dir;
        let frame = ShadingFrame::from_normal_tangent(si.ns, si.shading_tangent());
        let at = SurfacePoint::new(&si, &frame, w_prev, scene.geometry.attributes_at(&h.hit));
        let mut bsdf = Material::bsdf(
            &scene.shading_materials,
            scene.geometry.material(&h.hit),
            &at,
        );
        if integrator.regularize && any_non_delta {
            bsdf = bsdf.regularized();
        }
        let mut v = Vertex {
            kind: Kind::Surface(surface_emitter(scene, &h)),
            p: si.p,
            p_error: si.p_error,
            n: si.n,
            frame,
            bsdf: Some(bsdf),
            uv: si.uv,
            beta,
            delta: false,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
        };
        v.pdf_fwd = to_area(
            pdf_dir,
            path.last().expect("a subpath starts with its endpoint"),
            &v,
        );
        path.push(v);
        if path.len() >= max {
            break;
        }
        let wo = at.wo;
        let u_lobe = sampler.get_1d();
        let u_bsdf = sampler.get_2d();
        let Some(bs) = bsdf.sample(wo, u_lobe, u_bsdf) else {
            break;
        };
        let wi = frame.to_world(bs.wi);
        let (cg_o, cg_i) = (si.n.dot(w_prev), si.n.dot(wi));
        if cg_o * wo.z <= 0.0 || cg_i * bs.wi.z <= 0.0 {
            break;
        }
        let delta = bs.lobe.is_delta();
        any_non_delta |= !delta;
        let (mut fwd, mut rev) = (bs.pdf, bsdf.eval_pdf(bs.wi, wo).1);
        if delta {
            (fwd, rev) = (0.0, 0.0);
        }
        beta *= match mode {
            Mode::Radiance => bs.weight,
            // The adjoint BSDF: refraction's radiance scaling undone, shading normals corrected
            // (as `ptracer`).
            Mode::Importance => {
                bs.weight * (bs.eta * bs.eta * (wo.z * cg_i / (bs.wi.z * cg_o)).abs())
            }
        };
        eta *= bs.eta;
        let n = path.len();
        path[n - 1].delta = delta;
        path[n - 2].pdf_rev = to_area(rev, &path[n - 1], &path[n - 2]);
        pdf_dir = fwd;
        if bs.wi.z * wo.z < 0.0 {
            ctx.rays.refraction += 1;
        } else {
            ctx.rays.reflection += 1;
        }
        ray = Ray::new(offset_ray_origin(si.p, si.p_error, si.n, wi), wi);
        let t = beta.max_element() * eta * eta;
        if t <= 0.0 || !t.is_finite() {
            break;
        }
        if path.len() as u32 >= integrator.rr_depth {
            let q = t.min(RR_MAX_PROBABILITY);
            if sampler.get_1d() >= q {
                break;
            }
            beta /= q;
        }
    }
}

/// The camera subpath of a camera ray: the lens point, then the surfaces.
fn camera_subpath<S: Sampler>(
    scene: &Scene,
    integrator: &Bdpt,
    ray: &Ray,
    sampler: &mut S,
    path: &mut Vec<Vertex>,
    ctx: &mut TraceContext,
) {
    let camera = &scene.camera;
    // Camera rays start on the near plane; the vertex is the lens point behind it.
    let lens = ray.origin - ray.dir * (camera.near_clip / ray.dir.dot(camera.forward));
    path.push(Vertex {
        kind: Kind::Camera,
        p: lens,
        p_error: Vec3::ZERO,
        n: Vec3::ZERO,
        frame: ShadingFrame::from_normal(camera.forward),
        bsdf: None,
        uv: Vec2::ZERO,
        beta: Vec3::ONE,
        delta: false,
        pdf_fwd: 1.0,
        pdf_rev: 0.0,
    });
    let pdf_dir = camera.pdf_direction(lens, ray.dir);
    random_walk(
        scene,
        sampler,
        *ray,
        Vec3::ONE,
        pdf_dir,
        integrator.camera_vertices(),
        integrator,
        Mode::Radiance,
        path,
        ctx,
    );
}

/// A light subpath: a light and a point of it (whose vertex carries `1 / (pmf pdf_pos)`, the
/// emitted radiance being evaluated toward whatever it is joined to), then the surfaces.
fn light_subpath<S: Sampler>(
    scene: &Scene,
    integrator: &Bdpt,
    sampler: &mut S,
    path: &mut Vec<Vertex>,
    ctx: &mut TraceContext,
) {
    let max = integrator.light_vertices();
    let Some(start) = start_light_path(scene, sampler) else {
        return;
    };
    if max == 0 {
        return;
    }
    let (er, pmf) = (&start.emitted, start.pmf);
    let pdf_origin = pmf * er.pdf_pos;
    let e = start.emitter as u32;
    let infinite = scene.emitters.emitters[e as usize].is_infinite();
    path.push(Vertex {
        kind: if infinite {
            Kind::Infinite(e)
        } else {
            Kind::Light(e)
        },
        p: er.origin,
        p_error: er.origin_error,
        n: er.normal,
        frame: ShadingFrame::from_normal(if er.normal == Vec3::ZERO {
            er.dir
        } else {
            er.normal
        }),
        bsdf: None,
        uv: Vec2::ZERO,
        beta: Vec3::splat(1.0 / pdf_origin),
        delta: false,
        pdf_fwd: pdf_origin,
        pdf_rev: 0.0,
    });
    path[0].uv = er.uv;
    random_walk(
        scene,
        sampler,
        start.ray,
        er.weight / pmf,
        er.pdf_dir,
        max,
        integrator,
        Mode::Importance,
        path,
        ctx,
    );
    if infinite {
        // The first surface's density is the disk's projected onto it, not the direction's over
        // a distance; the light's own is its direction's (pbrt-v4's `GenerateLightSubpath`).
        if let Some(v) = path.get_mut(1) {
            v.pdf_fwd = er.pdf_pos;
            if v.n != Vec3::ZERO {
                v.pdf_fwd *= v.n.dot(er.dir).abs();
            }
        }
        path[0].pdf_fwd = infinite_light_density(scene, er.origin, -er.dir);
    }
}

/// The subpaths of one sample, kept from one sample to the next so that their vectors are
/// allocated once per row of pixels (or chunk of light paths), not per sample.
#[derive(Default)]
pub struct Subpaths {
    camera: Vec<Vertex>,
    light: Vec<Vertex>,
}

impl Subpaths {
    /// Room for the subpaths of `b` up to a few bounces (they grow past it if they must).
    fn for_integrator(b: &Bdpt) -> Self {
        const TYPICAL: usize = 16;
        Subpaths {
            camera: Vec::with_capacity(b.camera_vertices().min(TYPICAL)),
            light: Vec::with_capacity(b.light_vertices().min(TYPICAL)),
        }
    }
}

/// Vertex `i` of a subpath, `sampled` standing in for its first vertex where a strategy
/// sampled that afresh.
#[inline]
fn vertex_of<'a>(path: &'a [Vertex], sampled: Option<&'a Vertex>, i: usize) -> &'a Vertex {
    match sampled {
        Some(v) if i == 0 => v,
        _ => &path[i],
    }
}

/// The balance heuristic's weight of strategy `(s, t)` for the path of `light[..s]` and
/// `camera[..t]`, `sampled` the vertex a strategy with `s = 1` or `t = 1` sampled afresh in
/// place of the subpath's first (pbrt-v4's `MISWeight`): the densities of the vertices next to
/// the join are those the other direction would have sampled them with, and the weight is
/// `1 / sum_i (p_i / p_s)` over every strategy `i` that could have made the path (none through
/// a delta vertex), each ratio built up vertex by vertex from the join outward (Veach 1997
/// section 10.2). The subpaths are read, never copied: the four reverse densities the join
/// changes and the two endpoints' delta flags (a join is never through a delta lobe) are
/// overridden as they are read.
fn mis_weight(
    scene: &Scene,
    light: &[Vertex],
    camera: &[Vertex],
    sampled: Option<&Vertex>,
    (s, t): (usize, usize),
) -> f32 {
    if s + t == 2 {
        return 1.0;
    }
    let lv = |i: usize| vertex_of(light, sampled.filter(|_| s == 1), i);
    let cv = |i: usize| vertex_of(camera, sampled.filter(|_| t == 1), i);
    // The reverse densities of the endpoints (`[t - 1]`, `[s - 1]`) and of the vertices before
    // them (`[t - 2]`, `[s - 2]`).
    let cam_end_rev = if t == 0 {
        0.0
    } else if s > 0 {
        pdf(scene, lv(s - 1), s.checked_sub(2).map(lv), cv(t - 1))
    } else {
        pdf_light_origin(scene, cv(t - 1), cv(t - 2))
    };
    let cam_before_rev = if t < 2 {
        0.0
    } else if s > 0 {
        pdf(scene, cv(t - 1), Some(lv(s - 1)), cv(t - 2))
    } else {
        pdf_light(scene, cv(t - 1), cv(t - 2))
    };
    let light_end_rev = if s == 0 {
        0.0
    } else {
        pdf(scene, cv(t - 1), t.checked_sub(2).map(cv), lv(s - 1))
    };
    let light_before_rev = if s < 2 {
        0.0
    } else {
        pdf(scene, lv(s - 1), Some(cv(t - 1)), lv(s - 2))
    };
    let cam_rev = |i: usize| match t - 1 - i {
        0 => cam_end_rev,
        1 => cam_before_rev,
        _ => cv(i).pdf_rev,
    };
    let light_rev = |i: usize| match s - 1 - i {
        0 => light_end_rev,
        1 => light_before_rev,
        _ => lv(i).pdf_rev,
    };
    let cam_delta = |i: usize| i + 1 != t && cv(i).delta;
    let light_delta = |i: usize| i + 1 != s && lv(i).delta;
    // A zero density (a delta lobe's) counts as one: those strategies are excluded below.
    let remap = |x: f32| if x != 0.0 { x } else { 1.0 };
    let mut sum = 0.0f32;
    let mut r = 1.0f32;
    for i in (1..t).rev() {
        r *= remap(cam_rev(i)) / remap(cv(i).pdf_fwd);
        if !cam_delta(i) && !cam_delta(i - 1) {
            sum += r;
        }
    }
    r = 1.0;
    for i in (0..s).rev() {
        r *= remap(light_rev(i)) / remap(lv(i).pdf_fwd);
        let delta_before = if i > 0 {
            light_delta(i - 1)
        } else {
            is_delta_light(scene, lv(0))
        };
        if !light_delta(i) && !delta_before {
            sum += r;
        }
    }
    1.0 / (1.0 + sum)
}

/// The origin of a ray leaving vertex `v` along `dir`: off its surface where it has one.
fn leave(v: &Vertex, dir: Vec3) -> Vec3 {
    if v.n == Vec3::ZERO || v.p_error == Vec3::ZERO {
        v.p
    } else {
        offset_ray_origin(v.p, v.p_error, v.n, dir)
    }
}

/// Whether nothing blocks the segment from `a` to `b`.
fn unoccluded<S: Sampler>(
    scene: &Scene,
    a: &Vertex,
    b: Vec3,
    sampler: &mut S,
    ctx: &mut TraceContext,
) -> bool {
    let w = b - a.p;
    let dist = w.length();
    if dist.is_nan() || dist <= 0.0 {
        return false;
    }
    let dir = w / dist;
    let origin = leave(a, dir);
    let t_max = (b - origin).length() * (1.0 - SHADOW_EPSILON);
    visible_along(scene, Ray::new(origin, dir), t_max, sampler, ctx)
}

/// What a strategy adds to a pixel: its value and its MIS weight.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Contribution {
    /// The strategy's estimate of its path's light, before weighting.
    value: Vec3,
    weight: f32,
}

impl Contribution {
    const NONE: Contribution = Contribution {
        value: Vec3::ZERO,
        weight: 0.0,
    };

    fn weighted(&self) -> Vec3 {
        self.value * self.weight
    }
}

/// Strategy `(s, t)` with `t >= 2`: its contribution to the pixel (pbrt-v4's
/// `ConnectBDPT`).
#[allow(clippy::too_many_arguments)]
fn connect<S: Sampler>(
    scene: &Scene,
    integrator: &Bdpt,
    light: &[Vertex],
    camera: &[Vertex],
    (s, t): (usize, usize),
    sampler: &mut S,
    ctx: &mut TraceContext,
) -> Contribution {
    let pt = &camera[t - 1];
    let toward_eye = (camera[t - 2].p - pt.p).normalize();
    let mut sampled = None;
    let value = if s == 0 {
        // The camera subpath ends on an emitter, or leaves the scene toward the infinite ones.
        if t == 2 && integrator.hide_emitters {
            return Contribution::NONE;
        }
        let emitters = &scene.emitters;
        if pt.is_infinite() {
            let le: Vec3 = emitters
                .infinite
                .iter()
                .map(|&e| emitters.emitters[e as usize].radiance_env(-toward_eye))
                .sum();
            pt.beta * le
        } else {
            let e = pt.emitter();
            if e == NO_EMITTER {
                return Contribution::NONE;
            }
            pt.beta * emitters.emitters[e as usize].radiance_area(pt.frame.n, pt.uv, toward_eye)
        }
    } else if s == 1 {
        // A point of a light chosen afresh (next-event estimation).
        if !pt.connectible() {
            return Contribution::NONE;
        }
        let emitters = &scene.emitters;
        let (e, pmf) = emitters.picker.pick(sampler.get_1d());
        let u = sampler.get_2d();
        if pmf <= 0.0 {
            return Contribution::NONE;
        }
        let em = &emitters.emitters[e];
        if em.is_infinite() {
            return connect_to_infinite_light(scene, light, camera, t, (e, pmf), u, sampler, ctx);
        }
        let (v, radiance) = if em.is_delta() {
            let Some(ls) = em.sample_li(pt.p, u) else {
                return Contribution::NONE;
            };
            let p = pt.p + ls.wi * ls.dist;
            let v = light_vertex(e, p, Vec3::ZERO, Vec2::ZERO, pmf, 1.0);
            // The intensity toward `pt` is the sample's weight times the squared distance.
            (v, ls.weight * (ls.dist * ls.dist))
        } else {
            let Some(ps) = em.sample_position(u) else {
                return Contribution::NONE;
            };
            let mut v = light_vertex(e, ps.point, ps.normal, ps.uv, pmf, ps.pdf);
            v.p_error = ps.point_error;
            let to_pt = (pt.p - ps.point).normalize();
            let le = em.radiance_area(ps.normal, ps.uv, to_pt);
            (v, le * ps.normal.dot(to_pt).max(0.0))
        };
        let w = v.p - pt.p;
        let d2 = w.length_squared();
        let wi = w / d2.sqrt();
        let value = pt.beta
            * scattering(pt, toward_eye, wi)
            * (pt.n.dot(wi).abs() / d2)
            * radiance
            * v.beta;
        if value == Vec3::ZERO || !unoccluded(scene, pt, v.p, sampler, ctx) {
            return Contribution::NONE;
        }
        sampled = Some(v);
        value
    } else {
        let qs = &light[s - 1];
        if !qs.connectible() || !pt.connectible() {
            return Contribution::NONE;
        }
        let w = qs.p - pt.p;
        let d2 = w.length_squared();
        let wi = w / d2.sqrt();
        let toward_light = (light[s - 2].p - qs.p).normalize();
        let g = (pt.n.dot(wi) * qs.n.dot(wi)).abs() / d2;
        let value = qs.beta
            * scattering(qs, -wi, toward_light)
            * g
            * scattering(pt, toward_eye, wi)
            * pt.beta;
        if value == Vec3::ZERO || !unoccluded(scene, pt, qs.p, sampler, ctx) {
            return Contribution::NONE;
        }
        value
    };
    if value == Vec3::ZERO {
        return Contribution::NONE;
    }
    Contribution {
        value,
        weight: mis_weight(scene, light, camera, sampled.as_ref(), (s, t)),
    }
}

/// Strategy `(1, t)` with infinite light `e` chosen with probability `pmf`: a direction toward
/// it from `u`, unoccluded to infinity; its vertex's density is the direction's over all the
/// infinite lights, as a camera subpath leaving the scene would be weighed.
#[allow(clippy::too_many_arguments)]
fn connect_to_infinite_light<S: Sampler>(
    scene: &Scene,
    light: &[Vertex],
    camera: &[Vertex],
    t: usize,
    (e, pmf): (usize, f32),
    u: Vec2,
    sampler: &mut S,
    ctx: &mut TraceContext,
) -> Contribution {
    let pt = &camera[t - 1];
    let toward_eye = (camera[t - 2].p - pt.p).normalize();
    let Some(ls) = scene.emitters.emitters[e].sample_li(pt.p, u) else {
        return Contribution::NONE;
    };
    let wi = ls.wi;
    let value = pt.beta * scattering(pt, toward_eye, wi) * pt.n.dot(wi).abs() * ls.weight / pmf;
    if value == Vec3::ZERO
        || !visible_along(
            scene,
            Ray::new(leave(pt, wi), wi),
            f32::INFINITY,
            sampler,
            ctx,
        )
    {
        return Contribution::NONE;
    }
    let mut v = light_vertex(e, pt.p + wi, Vec3::ZERO, Vec2::ZERO, pmf, 1.0);
    v.kind = Kind::Infinite(e as u32);
    v.pdf_fwd = pdf_light_origin(scene, &v, pt);
    Contribution {
        value,
        weight: mis_weight(scene, light, camera, Some(&v), (1, t)),
    }
}

/// The vertex of a light's point chosen with probability `pmf` at density `pdf_pos` by area.
fn light_vertex(e: usize, p: Vec3, n: Vec3, uv: Vec2, pmf: f32, pdf_pos: f32) -> Vertex {
    Vertex {
        kind: Kind::Light(e as u32),
        p,
        p_error: Vec3::ZERO,
        n,
        frame: ShadingFrame::from_normal(if n == Vec3::ZERO { Vec3::Z } else { n }),
        bsdf: None,
        uv,
        beta: Vec3::splat(1.0 / (pmf * pdf_pos)),
        delta: false,
        pdf_fwd: pmf * pdf_pos,
        pdf_rev: 0.0,
    }
}

/// Strategy `(s, 1)`, `s >= 2`: light subpath vertex `s - 1` (a surface) joined to the camera,
/// its film position and contribution. Emitters seen directly are strategy `(0, 2)` alone
/// (weight one, as pbrt-v4 counts them: `(1, 1)` is not taken).
fn connect_to_camera<S: Sampler>(
    scene: &Scene,
    light: &[Vertex],
    s: usize,
    sampler: &mut S,
    ctx: &mut TraceContext,
) -> Option<(Vec2, Contribution)> {
    let qs = &light[s - 1];
    let u_lens = sampler.get_2d();
    if !qs.connectible() {
        return None;
    }
    let c = scene.camera.connect(qs.p, u_lens)?;
    let toward_light = (light[s - 2].p - qs.p).normalize();
    let value = qs.beta * scattering(qs, c.wi, toward_light) * (qs.n.dot(c.wi).abs() * c.weight);
    if value == Vec3::ZERO || !unoccluded(scene, qs, c.lens, sampler, ctx) {
        return None;
    }
    let camera_vertex = Vertex {
        kind: Kind::Camera,
        p: c.lens,
        p_error: Vec3::ZERO,
        n: Vec3::ZERO,
        frame: ShadingFrame::from_normal(scene.camera.forward),
        bsdf: None,
        uv: Vec2::ZERO,
        beta: Vec3::ONE,
        delta: false,
        pdf_fwd: 1.0,
        pdf_rev: 0.0,
    };
    let w = mis_weight(scene, light, &[camera_vertex], Some(&camera_vertex), (s, 1));
    Some((c.pos, Contribution { value, weight: w }))
}

impl Integrator for Bdpt {
    const NAME: &'static str = "bdpt";

    fn from_settings(s: &RenderSettings) -> Result<Self> {
        let b = Bdpt {
            max_depth: vertex_limit(s.max_depth),
            rr_depth: s.rr_depth,
            hide_emitters: s.hide_emitters,
            strategy_images: s.integrator_params.bdpt.strategy_images,
            regularize: s.integrator_params.bdpt.regularize,
        };
        if b.strategy_images.is_some() && b.max_depth > MAX_DEPTH_OF_STRATEGY_IMAGES {
            return Err(Error::Invalid(format!(
                "[render.bdpt] strategy_images: one image per strategy needs max_depth from 0 to \
                 {MAX_DEPTH_OF_STRATEGY_IMAGES}, got {}",
                s.max_depth
            )));
        }
        Ok(b)
    }

    /// The strategies with `t >= 2` through the render loop, those with `t = 1` by batches of
    /// light paths, each given half of a time limit; the film is their sum.
    fn render(&self, scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        check_camera(scene)?;
        if let Some(images) = self.strategy_images {
            let tracer = BdptStrategies {
                bdpt: *self,
                images,
            };
            return render_light_paths(scene, &tracer, 0, options);
        }
        let time_limit = options.time_limit.map(|t| t / 2);
        let progress = options.progress;
        let first_half = |n: u64| {
            if let Some(p) = progress {
                p(n / 2)
            }
        };
        let window_pixels = options
            .window
            .unwrap_or(super::Window::full(scene.camera.width, scene.camera.height))
            .pixel_count();
        let second_half = |n: u64| {
            if let Some(p) = progress {
                p(window_pixels / 2 + n / 2)
            }
        };
        let camera_options = RenderOptions {
            progress: progress.map(|_| &first_half as &(dyn Fn(u64) + Sync)),
            cancel: options.cancel,
            time_limit,
            window: options.window,
            skip_aovs: options.skip_aovs,
        };
        let (mut film, mut stats) = with_sampler(scene, &BdptCamera(*self), &camera_options)?;
        let light_options = RenderOptions {
            progress: progress.map(|_| &second_half as &(dyn Fn(u64) + Sync)),
            cancel: options.cancel,
            time_limit,
            window: options.window,
            skip_aovs: true,
        };
        let (splats, light_stats) =
            render_light_paths(scene, &BdptLight(*self), 0, &light_options)?;
        for (c, s) in film.rgb.iter_mut().zip(&splats.rgb) {
            *c += *s;
        }
        for (v, s) in film.variance.iter_mut().zip(&splats.variance) {
            *v += *s;
        }
        stats.add(&light_stats);
        Ok((film, stats))
    }
}

/// The camera side of [`Bdpt`]: strategies with `t >= 2`, per pixel sample.
#[derive(Clone, Copy, Debug)]
pub struct BdptCamera(pub Bdpt);

impl Integrator for BdptCamera {
    const NAME: &'static str = "bdpt";

    fn from_settings(s: &RenderSettings) -> Result<Self> {
        Bdpt::from_settings(s).map(BdptCamera)
    }

    fn render(&self, scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        with_sampler(scene, self, options)
    }
}

impl BdptCamera {
    /// [`PixelIntegrator::sample`] with the subpaths' vectors given.
    #[allow(clippy::too_many_arguments)]
    fn sample_into<S: Sampler>(
        &self,
        scene: &Scene,
        x: u32,
        y: u32,
        sampler: &mut S,
        aov: Option<&mut PixelAov>,
        paths: &mut Subpaths,
        ctx: &mut TraceContext,
    ) -> FilmSample {
        let b = &self.0;
        let CameraRay { pos, ray, .. } = camera_ray(scene, x, y, sampler);
        ctx.rays.camera += 1;
        if let Some(aov) = aov {
            *aov = centre_aov(scene, x, y, ctx);
        }
        let Subpaths { camera, light } = paths;
        camera.clear();
        light.clear();
        let mut radiance = Vec3::ZERO;
        if b.max_depth > 0 {
            camera_subpath(scene, b, &ray, sampler, camera, ctx);
            light_subpath(scene, b, sampler, light, ctx);
            for t in 2..=camera.len() {
                for s in 0..=light.len().max(1) {
                    if s + t - 1 > b.max_depth as usize {
                        break;
                    }
                    radiance += connect(scene, b, light, camera, (s, t), sampler, ctx).weighted();
                }
            }
        }
        FilmSample { pos, radiance }
    }
}

impl PixelIntegrator for BdptCamera {
    fn sample<S: Sampler>(
        &self,
        scene: &Scene,
        x: u32,
        y: u32,
        sampler: &mut S,
        aov: Option<&mut PixelAov>,
        ctx: &mut TraceContext,
    ) -> FilmSample {
        let mut paths = Subpaths::for_integrator(&self.0);
        self.sample_into(scene, x, y, sampler, aov, &mut paths, ctx)
    }

    /// The row's samples one by one (as `sample_row_one_by_one`), their subpaths in vectors
    /// shared by the row.
    fn sample_row<S: Sampler>(
        &self,
        scene: &Scene,
        row: PixelRow,
        sampler: &mut S,
        out: &mut [FilmSample],
        mut aovs: Option<&mut [PixelAov]>,
        ctx: &mut TraceContext,
    ) {
        let mut paths = Subpaths::for_integrator(&self.0);
        for (i, o) in out.iter_mut().enumerate() {
            let x = row.x0 + i as u32;
            sampler.start_pixel_sample(x, row.y, row.index);
            let aov = aovs.as_deref_mut().map(|a| &mut a[i]);
            *o = self.sample_into(scene, x, row.y, sampler, aov, &mut paths, ctx);
        }
    }
}

/// The light side of [`Bdpt`]: strategies with `t = 1`, splatted.
#[derive(Clone, Copy, Debug)]
pub struct BdptLight(pub Bdpt);

impl LightPathTracer for BdptLight {
    /// The light subpath's vertices (the camera's vector stays empty).
    type Scratch = Subpaths;

    fn trace<S: Sampler>(
        &self,
        scene: &Scene,
        _: (u32, u32),
        sampler: &mut S,
        splats: &mut Vec<Splat>,
        paths: &mut Subpaths,
        ctx: &mut TraceContext,
    ) {
        let light = &mut paths.light;
        light.clear();
        light_subpath(scene, &self.0, sampler, light, ctx);
        for s in 2..=light.len() {
            if let Some((pos, c)) = connect_to_camera(scene, light, s, sampler, ctx) {
                splats.push(Splat::new(pos, c.weighted()));
            }
        }
    }
}

/// All of [`Bdpt`] with an image of each strategy beside the render (pbrt-v4's
/// `visualizestrategies` and `visualizeweights`): per sample of each pixel, one camera and one
/// light subpath joined in every way (pbrt-v4's estimator, the light subpath serving the
/// strategies of both films), every contribution splatted by `light_pass` onto the image and
/// onto its strategy's. A pixel's own camera-side contributions are splats at its sample's
/// position: with W x H samples a batch, their filter-weighted sums over the filter's integral
/// estimate what the render loop's weighted means do (see `splat_film`).
pub struct BdptStrategies {
    bdpt: Bdpt,
    images: StrategyImages,
}

impl BdptStrategies {
    /// The image of strategy `(s, t)` among the film's further images, counted from 1: by depth
    /// `d = s + t - 2` (pbrt's, from 0 to `max_depth - 1`), then by `s`; `(1, 1)` has none (that
    /// path is `(0, 2)`'s alone).
    fn image((s, t): (usize, usize)) -> u16 {
        let d = s + t - 2;
        let first = if d == 0 { 0 } else { 1 + (d - 1) * (d + 4) / 2 };
        (1 + first + s) as u16
    }

    /// Each strategy `(s, t)` with an image, in image order.
    fn strategies(max_depth: u32) -> impl Iterator<Item = (usize, usize)> {
        (0..max_depth as usize).flat_map(|d| {
            (0..=d + 1)
                .map(move |s| (s, d + 2 - s))
                .filter(|&st| st != (1, 1))
        })
    }

    /// What the strategy's image shows of a contribution.
    fn shown(&self, c: &Contribution) -> Vec3 {
        match self.images {
            StrategyImages::Weighted => c.weighted(),
            StrategyImages::Unweighted if c.weight > 0.0 => c.value,
            StrategyImages::Unweighted => Vec3::ZERO,
        }
    }
}

impl LightPathTracer for BdptStrategies {
    type Scratch = Subpaths;

    fn trace<S: Sampler>(
        &self,
        scene: &Scene,
        (x, y): (u32, u32),
        sampler: &mut S,
        splats: &mut Vec<Splat>,
        paths: &mut Subpaths,
        ctx: &mut TraceContext,
    ) {
        let b = &self.bdpt;
        let CameraRay { pos, ray, .. } = camera_ray(scene, x, y, sampler);
        ctx.rays.camera += 1;
        let Subpaths { camera, light } = paths;
        camera.clear();
        light.clear();
        if b.max_depth == 0 {
            return;
        }
        camera_subpath(scene, b, &ray, sampler, camera, ctx);
        light_subpath(scene, b, sampler, light, ctx);
        let mut splat = |pos: Vec2, c: &Contribution, st: (usize, usize)| {
            splats.push(Splat::new(pos, c.weighted()));
            splats.push(Splat {
                pos,
                value: self.shown(c),
                image: Self::image(st),
            });
        };
        for t in 2..=camera.len() {
            for s in 0..=light.len().max(1) {
                if s + t - 1 > b.max_depth as usize {
                    break;
                }
                let c = connect(scene, b, light, camera, (s, t), sampler, ctx);
                if c != Contribution::NONE {
                    splat(pos, &c, (s, t));
                }
            }
        }
        for s in 2..=light.len() {
            if let Some((pos, c)) = connect_to_camera(scene, light, s, sampler, ctx) {
                splat(pos, &c, (s, 1));
            }
        }
    }

    /// pbrt-v4's names of the images' files, `bdpt_dDD_sSS_tTT`.
    fn further_images(&self) -> Vec<String> {
        Self::strategies(self.bdpt.max_depth)
            .map(|(s, t)| format!("bdpt_d{:02}_s{s:02}_t{t:02}", s + t - 2))
            .collect()
    }

    /// A path's dozens of splats (two per strategy) are held until its pass ends.
    fn paths_per_pass(&self) -> u64 {
        1 << 16
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::description_from_str;
    use crate::description::parse::Syntax;
    use crate::render::sampler::IndependentSampler;
    use std::path::Path;

    /// A closed room (a two-sided diffuse sphere seen from inside), a rough plastic ball, an area
    /// light and a point light: paths bounce several times and end on the area light.
    const BOX: &str = "[camera]\neye = [0.0, 1.0, 2.8]\nlook_at = [0.0, 1.0, 0.0]\nwidth = 16\n\
        height = 16\nfov = 50\n[render]\nintegrator = \"bdpt\"\nmax_depth = 8\n\
        [materials.grey]\ntype = \"diffuse\"\nreflectance = [0.8, 0.8, 0.8]\n\
        [materials.white]\ntype = \"twosided\"\nfront = \"grey\"\n\
        [materials.plastic]\ntype = \"roughplastic\"\ndiffuse_reflectance = [0.2, 0.6, 0.3]\n\
        [[shape]]\ntype = \"sphere\"\ncenter = [0.0, 1.0, 0.0]\nradius = 3.0\nmaterial = \"white\"\n\
        [[shape]]\ntype = \"sphere\"\ncenter = [0.3, 0.5, 0.0]\nradius = 0.4\nmaterial = \"plastic\"\n\
        [[shape]]\ntype = \"rectangle\"\n\
        transform = { scale = [0.8, 0.8, 1.0], rotate = { axis = [1.0, 0.0, 0.0], degrees = 90.0 }, translate = [0.0, 2.5, 0.0] }\n\
        emitter = { radiance = [4.0, 4.0, 4.0] }\n\
        [[light]]\ntype = \"point\"\nposition = [-1.0, 1.5, 0.5]\nintensity = 2.0\n";

    /// An open scene: a diffuse ground, a rough plastic ball and a glass ball under the sun and
    /// sky (an infinite light sampled by its image), a directional light and an area light; paths
    /// leave the scene toward the sky.
    const OPEN: &str = "[camera]\neye = [0.0, 1.0, 3.0]\nlook_at = [0.0, 0.4, 0.0]\nwidth = 16\n\
        height = 16\nfov = 60\n[render]\nintegrator = \"bdpt\"\nmax_depth = 8\n\
        [materials.grey]\ntype = \"diffuse\"\nreflectance = [0.8, 0.8, 0.8]\n\
        [materials.glass]\ntype = \"dielectric\"\n\
        [materials.plastic]\ntype = \"roughplastic\"\ndiffuse_reflectance = [0.2, 0.6, 0.3]\n\
        [[shape]]\ntype = \"rectangle\"\nmaterial = \"grey\"\n\
        transform = { scale = [3.0, 3.0, 1.0], rotate = { axis = [1.0, 0.0, 0.0], degrees = -90.0 } }\n\
        [[shape]]\ntype = \"sphere\"\ncenter = [0.4, 0.4, 0.0]\nradius = 0.4\nmaterial = \"plastic\"\n\
        [[shape]]\ntype = \"sphere\"\ncenter = [-0.5, 0.3, 0.3]\nradius = 0.3\nmaterial = \"glass\"\n\
        [[shape]]\ntype = \"rectangle\"\n\
        transform = { scale = [0.3, 0.3, 1.0], rotate = { axis = [1.0, 0.0, 0.0], degrees = 90.0 }, translate = [0.0, 1.5, 0.0] }\n\
        emitter = { radiance = [4.0, 4.0, 4.0] }\n\
        [[light]]\ntype = \"sunsky\"\nsun_direction = [0.3, 1.0, 0.4]\nsun_aperture = 5.0\nsky_scale = 0.05\nsun_scale = 0.05\n\
        [[light]]\ntype = \"directional\"\ndirection = [0.5, -1.0, 0.2]\nintensity = 1.0\n";

    /// The camera-side and light-side densities of path `x` (`x[0]` the lens, `x[k-1]` on an
    /// emitter), and the vertex arrays of strategy `(s, t)` built from them: the light subpath
    /// is the path's end reversed, its first vertex the emitter's point as a light's.
    fn split(scene: &Scene, x: &[Vertex], s: usize) -> (Vec<Vertex>, Vec<Vertex>) {
        let k = x.len();
        let t = k - s;
        let mut as_light: Vec<Vertex> = x.iter().rev().copied().collect();
        as_light[0].kind = if x[k - 1].is_infinite() {
            Kind::Infinite(scene.emitters.infinite[0])
        } else {
            Kind::Light(x[k - 1].emitter())
        };
        as_light[0].bsdf = None;
        // Densities as each direction samples: camera side forward along `x`, light side backward.
        let cam_fwd = |i: usize| -> f32 {
            match i {
                0 => 1.0,
                1 => pdf(scene, &x[0], None, &x[1]),
                _ => pdf(scene, &x[i - 1], Some(&x[i - 2]), &x[i]),
            }
        };
        let light_fwd = |j: usize| -> f32 {
            match j {
                0 => pdf_light_origin(scene, &as_light[0], &as_light[1]),
                1 => pdf_light(scene, &as_light[0], &as_light[1]),
                _ => pdf(
                    scene,
                    &as_light[j - 1],
                    Some(&as_light[j - 2]),
                    &as_light[j],
                ),
            }
        };
        let camera: Vec<Vertex> = (0..t)
            .map(|i| Vertex {
                pdf_fwd: cam_fwd(i),
                pdf_rev: light_fwd(k - 1 - i),
                ..x[i]
            })
            .collect();
        let light: Vec<Vertex> = (0..s)
            .map(|j| Vertex {
                pdf_fwd: light_fwd(j),
                pdf_rev: cam_fwd(k - 1 - j),
                ..as_light[j]
            })
            .collect();
        (light, camera)
    }

    /// For paths of every length from 3 to 8 vertices that the camera's random walks find in
    /// the box, the balance heuristic's weights of all strategies that can make the path (every
    /// split into `s` light and `t >= 1` camera vertices not joined at a delta lobe; the point
    /// light no path hits is no strategy) sum to one.
    #[test]
    fn mis_weights_of_all_strategies_sum_to_one() {
        weights_sum_to_one(BOX, 8, |_| true);
    }

    /// The same in the open scene (to 7 vertices), for the paths that end in the sky: the
    /// strategies of a light at infinity (its subpaths entering through the disk, its directions sampled toward it,
    /// camera subpaths leaving the scene) weigh each other as the rest do.
    #[test]
    fn mis_weights_sum_to_one_for_paths_from_the_sky() {
        weights_sum_to_one(OPEN, 7, |v| v.is_infinite());
    }

    /// The strategies' images are numbered in the order of their names, one for each strategy
    /// of each depth but `(1, 1)`.
    #[test]
    fn strategy_images_follow_their_names() {
        let all: Vec<_> = BdptStrategies::strategies(10).collect();
        assert_eq!(all.len(), 64);
        for (i, &st) in all.iter().enumerate() {
            assert_eq!(BdptStrategies::image(st) as usize, i + 1, "{st:?}");
        }
        assert_eq!(&all[..5], &[(0, 2), (0, 3), (1, 2), (2, 1), (0, 4)]);
    }

    /// Checks the paths that end on a vertex `ends` accepts, at least five of each length from
    /// 3 to `longest` vertices.
    fn weights_sum_to_one(toml: &str, longest: usize, ends: impl Fn(&Vertex) -> bool) {
        let d = description_from_str(toml, Syntax::Toml, Path::new("box.toml")).unwrap();
        let scene = Scene::new(&d, Path::new(".")).unwrap();
        let b = Bdpt::from_settings(&scene.settings).unwrap();
        let mut sampler = IndependentSampler::new(3);
        let mut ctx = TraceContext::default();
        let mut checked = [0usize; 10];
        for index in 0..4000 {
            sampler.start_pixel_sample(index % 16, (index / 16) % 16, index);
            let ray = scene.camera.ray(
                (index % 16) as f32 + sampler.get_1d(),
                ((index / 16) % 16) as f32 + sampler.get_1d(),
            );
            let mut path = Vec::new();
            camera_subpath(&scene, &b, &ray, &mut sampler, &mut path, &mut ctx);
            for k in 3..=path.len() {
                let x = &path[..k];
                let on_light = x[k - 1].emitter() != NO_EMITTER || x[k - 1].is_infinite();
                if !on_light || !ends(&x[k - 1]) {
                    continue;
                }
                let mut sum = 0.0f64;
                for s in 0..k {
                    let t = k - s;
                    // No strategy joins the subpaths at a surface that scatters by a delta lobe
                    // (the glass ball's).
                    if s > 0 && (x[t - 1].delta || x[t].delta) {
                        continue;
                    }
                    let (light, camera) = split(&scene, x, s);
                    let sampled = match (s, t) {
                        (1, _) => Some(&light[0]),
                        (_, 1) => Some(&camera[0]),
                        _ => None,
                    };
                    let w = mis_weight(&scene, &light, &camera, sampled, (s, t));
                    assert!((0.0..=1.0).contains(&w), "weight {w} of ({s}, {t})");
                    sum += w as f64;
                }
                assert!(
                    (sum - 1.0).abs() < 1e-4,
                    "{k} vertices: weights sum to {sum}"
                );
                checked[k] += 1;
            }
        }
        for (k, &n) in checked.iter().enumerate().take(longest + 1).skip(3) {
            assert!(n >= 5, "only {n} paths of {k} vertices: {checked:?}");
        }
    }
}
