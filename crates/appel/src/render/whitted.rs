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
    aov_of, camera_ray, centre_aov, surface_hit, CameraRay, FilmSample, Integrator, PixelRow,
    SurfaceHit,
};
use super::optics::{fresnel_dielectric, reflect, refract};
use super::sampler::Sampler;
use super::{PixelAov, TraceContext};
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
                sample_row_first_hit(self, scene, row, sampler, out, aovs, ctx)
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
        if kr > 0.0 {
            let dir = reflect(ray.dir, ns);
            let origin = origins.towards(dir);
            color += kr * self.spawn(scene, origin, dir, depth, Bounce::Reflection, ctx);
        }
        if let (Some(dir), true) = (refracted, kt > 0.0) {
            let origin = origins.towards(dir);
            color += kt * self.spawn(scene, origin, dir, depth, Bounce::Refraction, ctx);
        }
        color
    }

    fn spawn(
        &self,
        scene: &Scene,
        origin: Vec3,
        dir: Vec3,
        depth: u32,
        kind: Bounce,
        ctx: &mut TraceContext,
    ) -> Vec3 {
        match kind {
            Bounce::Reflection => ctx.rays.reflection += 1,
            Bounce::Refraction => ctx.rays.refraction += 1,
        }
        let ray = Ray::new(origin, dir);
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
    let mut color = m.ambient * scene.ambient * albedo;
    if m.diffuse == 0.0 && m.specular == 0.0 {
        return color;
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
        ctx.rays.shadow += 1;
        if scene.occluded(&shadow_ray, t_max, &mut ctx.traversal) {
            continue;
        }
        let h = (wi + wo).normalize();
        let highlight = if m.specular > 0.0 {
            m.specular * ns.dot(h).max(0.0).powf(m.shininess)
        } else {
            0.0
        };
        color += radiance * (m.diffuse * cos * albedo + Vec3::splat(highlight));
    }
    color
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
