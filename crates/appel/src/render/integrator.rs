//! The interface between the render loop and an integrator: the loop names a pixel and a sample
//! index and positions the sampler there; the integrator draws the film position from the sampler,
//! traces its own camera ray and everything after it, and may fill the pixel's AOVs. The loop
//! only splats what comes back through the reconstruction filter.

use super::sampler::Sampler;
use super::{Film, PixelAov, RenderOptions, RenderStats, TraceContext};
use crate::error::Result;
use crate::geometry::SurfaceInteraction;
use crate::math::{Ray, Vec2, Vec3};
use crate::scene::{RenderSettings, Scene, SceneHit};

/// What one sample brought back: where on the film it was taken (in pixels, pixel `(i, j)`
/// spanning `[i, i+1) x [j, j+1)`) and the radiance along its camera ray.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FilmSample {
    pub pos: Vec2,
    pub radiance: Vec3,
}

/// Sample `index` of the pixels `x0, x0 + 1, ...` of row `y` (as many as the caller's output
/// slice holds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRow {
    pub x0: u32,
    pub y: u32,
    pub index: u32,
}

/// An integrator: how a scene becomes a film. Each is listed once in the registry
/// (`for_each_integrator!`), from which the render dispatch ([`super::render`]) is generated.
/// Most integrators trace from the camera, one pixel sample at a time ([`PixelIntegrator`]),
/// and render through the one render loop; an integrator that traces from the lights (`ptracer`)
/// or wraps another (`aov`) renders its own way.
pub trait Integrator: Sync + Sized {
    /// Its name in the registry (`render.integrator`), checked against the list at compile time.
    const NAME: &'static str;

    /// The integrator the scene's settings describe (its `[render.NAME]` table among them).
    fn from_settings(settings: &RenderSettings) -> Result<Self>;

    /// Renders the scene: for a [`PixelIntegrator`], the render loop over it and the scene's
    /// sampler ([`super::with_sampler`]).
    fn render(&self, scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)>;
}

/// An integrator that estimates each pixel sample from the camera, monomorphized by the render
/// loop for each sampler: no dynamic dispatch per ray or per sample.
///
/// The per-sample methods take one pixel sample at a time. A version over 8 SIMD lanes would
/// keep this shape with the scalar types made generic (as Mitsuba 3 writes its integrators once
/// over Dr.Jit's `Float`): `sample_row` already hands an integrator a row of pixels, so a lane
/// version takes `out.chunks_mut(8)` with a lane mask for the row's tail, draws `[Vec2; 8]` film
/// positions from the sampler, and traces the 8 camera rays as a packet
/// ([`Scene::intersect_coherent`]); `FilmSample` and `PixelAov` become structures of 8-wide
/// arrays.
pub trait PixelIntegrator: Integrator {
    /// Sample `index` of pixel `(x, y)`, the sampler already started there. `aov`, when given
    /// (sample 0), receives what the ray through the pixel centre sees first.
    fn sample<S: Sampler>(
        &self,
        scene: &Scene,
        x: u32,
        y: u32,
        sampler: &mut S,
        aov: Option<&mut PixelAov>,
        ctx: &mut TraceContext,
    ) -> FilmSample;

    /// [`Self::sample`] for `out.len()` neighbouring pixels of one row, `out[i]` and `aovs[i]`
    /// for pixel `row.x0 + i`: the loop's unit of work. An integrator whose camera rays need no
    /// random numbers after the film position may trace them together (see
    /// [`Scene::intersect_coherent`]); the results must be those of one sample at a time.
    fn sample_row<S: Sampler>(
        &self,
        scene: &Scene,
        row: PixelRow,
        sampler: &mut S,
        out: &mut [FilmSample],
        aovs: Option<&mut [PixelAov]>,
        ctx: &mut TraceContext,
    ) {
        sample_row_one_by_one(self, scene, row, sampler, out, aovs, ctx)
    }
}

/// [`PixelIntegrator::sample_row`] as [`PixelIntegrator::sample`] of one pixel after the other (the
/// default, and the fallback of integrators whose own row method does not apply to a scene).
pub fn sample_row_one_by_one<I: PixelIntegrator, S: Sampler>(
    integrator: &I,
    scene: &Scene,
    row: PixelRow,
    sampler: &mut S,
    out: &mut [FilmSample],
    mut aovs: Option<&mut [PixelAov]>,
    ctx: &mut TraceContext,
) {
    for (i, o) in out.iter_mut().enumerate() {
        let x = row.x0 + i as u32;
        sampler.start_pixel_sample(x, row.y, row.index);
        let aov = aovs.as_deref_mut().map(|a| &mut a[i]);
        *o = integrator.sample(scene, x, row.y, sampler, aov, ctx);
    }
}

/// A sample's camera ray and where on the film it was taken.
#[derive(Clone, Copy, Debug)]
pub struct CameraRay {
    /// The film position in pixels.
    pub pos: Vec2,
    pub ray: Ray,
    /// Whether the ray is the one through the pixel's centre and the lens's centre: the ray
    /// whose first hit the pixel's AOVs describe.
    pub centre: bool,
}

/// The most vertices of a path for the settings' `max_depth` (Mitsuba's meaning): -1, or any
/// negative value, is unlimited, `u32::MAX`.
pub fn vertex_limit(max_depth: i32) -> u32 {
    u32::try_from(max_depth).unwrap_or(u32::MAX)
}

/// The current sample's film position in pixel `(x, y)` (its first two dimensions), the lens
/// point (the next two, drawn only by a camera with an aperture) and the camera ray through
/// them.
#[inline]
pub fn camera_ray<S: Sampler>(scene: &Scene, x: u32, y: u32, sampler: &mut S) -> CameraRay {
    let pos = Vec2::new(x as f32, y as f32) + sampler.get_2d();
    let at_centre = pos == Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
    let camera = &scene.camera;
    if camera.has_lens() {
        let lens = sampler.get_lens_2d();
        return CameraRay {
            pos,
            ray: camera.ray_through_lens(pos.x, pos.y, lens),
            centre: at_centre && lens == Vec2::splat(0.5),
        };
    }
    CameraRay {
        pos,
        ray: camera.ray(pos.x, pos.y),
        centre: at_centre,
    }
}

/// A closest hit with its surface, computed once: the renderer needs the surface for the AOVs of the
/// camera ray and the integrator for shading it.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    pub hit: SceneHit,
    pub si: SurfaceInteraction,
}

/// The surface at `hit`, with texture coordinates only where the material reads them.
#[inline(always)]
pub fn surface_hit(scene: &Scene, ray: &Ray, hit: SceneHit) -> SurfaceHit {
    let with_uv = scene.material(&hit).needs_uv();
    SurfaceHit {
        hit,
        si: scene.geometry.interaction_with(ray, &hit, with_uv),
    }
}

/// The AOVs of a surface seen first (or of nothing).
#[inline]
pub fn aov_of(scene: &Scene, hit: Option<&SurfaceHit>) -> PixelAov {
    hit.map_or(PixelAov::MISS, |h| {
        let (shape_id, prim_id) = scene.geometry.source_ids(&h.hit);
        PixelAov {
            depth: h.hit.t,
            normal: h.si.ns,
            shape_id,
            prim_id,
            instance_id: h.hit.instance,
        }
    })
}

/// The AOVs of the ray through the centre of pixel `(x, y)` (and of the lens), traced for them alone (integrators
/// whose samples are not at the centre, or which pass through cut-outs).
pub fn centre_aov(scene: &Scene, x: u32, y: u32, ctx: &mut TraceContext) -> PixelAov {
    let ray = scene.camera.pixel_ray(x, y);
    ctx.rays.camera += 1;
    let hit = scene
        .intersect(&ray, f32::INFINITY, &mut ctx.traversal)
        .map(|h| surface_hit(scene, &ray, h));
    aov_of(scene, hit.as_ref())
}
