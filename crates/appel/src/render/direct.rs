//! Mitsuba's `direct` integrator: emitters seen by the camera, and direct light by multiple
//! importance sampling of one emitter and one BSDF sample; the path tracer's estimator stopped
//! after direct light.

use super::integrator::{FilmSample, Integrator, PixelIntegrator, PixelRow};
use super::path::PathTracer;
use super::sampler::Sampler;
use super::{with_sampler, Film, PixelAov, RenderOptions, RenderStats, TraceContext};
use crate::error::Result;
use crate::scene::{RenderSettings, Scene};

#[derive(Clone, Copy, Debug)]
pub struct Direct(pub PathTracer);

impl Integrator for Direct {
    const NAME: &'static str = "direct";

    fn from_settings(s: &RenderSettings) -> Result<Self> {
        Ok(Direct(PathTracer::direct(s.hide_emitters)))
    }

    fn render(&self, scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        with_sampler(scene, self, options)
    }
}

impl PixelIntegrator for Direct {
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
        self.0.sample(scene, x, y, sampler, aov, ctx)
    }

    #[inline]
    fn sample_row<S: Sampler>(
        &self,
        scene: &Scene,
        row: PixelRow,
        sampler: &mut S,
        out: &mut [FilmSample],
        aovs: Option<&mut [PixelAov]>,
        ctx: &mut TraceContext,
    ) {
        self.0.sample_row(scene, row, sampler, out, aovs, ctx)
    }
}
