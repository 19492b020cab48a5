//! Rendering: one loop for every integrator (`render_loop`): passes of samples over image tiles in
//! parallel; the integrator traces each sample's camera ray itself, from the sampler's film
//! position; the film sums the samples through the reconstruction filter.

pub mod aov;
pub mod bdpt;
pub mod cost;
pub mod direct;
mod film;
pub mod film_block;
pub mod filter;
pub mod integrator;
mod light_pass;
pub mod optics;
pub mod path;
mod path_wave;
pub mod ptracer;
pub mod render_loop;
pub mod sampler;
pub mod splat_film;
pub mod sppm;
mod tile_film;
pub mod volpath;
mod whitted;
mod window;

pub use film::{Channel, Film, PixelAov, MISS_ID};
pub use integrator::{surface_hit, FilmSample, Integrator, PixelIntegrator, PixelRow, SurfaceHit};
pub use whitted::{local_shading, Raycast, Whitted};
pub use window::Window;

use crate::accel::TraversalStats;
use crate::description::SamplerName;
use crate::error::Result;
use crate::scene::{IntegratorKind, Scene};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// Side of the square tiles the image is cut into; each tile is one parallel task.
pub const TILE_SIZE: u32 = 16;

/// Rays cast, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub camera: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.reflection + self.refraction
    }

    fn merge(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
    }
}

/// Per-thread tallies carried along every ray.
#[derive(Clone, Copy, Debug, Default)]
pub struct TraceContext {
    pub rays: RayCounts,
    pub traversal: TraversalStats,
    /// Monte Carlo samples whose value was not finite (counted as zero).
    pub invalid_samples: u64,
}

/// What a render did.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderStats {
    pub time: Duration,
    pub rays: RayCounts,
    pub traversal: TraversalStats,
    /// Samples per pixel taken (fewer than asked when a time limit stopped the render).
    pub spp: u32,
    pub invalid_samples: u64,
}

impl RenderStats {
    /// Adds another render's work (of the same image: the samples per pixel are the fewer).
    pub(crate) fn add(&mut self, o: &RenderStats) {
        self.time += o.time;
        self.rays.merge(&o.rays);
        self.traversal.merge(&o.traversal);
        self.spp = self.spp.min(o.spp);
        self.invalid_samples += o.invalid_samples;
    }

    pub(crate) fn merge(&mut self, ctx: &TraceContext) {
        self.rays.merge(&ctx.rays);
        self.traversal.merge(&ctx.traversal);
        self.invalid_samples += ctx.invalid_samples;
    }

    pub fn mrays_per_second(&self) -> f64 {
        self.rays.total() as f64 / self.time.as_secs_f64().max(1e-9) / 1e6
    }
}

/// How to render, beyond what the scene says. Callers set what they need and take the rest from
/// `..Default::default()`.
#[derive(Default)]
pub struct RenderOptions<'a> {
    /// Called with the number of pixels finished so far (in the window), after each tile.
    pub progress: Option<&'a (dyn Fn(u64) + Sync)>,
    /// When set (Ctrl-C), the render stops after the tiles in flight and returns [`Error::Cancelled`].
    pub cancel: Option<&'a AtomicBool>,
    /// Stop after the pass of samples during which this much time has passed (the image then
    /// has fewer samples per pixel than the scene asks; [`RenderStats::spp`] says how many).
    pub time_limit: Option<Duration>,
    /// Render only these pixels: the film is the window's size, and its pixels are those of the
    /// whole image's render, bit for bit.
    pub window: Option<Window>,
    /// Leave the film's AOVs (depth, normal, ids) empty: a frame that shows only the image
    /// (`appel bench --frames`, the viewer's colour frames) saves finding, storing and copying
    /// them.
    pub skip_aovs: bool,
}

/// Renders the scene with its own integrator, sampler and filter on the current rayon thread
/// pool. The image does not depend on the number of threads (see [`render_loop`]).
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
    render_with(scene.settings.integrator, scene, options)
}

/// The render dispatch generated from the integrator list: one match per render, then the
/// integrator's own code, monomorphized with the sampler.
macro_rules! define_integrator_dispatch {
    ($($Variant:ident { name: $name:ident, runtime: $module:ident::$Type:ident, params: $Params:ident, sampler: $sampler:ident, monte_carlo: $mc:literal, media: $media:literal }),* $(,)?) => {
        $(const _: () = assert!(
            crate::accel::same_name(<$module::$Type as Integrator>::NAME, stringify!($name)),
            concat!("`", stringify!($Type), "::NAME` must be its name in the integrator list")
        );)*

        /// Renders the scene with integrator `kind` (whose parameters the settings hold).
        pub fn render_with(
            kind: IntegratorKind,
            scene: &Scene,
            options: &RenderOptions,
        ) -> Result<(Film, RenderStats)> {
            match kind {
                $(IntegratorKind::$Variant => {
                    <$module::$Type as Integrator>::from_settings(&scene.settings)?
                        .render(scene, options)
                })*
            }
        }
    };
}
crate::description::for_each_integrator!(define_integrator_dispatch);

/// The render loop monomorphized for the integrator and the scene's sampler.
pub(crate) fn with_sampler<I: integrator::PixelIntegrator>(
    scene: &Scene,
    integrator: &I,
    options: &RenderOptions,
) -> Result<(Film, RenderStats)> {
    let s = &scene.settings;
    let passes = render_loop::Passes {
        filter: filter::Filter::new(&s.filter),
        spp: s.spp,
    };
    use render_loop::render_loop as run;
    match s.sampler {
        SamplerName::Independent => run(
            scene,
            integrator,
            &sampler::IndependentSampler::new(s.seed),
            &passes,
            options,
        ),
        SamplerName::Sobol => run(
            scene,
            integrator,
            &sampler::SobolSampler::new(s.seed, s.spp),
            &passes,
            options,
        ),
        SamplerName::PixelPattern => run(
            scene,
            integrator,
            &sampler::PixelPatternSampler::new(s.seed, s.spp),
            &passes,
            options,
        ),
    }
}
