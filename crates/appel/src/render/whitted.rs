//! The deterministic integrators: ray casting (Appel 1968) shades the first hit locally; Whitted
//! (1980) adds recursively traced reflected and refracted rays. They read only the film position
//! from the sampler, so the camera rays of a row are traced together.
//!
//! Both read the scene's one material list and its emitters, as `path` and `direct` do: each
//! material through its Whitted response ([`crate::shading::bsdf::Bsdf::whitted`], a `phong`
//! material's own parameters), lit by the delta emitters (point, spot, projector and directional
//! lights), each behind one shadow ray. Area and environment emitters have no part in the model:
//! `environment.background` is its sky and `environment.ambient` its ambient light.

use super::integrator::{
    aov_of, camera_ray, centre_aov, surface_hit, CameraRay, FilmSample, Integrator,
    PixelIntegrator, PixelRow, SurfaceHit,
};
use super::optics::{fresnel_dielectric, reflect, refract};
use super::sampler::Sampler;
use super::{Film, PixelAov, RenderOptions, RenderStats, TraceContext};
use crate::error::Result;
use crate::geometry::SurfaceInteraction;
use crate::math::{offset_ray_origin_by, surface_offset, Ray, Vec2, Vec3};
use crate::scene::{RenderSettings, Scene, SceneHit};
use crate::shading::bsdf::Phong;
use crate::shading::emitter::Emitter;

/// Shadow rays towards a point light stop this fraction short of it (pbrt-v4's `ShadowEpsilon`):
/// relative to the segment, so it is scale-free.
const SHADOW_EPSILON: f32 = 1e-4;

/// One eye ray per pixel, one shadow ray per light, local shading only.
pub struct Raycast;

/// Recursive ray tracing to `max_depth` specular bounces.
pub struct Whitted {
    pub max_depth: u32,
}

/// Integrators that need no random numbers after the film position: everything follows from the
/// camera ray's closest hit.
trait ShadeFirstHit: Sync {
    /// Radiance arriving along the camera ray `ray`, whose closest hit and surface are `hit`.
    fn radiance(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: Option<&SurfaceHit>,
        ctx: &mut TraceContext,
    ) -> Vec3;

    /// The samples of a row without AOVs: [`sample_row_first_hit`]'s values, by whatever way the
    /// integrator has to them.
    fn sample_row_colour<S: Sampler>(
        &self,
        scene: &Scene,
        row: PixelRow,
        sampler: &mut S,
        out: &mut [FilmSample],
        ctx: &mut TraceContext,
    ) where
        Self: Sized,
    {
        sample_row_first_hit(self, scene, row, sampler, out, None, ctx)
    }
}

impl ShadeFirstHit for Raycast {
    fn radiance(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: Option<&SurfaceHit>,
        ctx: &mut TraceContext,
    ) -> Vec3 {
        let Some(h) = hit else {
            return scene.background;
        };
        let origins = Origins::new(&h.si);
        let mut other = None;
        let (m, albedo) = scene.whitted_material(&h.hit, h.si.uv, &mut other);
        shade_locally(scene, m, albedo, &h.si, -ray.dir, &origins, ctx)
    }
}

impl ShadeFirstHit for Whitted {
    fn radiance(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: Option<&SurfaceHit>,
        ctx: &mut TraceContext,
    ) -> Vec3 {
        self.trace(scene, ray, hit, 0, ctx)
    }

    fn sample_row_colour<S: Sampler>(
        &self,
        scene: &Scene,
        row: PixelRow,
        sampler: &mut S,
        out: &mut [FilmSample],
        ctx: &mut TraceContext,
    ) {
        self.sample_row_wavefront(scene, row, sampler, out, ctx)
    }
}

/// Pixels of a row whose camera rays are intersected together.
const ROW_CHUNK: usize = 16;

/// One sample: the camera ray's hit, its AOVs, its shading.
#[inline]
fn sample_first_hit<T: ShadeFirstHit, S: Sampler>(
    integrator: &T,
    scene: &Scene,
    x: u32,
    y: u32,
    sampler: &mut S,
    aov: Option<&mut PixelAov>,
    ctx: &mut TraceContext,
) -> FilmSample {
    let c = camera_ray(scene, x, y, sampler);
    ctx.rays.camera += 1;
    let hit = scene.intersect(&c.ray, f32::INFINITY, &mut ctx.traversal);
    shade_camera_hit(integrator, scene, x, y, &c, hit, aov, ctx)
}

/// The camera rays of a row's samples intersected together (in packets where the structure has
/// them), then shaded one by one: the same results as [`sample_first_hit`] on each.
fn sample_row_first_hit<T: ShadeFirstHit, S: Sampler>(
    integrator: &T,
    scene: &Scene,
    row: PixelRow,
    sampler: &mut S,
    out: &mut [FilmSample],
    mut aovs: Option<&mut [PixelAov]>,
    ctx: &mut TraceContext,
) {
    for (c, out) in out.chunks_mut(ROW_CHUNK).enumerate() {
        let n = out.len();
        let x0 = row.x0 + (c * ROW_CHUNK) as u32;
        let mut film = [(Vec2::ZERO, false); ROW_CHUNK];
        let rays: [Ray; ROW_CHUNK] = std::array::from_fn(|i| {
            // Past the row's end, copies of its last ray (never traced).
            let x = x0 + i.min(n - 1) as u32;
            sampler.start_pixel_sample(x, row.y, row.index);
            let c = camera_ray(scene, x, row.y, sampler);
            film[i] = (c.pos, c.centre);
            c.ray
        });
        let mut hits = [None; ROW_CHUNK];
        scene.intersect_coherent(
            &rays[..n],
            f32::INFINITY,
            &mut hits[..n],
            &mut ctx.traversal,
        );
        ctx.rays.camera += n as u64;
        for (i, o) in out.iter_mut().enumerate() {
            let aov = aovs.as_deref_mut().map(|a| &mut a[c * ROW_CHUNK + i]);
            *o = shade_camera_hit(
                integrator,
                scene,
                x0 + i as u32,
                row.y,
                &CameraRay {
                    pos: film[i].0,
                    ray: rays[i],
                    centre: film[i].1,
                },
                hits[i],
                aov,
                ctx,
            );
        }
    }
}

#[allow(clippy::too_many_arguments)]
#[inline]
fn shade_camera_hit<T: ShadeFirstHit>(
    integrator: &T,
    scene: &Scene,
    x: u32,
    y: u32,
    c: &CameraRay,
    hit: Option<SceneHit>,
    aov: Option<&mut PixelAov>,
    ctx: &mut TraceContext,
) -> FilmSample {
    // The surface built where it is read, not moved into an `Option` (see `Whitted::spawn`).
    match hit {
        Some(h) => {
            let h = surface_hit(scene, &c.ray, h);
            shade_camera_surface(integrator, scene, x, y, c, Some(&h), aov, ctx)
        }
        None => shade_camera_surface(integrator, scene, x, y, c, None, aov, ctx),
    }
}

/// [`shade_camera_hit`] once the surface is known.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn shade_camera_surface<T: ShadeFirstHit>(
    integrator: &T,
    scene: &Scene,
    x: u32,
    y: u32,
    c: &CameraRay,
    hit: Option<&SurfaceHit>,
    aov: Option<&mut PixelAov>,
    ctx: &mut TraceContext,
) -> FilmSample {
    if let Some(aov) = aov {
        // The AOVs describe the ray through the pixel's centre (and the lens's): this ray's hit
        // when it is that one.
        *aov = if c.centre {
            aov_of(scene, hit)
        } else {
            centre_aov(scene, x, y, ctx)
        };
    }
    FilmSample {
        pos: c.pos,
        radiance: integrator.radiance(scene, &c.ray, hit, ctx),
    }
}

macro_rules! first_hit_integrator {
    ($t:ty, $name:literal, |$s:ident| $new:expr) => {
        impl Integrator for $t {
            const NAME: &'static str = $name;

            fn from_settings($s: &RenderSettings) -> Result<Self> {
                Ok($new)
            }

            fn render(
                &self,
                scene: &Scene,
                options: &RenderOptions,
            ) -> Result<(Film, RenderStats)> {
                super::with_sampler(scene, self, options)
            }
        }

        impl PixelIntegrator for $t {
            #[inline]
            fn sample<S: Sampler>(
                &self,
                scene: &Scene,
                x: u32,
                y: u32,
                sampler: &mut S,
                aov: Option<&mut PixelAov>,
                ctx: &mut TraceContext,
            ) -> FilmSample {
                sample_first_hit(self, scene, x, y, sampler, aov, ctx)
            }

            fn sample_row<S: Sampler>(
                &self,
                scene: &Scene,
                row: PixelRow,
                sampler: &mut S,
                out: &mut [FilmSample],
                aovs: Option<&mut [PixelAov]>,
                ctx: &mut TraceContext,
            ) {
                match aovs {
                    None => self.sample_row_colour(scene, row, sampler, out, ctx),
                    aovs => sample_row_first_hit(self, scene, row, sampler, out, aovs, ctx),
                }
            }
        }
    };
}

first_hit_integrator!(Raycast, "raycast", |_s| Raycast);
first_hit_integrator!(Whitted, "whitted", |s| Whitted {
    max_depth: s.max_depth.max(0) as u32
});

#[derive(Clone, Copy, PartialEq, Eq)]
enum Bounce {
    Reflection,
    Refraction,
}

impl Whitted {
    fn trace(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: Option<&SurfaceHit>,
        depth: u32,
        ctx: &mut TraceContext,
    ) -> Vec3 {
        let Some(SurfaceHit { hit, si }) = hit else {
            return scene.background;
        };
        let mut other = None;
        let (m, albedo) = scene.whitted_material(hit, si.uv, &mut other);
        let wo = -ray.dir;
        let origins = Origins::new(si);
        let mut color = shade_locally(scene, m, albedo, si, wo, &origins, ctx);
        if depth >= self.max_depth || !m.is_specular() {
            return color;
        }
        let [reflected, refracted] = specular_rays(m, ray, si, &origins);
        if let Some((kr, r)) = reflected {
            color += kr * self.spawn(scene, &r, depth, Bounce::Reflection, ctx);
        }
        if let Some((kt, r)) = refracted {
            color += kt * self.spawn(scene, &r, depth, Bounce::Refraction, ctx);
        }
        color
    }

    fn spawn(
        &self,
        scene: &Scene,
        ray: &Ray,
        depth: u32,
        kind: Bounce,
        ctx: &mut TraceContext,
    ) -> Vec3 {
        match kind {
            Bounce::Reflection => ctx.rays.reflection += 1,
            Bounce::Refraction => ctx.rays.refraction += 1,
        }
        let ray = *ray;
        // The surface built where `trace` reads it, not moved into an `Option` (a copy by wider
        // loads than its stores, which stalls store-to-load forwarding).
        match scene.intersect(&ray, f32::INFINITY, &mut ctx.traversal) {
            Some(h) => {
                let hit = surface_hit(scene, &ray, h);
                self.trace(scene, &ray, Some(&hit), depth + 1, ctx)
            }
            None => self.trace(scene, &ray, None, depth + 1, ctx),
        }
    }
}

/// A ray of a pixel's ray tree, traced in waves: [`Whitted::sample_row_wavefront`].
#[derive(Clone, Copy)]
struct TreeRay {
    ray: Ray,
    depth: u32,
    /// Its local shading, then (once its children are combined) the radiance along it.
    color: Vec3,
    /// The weights and indices of its reflected and refracted rays ([`NO_CHILD`]: none).
    kr: f32,
    kt: f32,
    reflected: u32,
    refracted: u32,
}

const NO_CHILD: u32 = u32::MAX;

impl TreeRay {
    fn new(ray: Ray, depth: u32) -> Self {
        Self {
            ray,
            depth,
            color: Vec3::ZERO,
            kr: 0.0,
            kt: 0.0,
            reflected: NO_CHILD,
            refracted: NO_CHILD,
        }
    }
}

/// What a wave keeps between its rays' shading and their shadow rays' answers.
#[derive(Default)]
struct WaveBuffers {
    nodes: Vec<TreeRay>,
    rays: Vec<Ray>,
    hits: Vec<Option<SceneHit>>,
    shadow_rays: Vec<Ray>,
    shadow_t_max: Vec<f32>,
    /// The tree ray each shadow ray leaves from and the term it adds when unoccluded.
    shadow_terms: Vec<(u32, LightTerm)>,
    occluded: Vec<bool>,
}

thread_local! {
    static WAVE: std::cell::RefCell<WaveBuffers> = std::cell::RefCell::default();
}

impl Whitted {
    /// [`Whitted::trace`] of a row's camera rays, breadth first instead of depth first (a
    /// wavefront, after Laine, Karras & Aila 2013, "Megakernels considered harmful"): each wave's
    /// rays are intersected together ([`Scene::intersect_stream`], SIMD packets where the scene
    /// is one leaf), their shadow rays answered together ([`Scene::occluded_stream`]), then their
    /// reflected and refracted rays form the next wave. Independent pixels' long chains of square
    /// roots and divisions then also sit side by side. The values are `trace`'s bit for bit: each
    /// ray keeps its local colour and its children, and the colours are combined from the leaves
    /// up as `trace` adds them (`local + kr * reflected + kt * refracted`, shadowed terms in the
    /// emitters' order).
    fn sample_row_wavefront<S: Sampler>(
        &self,
        scene: &Scene,
        row: PixelRow,
        sampler: &mut S,
        out: &mut [FilmSample],
        ctx: &mut TraceContext,
    ) {
        WAVE.with_borrow_mut(|w| self.wavefront(scene, row, sampler, out, w, ctx));
    }

    fn wavefront<S: Sampler>(
        &self,
        scene: &Scene,
        row: PixelRow,
        sampler: &mut S,
        out: &mut [FilmSample],
        w: &mut WaveBuffers,
        ctx: &mut TraceContext,
    ) {
        let n = out.len();
        w.nodes.clear();
        w.rays.clear();
        for (i, o) in out.iter_mut().enumerate() {
            let x = row.x0 + i as u32;
            sampler.start_pixel_sample(x, row.y, row.index);
            let CameraRay { pos, ray, .. } = camera_ray(scene, x, row.y, sampler);
            o.pos = pos;
            w.nodes.push(TreeRay::new(ray, 0));
            w.rays.push(ray);
        }
        w.hits.clear();
        w.hits.resize(n, None);
        scene.intersect_coherent(&w.rays, f32::INFINITY, &mut w.hits, &mut ctx.traversal);
        ctx.rays.camera += n as u64;
        let mut wave = 0..n;
        while !wave.is_empty() {
            w.shadow_rays.clear();
            w.shadow_t_max.clear();
            w.shadow_terms.clear();
            for i in wave.clone() {
                let Some(h) = w.hits[i - wave.start] else {
                    w.nodes[i].color = scene.background;
                    continue;
                };
                let TreeRay { ray, depth, .. } = w.nodes[i];
                let SurfaceHit { hit, si } = surface_hit(scene, &ray, h);
                let mut other = None;
                let (m, albedo) = scene.whitted_material(&hit, si.uv, &mut other);
                let origins = Origins::new(&si);
                w.nodes[i].color = ambient_term(scene, m, albedo);
                direct_terms(scene, m, albedo, &si, -ray.dir, &origins, |r, t, term| {
                    w.shadow_rays.push(r);
                    w.shadow_t_max.push(t);
                    w.shadow_terms.push((i as u32, term));
                });
                if depth >= self.max_depth || !m.is_specular() {
                    continue;
                }
                let [reflected, refracted] = specular_rays(m, &ray, &si, &origins);
                if let Some((kr, r)) = reflected {
                    ctx.rays.reflection += 1;
                    w.nodes[i].kr = kr;
                    w.nodes[i].reflected = w.nodes.len() as u32;
                    w.nodes.push(TreeRay::new(r, depth + 1));
                }
                if let Some((kt, r)) = refracted {
                    ctx.rays.refraction += 1;
                    w.nodes[i].kt = kt;
                    w.nodes[i].refracted = w.nodes.len() as u32;
                    w.nodes.push(TreeRay::new(r, depth + 1));
                }
            }
            ctx.rays.shadow += w.shadow_rays.len() as u64;
            w.occluded.clear();
            w.occluded.resize(w.shadow_rays.len(), false);
            scene.occluded_stream(
                &w.shadow_rays,
                &w.shadow_t_max,
                &mut w.occluded,
                &mut ctx.traversal,
            );
            for (&(i, term), &occluded) in w.shadow_terms.iter().zip(&w.occluded) {
                if !occluded {
                    w.nodes[i as usize].color += term.value();
                }
            }
            let next = wave.end..w.nodes.len();
            w.rays.clear();
            w.rays.extend(w.nodes[next.clone()].iter().map(|t| t.ray));
            w.hits.clear();
            w.hits.resize(next.len(), None);
            scene.intersect_stream(&w.rays, f32::INFINITY, &mut w.hits, &mut ctx.traversal);
            wave = next;
        }
        // Children come after their parents: from the last ray back, each ray's children are
        // complete when it is combined.
        for i in (0..w.nodes.len()).rev() {
            let t = w.nodes[i];
            let mut color = t.color;
            if t.reflected != NO_CHILD {
                color += t.kr * w.nodes[t.reflected as usize].color;
            }
            if t.refracted != NO_CHILD {
                color += t.kt * w.nodes[t.refracted as usize].color;
            }
            w.nodes[i].color = color;
        }
        for (o, t) in out.iter_mut().zip(&w.nodes) {
            o.radiance = t.color;
        }
    }
}

/// Whitted's local model: ambient, plus Lambertian diffuse and a Blinn-Phong highlight from every
/// delta emitter a shadow ray reaches. Surfaces are two-sided: normals are turned towards the
/// viewer.
pub fn local_shading(
    scene: &Scene,
    m: &Phong,
    si: &SurfaceInteraction,
    wo: Vec3,
    ctx: &mut TraceContext,
) -> Vec3 {
    shade_locally(scene, m, m.albedo, si, wo, &Origins::new(si), ctx)
}

/// The origins of the rays leaving one shading point: [`crate::math::offset_ray_origin`] depends on
/// the direction only through the side of the surface it points to, so the offset is computed once
/// and shared by the shadow rays and the reflected and refracted rays. No cache of the rounded
/// origins: the compiler kept that (an `Option` per side) out of line, and its result then went
/// through memory (see [`Origins::towards`]).
struct Origins<'a> {
    si: &'a SurfaceInteraction,
    offset: Vec3,
}

impl<'a> Origins<'a> {
    #[inline(always)]
    fn new(si: &'a SurfaceInteraction) -> Self {
        Self {
            si,
            offset: surface_offset(si.p_error, si.n),
        }
    }

    /// `offset_ray_origin(si.p, si.p_error, si.n, w)`, the same value. Inlined: called out of
    /// line, `w` went through memory, and reading it back as wider loads than the caller's stores
    /// stalled store-to-load forwarding (the largest single cost in the Whitted frame, perf).
    #[inline(always)]
    fn towards(&self, w: Vec3) -> Vec3 {
        let si = self.si;
        offset_ray_origin_by(si.p, self.offset, w.dot(si.n) < 0.0)
    }
}

/// [`local_shading`] with the albedo apart from the lobes `m` (whose own `albedo` is not read):
/// a `phong` material's lobes are then read in place (see [`Scene::whitted_material`]). Inlined,
/// so that the surface interaction is read from where its caller built it, in registers or in
/// stores of the same widths (see [`Origins::towards`]).
#[inline(always)]
fn shade_locally(
    scene: &Scene,
    m: &Phong,
    albedo: Vec3,
    si: &SurfaceInteraction,
    wo: Vec3,
    origins: &Origins,
    ctx: &mut TraceContext,
) -> Vec3 {
    let mut color = ambient_term(scene, m, albedo);
    direct_terms(
        scene,
        m,
        albedo,
        si,
        wo,
        origins,
        |shadow_ray, t_max, term| {
            ctx.rays.shadow += 1;
            if !scene.occluded(&shadow_ray, t_max, &mut ctx.traversal) {
                color += term.value();
            }
        },
    );
    color
}

/// The ambient part of Whitted's local model, the colour a shading point starts from.
#[inline(always)]
fn ambient_term(scene: &Scene, m: &Phong, albedo: Vec3) -> Vec3 {
    m.ambient * scene.ambient * albedo
}

/// The diffuse and highlight terms of each delta emitter that can light this side of the
/// surface, in the emitters' order: `light(shadow_ray, t_max, term)`, where `term` is to be added
/// to the colour when nothing lies on the shadow ray within `t_max`. The term is computed before
/// the shadow ray is answered (all but its highlight's power, see [`LightTerm`]), so that a caller
/// may answer many at once (a stream).
#[inline(always)]
fn direct_terms(
    scene: &Scene,
    m: &Phong,
    albedo: Vec3,
    si: &SurfaceInteraction,
    wo: Vec3,
    origins: &Origins,
    mut light: impl FnMut(Ray, f32, LightTerm),
) {
    if m.diffuse == 0.0 && m.specular == 0.0 {
        return;
    }
    let wo = wo.normalize();
    let ns = if si.ns.dot(wo) < 0.0 { -si.ns } else { si.ns };
    let emitters = &scene.emitters;
    for &e in &emitters.delta {
        // Direction and radiance first: the shadow ray is only built for a light that can reach
        // this side of the surface.
        let Some((wi, radiance, target)) = delta_light(&emitters.emitters[e as usize], si.p) else {
            continue;
        };
        let cos = ns.dot(wi);
        // A light behind the shading normal, or below the geometric surface, cannot light this side.
        if cos <= 0.0 || si.n.dot(wi) * si.n.dot(wo) <= 0.0 {
            continue;
        }
        let origin = origins.towards(wi);
        let (shadow_ray, t_max) = match target {
            Some(position) => (Ray::new(origin, position - origin), 1.0 - SHADOW_EPSILON),
            None => (Ray::new(origin, wi), f32::INFINITY),
        };
        let term = LightTerm {
            radiance,
            diffuse: m.diffuse * cos * albedo,
            specular: m.specular,
            shininess: m.shininess,
            cos_h: ns.dot((wi + wo).normalize()),
        };
        light(shadow_ray, t_max, term);
    }
}

/// What one delta emitter adds to a shading point that its shadow ray reaches, kept apart until
/// the shadow ray is answered so that the highlight's `powf` is paid only for lit points.
#[derive(Clone, Copy)]
struct LightTerm {
    radiance: Vec3,
    /// `diffuse * cos * albedo`.
    diffuse: Vec3,
    specular: f32,
    shininess: f32,
    /// The cosine between the shading normal and the half vector.
    cos_h: f32,
}

impl LightTerm {
    /// Lambertian diffuse and the Blinn-Phong highlight.
    #[inline(always)]
    fn value(&self) -> Vec3 {
        let highlight = if self.specular > 0.0 {
            self.specular * self.cos_h.max(0.0).powf(self.shininess)
        } else {
            0.0
        };
        self.radiance * (self.diffuse + Vec3::splat(highlight))
    }
}

/// The reflected and refracted rays leaving a specular surface hit by `ray`, each with its weight
/// (`None` where the material has none, or the weight is zero): Fresnel's split of a dielectric,
/// total internal reflection folded into the reflection.
#[inline(always)]
fn specular_rays(
    m: &Phong,
    ray: &Ray,
    si: &SurfaceInteraction,
    origins: &Origins,
) -> [Option<(f32, Ray)>; 2] {
    let wo = -ray.dir;
    // Normals on the side the ray arrives from.
    let entering = ray.dir.dot(si.n) < 0.0;
    let ns = if si.ns.dot(wo) < 0.0 { -si.ns } else { si.ns };
    let mut kr = m.reflection;
    let mut kt = m.transmission;
    let mut refracted = None;
    if kt > 0.0 {
        // eta = n_incident / n_transmitted; the outside is taken to be vacuum (no nested media).
        let eta = if entering { 1.0 / m.ior } else { m.ior };
        match refract(ray.dir, ns, eta) {
            None => {
                // Total internal reflection: everything transmitted is reflected instead.
                kr += kt;
                kt = 0.0;
            }
            Some(t) => {
                if m.fresnel {
                    let f = fresnel_dielectric(ns.dot(wo), eta);
                    kr += kt * f;
                    kt *= 1.0 - f;
                }
                refracted = Some(t);
            }
        }
    }
    let reflected = if kr > 0.0 {
        let dir = reflect(ray.dir, ns);
        Some((kr, Ray::new(origins.towards(dir), dir)))
    } else {
        None
    };
    let refracted = match (refracted, kt > 0.0) {
        (Some(dir), true) => Some((kt, Ray::new(origins.towards(dir), dir))),
        _ => None,
    };
    [reflected, refracted]
}

/// The direction toward a delta emitter from `p`, the radiance it brings (intensity over the
/// squared distance, or a directional light's irradiance), and where a shadow ray toward it ends
/// (`None`: at infinity). Point and directional lights, the common cases, inline; the others
/// through the general dispatch, which is a call.
#[inline(always)]
fn delta_light(light: &Emitter, p: Vec3) -> Option<(Vec3, Vec3, Option<Vec3>)> {
    match light {
        Emitter::Point(l) => l.sample_li(p).map(|s| (s.wi, s.weight, Some(l.position))),
        Emitter::Directional(l) => l.sample_li().map(|s| (s.wi, s.weight, None)),
        other => other
            .sample_li(p, Vec2::ZERO)
            .map(|s| (s.wi, s.weight, other.position())),
    }
}

#[cfg(test)]
mod tests {
    use crate::description::description_from_str;
    use crate::description::parse::Syntax;
    use crate::math::Vec3;
    use crate::render::{render, RenderOptions};
    use crate::scene::builtin::builtin_scene;
    use crate::scene::Scene;
    use std::path::Path;

    /// The wavefront (rows without AOVs) gives `trace`'s pixels bit for bit and the same ray
    /// counts: one sample per pixel with the AOVs (the camera rays traced depth first, as AOVs
    /// need) against the same without them, on scenes of one leaf and of a tree, with glass,
    /// mirrors and total internal reflection.
    #[test]
    fn the_wavefront_gives_the_recursions_pixels() {
        for name in ["whitted", "glass-block", "mirror-room"] {
            let text = builtin_scene(name).unwrap();
            let mut d = description_from_str(text, Syntax::Toml, Path::new(name)).unwrap();
            (d.camera.width, d.camera.height) = (83, 61);
            d.render.spp = 1;
            let scene = Scene::new(&d, Path::new(".")).unwrap();
            let (depth_first, a) = render(&scene, &RenderOptions::default()).unwrap();
            let skip = RenderOptions {
                skip_aovs: true,
                ..Default::default()
            };
            let (wavefront, b) = render(&scene, &skip).unwrap();
            let bits = |v: &[Vec3]| {
                v.iter()
                    .map(|c| c.to_array().map(f32::to_bits))
                    .collect::<Vec<_>>()
            };
            assert!(bits(&depth_first.rgb) == bits(&wavefront.rgb), "{name}");
            assert_eq!(a.rays, b.rays, "{name}");
            assert_eq!(a.traversal, b.traversal, "{name}");
            assert!(a.rays.reflection > 0 && a.rays.shadow > 0, "{name}");
        }
    }
}
