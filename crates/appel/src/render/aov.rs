//! Mitsuba 3's `aov` integrator: named arbitrary output variables of the surface each pixel sees
//! (depth, position, uv, normals, surface derivatives, primitive and shape indices), written as
//! image channels with Mitsuba's names (`name.T`, `name.X/Y/Z`, `name.U/V`, `name.I`), beside the
//! image of an optional nested integrator (the film's R, G, B, and `NAME.R/G/B/A` when the nested
//! integrator is named).
//!
//! Mitsuba averages the AOVs of all of a pixel's samples through the reconstruction filter; Appel
//! evaluates them, as its other AOVs, on the ray through the pixel's centre. The two agree where
//! the pixel sees one smooth surface and differ at silhouettes, where Mitsuba blends the values
//! of both sides (a depth between the two distances, an index that is no index). A pixel whose
//! centre ray hits nothing has zeros, as in Mitsuba.

use super::integrator::{centre_aov, FilmSample, Integrator, PixelIntegrator};
use super::sampler::Sampler;
use super::{
    render_with, with_sampler, Channel, Film, PixelAov, RenderOptions, RenderStats, TraceContext,
    Window,
};
use crate::description::{AovChannel, AovType};
use crate::error::{Error, Result};
use crate::geometry::SurfaceInteraction;
use crate::math::{Vec2, Vec3};
use crate::scene::{IntegratorKind, RenderSettings, Scene, SceneHit};
use rayon::prelude::*;
use std::time::Instant;

#[derive(Clone, Debug)]
pub struct Aov {
    channels: Vec<AovChannel>,
    /// The integrator whose image the film holds; none: black.
    nested: Option<IntegratorKind>,
    /// The name under which the nested integrator's image is written again.
    image: Option<String>,
    /// Whether emitters seen directly are hidden: then a ray that leaves the scene does not
    /// cover its pixel in the nested image's alpha even where an environment emitter lies.
    hide_emitters: bool,
}

impl Integrator for Aov {
    const NAME: &'static str = "aov";

    fn from_settings(s: &RenderSettings) -> Result<Self> {
        let p = &s.integrator_params.aov;
        let channels = p
            .channels()
            .map_err(|e| Error::Invalid(format!("[render.aov] aovs: {e}")))?;
        if p.integrator == Some(IntegratorKind::Aov) {
            return Err(Error::Invalid(
                "[render.aov] integrator: the nested integrator cannot be another `aov`".into(),
            ));
        }
        Ok(Aov {
            channels,
            nested: p.integrator,
            image: p.image.clone(),
            hide_emitters: s.hide_emitters,
        })
    }

    fn render(&self, scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        let (mut film, mut stats) = match self.nested {
            Some(kind) => render_with(kind, scene, options)?,
            None => with_sampler(scene, self, options)?,
        };
        // A film asked for the image alone gets no channels either.
        if options.skip_aovs {
            return Ok((film, stats));
        }
        let start = Instant::now();
        let (w, h) = (scene.camera.width, scene.camera.height);
        let window = options.window.unwrap_or(Window::full(w, h));
        let (channels, ctx) = self.channels(scene, window, &film);
        film.channels = channels;
        stats.merge(&ctx);
        stats.time += start.elapsed();
        Ok((film, stats))
    }
}

impl PixelIntegrator for Aov {
    /// Without a nested integrator the image is black (Mitsuba's), and the samples only place
    /// it on the film.
    fn sample<S: Sampler>(
        &self,
        scene: &Scene,
        x: u32,
        y: u32,
        sampler: &mut S,
        aov: Option<&mut PixelAov>,
        ctx: &mut TraceContext,
    ) -> FilmSample {
        let pos = Vec2::new(x as f32, y as f32) + sampler.get_2d();
        if let Some(aov) = aov {
            *aov = centre_aov(scene, x, y, ctx);
        }
        FilmSample {
            pos,
            radiance: Vec3::ZERO,
        }
    }
}

impl Aov {
    /// The channels of the pixels of `window` (the film's), in order: the nested image's under
    /// its name, then the AOVs in the order `aovs` lists them.
    fn channels(&self, scene: &Scene, window: Window, film: &Film) -> (Vec<Channel>, TraceContext) {
        let mut names: Vec<String> = Vec::new();
        if let Some(image) = &self.image {
            names.extend(["R", "G", "B", "A"].map(|c| format!("{image}.{c}")));
        }
        for c in &self.channels {
            names.extend(c.channel_names());
        }
        let per_pixel = names.len();
        if per_pixel == 0 {
            return (Vec::new(), TraceContext::default());
        }
        let environment = !self.hide_emitters
            && scene
                .emitters
                .emitters
                .iter()
                .any(|e| e.is_infinite() && !e.is_delta());
        let ww = (window.x1 - window.x0) as usize;
        let rows: Vec<(Vec<f32>, TraceContext)> = (window.y0..window.y1)
            .into_par_iter()
            .map(|y| {
                let mut ctx = TraceContext::default();
                let mut values = Vec::with_capacity(ww * per_pixel);
                for x in window.x0..window.x1 {
                    let ray = scene.camera.pixel_ray(x, y);
                    ctx.rays.camera += 1;
                    let hit = scene
                        .intersect(&ray, f32::INFINITY, &mut ctx.traversal)
                        .map(|h| (h, scene.geometry.interaction_with(&ray, &h, true)));
                    if self.image.is_some() {
                        let i = film.index(x - window.x0, y - window.y0);
                        let rgb = film.rgb[i];
                        let alpha = hit.is_some() || environment;
                        values.extend([rgb.x, rgb.y, rgb.z, f32::from(u8::from(alpha))]);
                    }
                    for c in &self.channels {
                        push_values(scene, c.ty, hit.as_ref(), &mut values);
                    }
                }
                (values, ctx)
            })
            .collect();
        let n = ww * (window.y1 - window.y0) as usize;
        let mut channels: Vec<Channel> = names
            .into_iter()
            .map(|name| Channel {
                name,
                values: Vec::with_capacity(n),
            })
            .collect();
        let mut ctx = TraceContext::default();
        for (values, row_ctx) in &rows {
            for pixel in values.chunks_exact(per_pixel) {
                for (c, v) in channels.iter_mut().zip(pixel) {
                    c.values.push(*v);
                }
            }
            ctx.rays.camera += row_ctx.rays.camera;
            ctx.traversal.merge(&row_ctx.traversal);
        }
        (channels, ctx)
    }
}

/// The values of an AOV of type `ty` at a hit (zeros where there is none), as many as its
/// channels.
fn push_values(
    scene: &Scene,
    ty: AovType,
    hit: Option<&(SceneHit, SurfaceInteraction)>,
    out: &mut Vec<f32>,
) {
    let Some((h, si)) = hit else {
        out.extend(std::iter::repeat_n(0.0, ty.suffixes().len()));
        return;
    };
    let v3 = |out: &mut Vec<f32>, v: Vec3| out.extend(v.to_array());
    match ty {
        AovType::Depth => out.push(h.t),
        AovType::Position => v3(out, si.p),
        AovType::Uv => out.extend(si.uv.to_array()),
        AovType::GeoNormal => v3(out, si.n),
        AovType::ShNormal => v3(out, si.ns),
        AovType::DpDu => v3(out, si.dpdu),
        AovType::DpDv => v3(out, si.dpdv),
        AovType::PrimIndex => out.push(scene.geometry.source_ids(h).1 as f32),
        AovType::ShapeIndex => out.push((scene.geometry.source_ids(h).0 + 1) as f32),
    }
}
