//! Mitsuba 3's particle tracer, `ptracer` (light tracing: Veach 1997 section 10.2, pbrt-v4's
//! `LightPathIntegrator`): paths start at the lights, chosen by the scene's light picker, and
//! every vertex is connected to the camera and splatted where it lands on the film; emitters seen
//! directly are a point of an emitter connected to the camera (Mitsuba's
//! `sample_visible_emitters`). The meanings of `max_depth` (1: emitters seen directly, 2: direct
//! light), `rr_depth` and `hide_emitters` are Mitsuba's. Shading normals are corrected for the
//! adjoint transport (Veach 1997 section 5.3.2); refraction's radiance scaling is undone for
//! importance (section 5.2).
//!
//! The batches of light paths, their determinism and the variance of the film are `light_pass`'s
//! and `splat_film`'s.

use super::integrator::{vertex_limit, Integrator};
use super::light_pass::{
    render_light_paths, start_light_path, LightPath, LightPathTracer, LightVertex,
};
use super::path::{visible, visible_along, SHADOW_EPSILON};
use super::sampler::Sampler;
use super::splat_film::Splat;
use super::{Film, RenderOptions, RenderStats, TraceContext};
use crate::description::CameraKind;
use crate::error::{Error, Result};
use crate::math::{offset_ray_origin, Ray, Vec3};
use crate::scene::{RenderSettings, Scene};

#[derive(Clone, Copy, Debug)]
pub struct ParticleTracer {
    /// The most vertices of a path; `u32::MAX` for unlimited.
    pub max_depth: u32,
    pub rr_depth: u32,
    pub hide_emitters: bool,
    pub samples_per_pass: u32,
}

impl Integrator for ParticleTracer {
    const NAME: &'static str = "ptracer";

    fn from_settings(s: &RenderSettings) -> Result<Self> {
        Ok(ParticleTracer {
            max_depth: vertex_limit(s.max_depth),
            rr_depth: s.rr_depth,
            hide_emitters: s.hide_emitters,
            samples_per_pass: s.integrator_params.ptracer.samples_per_pass,
        })
    }

    fn render(&self, scene: &Scene, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        check_camera(scene)?;
        render_light_paths(scene, self, self.samples_per_pass, options)
    }
}

/// Light paths reach the film only through a camera that points can be connected to.
pub(super) fn check_camera(scene: &Scene) -> Result<()> {
    if scene.camera.kind == CameraKind::Orthographic {
        return Err(Error::Invalid(
            "integrators that trace from the lights need a perspective camera: an orthographic \
             camera sees along one direction, through which no light path can be connected \
             (Mitsuba 3's orthographic sensor does not sample directions either)"
                .into(),
        ));
    }
    Ok(())
}

impl LightPathTracer for ParticleTracer {
    type Scratch = ();

    fn trace<S: Sampler>(
        &self,
        scene: &Scene,
        _: (u32, u32),
        sampler: &mut S,
        splats: &mut Vec<Splat>,
        _: &mut (),
        ctx: &mut TraceContext,
    ) {
        let emitters = &scene.emitters;
        if self.max_depth == 0 || emitters.picker.is_empty() {
            return;
        }
        if !self.hide_emitters {
            self.visible_emitter(scene, sampler, splats, ctx);
        }
        let Some(start) = start_light_path(scene, sampler) else {
            return;
        };
        let mut path = LightPath::new(&start);
        while path.depth < self.max_depth {
            let Some(v) = path.next_vertex(scene, sampler, ctx) else {
                break;
            };
            if v.leaks() {
                break;
            }
            let LightVertex {
                si,
                frame,
                bsdf,
                prev_local,
                cos_g_prev,
                ..
            } = v;
            // Connection to the camera.
            let u_lens = sampler.get_2d();
            if bsdf.flags().has_smooth() {
                if let Some(c) = scene.camera.connect(si.p, u_lens) {
                    let cam_local = frame.to_local(c.wi);
                    let cos_g_cam = si.n.dot(c.wi);
                    if cos_g_cam * cam_local.z > 0.0 {
                        // Light flows from the previous vertex to the camera: the BSDF with its
                        // outgoing direction toward the camera (the radiance BSDF, its cosine at
                        // the previous vertex), and the adjoint's shading-normal factor
                        // |cos_g(camera)| / |cos_g(previous)|.
                        let f = bsdf.eval_pdf(cam_local, prev_local).0;
                        let value =
                            path.throughput * f * (cos_g_cam.abs() / cos_g_prev.abs() * c.weight);
                        if value != Vec3::ZERO {
                            let t_max = c.dist * (1.0 - SHADOW_EPSILON);
                            if visible(scene, &si, c.wi, t_max, sampler, ctx) {
                                splats.push(Splat::new(c.pos, value));
                            }
                        }
                    }
                }
            }
            // BSDF sampling continues the light path.
            if !path.scatter(&v, self.rr_depth, sampler, ctx) {
                break;
            }
        }
    }
}

impl ParticleTracer {
    /// A point of one emitter connected to the camera: the emitters the camera sees directly,
    /// which no light path's later vertex shows (Mitsuba's `sample_visible_emitters`). Delta
    /// lights have no surface to see; an infinite light is seen along a direction it samples.
    fn visible_emitter<S: Sampler>(
        &self,
        scene: &Scene,
        sampler: &mut S,
        splats: &mut Vec<Splat>,
        ctx: &mut TraceContext,
    ) {
        let emitters = &scene.emitters;
        let (e, pmf) = emitters.picker.pick(sampler.get_1d());
        let (u_pos, u_lens) = (sampler.get_2d(), sampler.get_2d());
        let em = &emitters.emitters[e];
        if pmf <= 0.0 || em.is_delta() {
            return;
        }
        if em.is_infinite() {
            let camera = &scene.camera;
            let Some(s) = em.sample_li(camera.eye, u_pos) else {
                return;
            };
            let Some(c) = camera.connect_direction(s.wi, u_lens) else {
                return;
            };
            let value = s.weight * (c.weight / pmf);
            if value == Vec3::ZERO {
                return;
            }
            // From the near plane, as camera rays start.
            let origin = c.lens + s.wi * (camera.near_clip / s.wi.dot(camera.forward));
            if visible_along(scene, Ray::new(origin, s.wi), f32::INFINITY, sampler, ctx) {
                splats.push(Splat::new(c.pos, value));
            }
            return;
        }
        let Some(ps) = em.sample_position(u_pos) else {
            return;
        };
        let Some(c) = scene.camera.connect(ps.point, u_lens) else {
            return;
        };
        let cos_light = ps.normal.dot(c.wi);
        if cos_light <= 0.0 {
            return;
        }
        let le = em.radiance_area(ps.normal, ps.uv, c.wi);
        let value = le * (cos_light / (pmf * ps.pdf) * c.weight);
        if value == Vec3::ZERO {
            return;
        }
        let origin = offset_ray_origin(ps.point, ps.point_error, ps.normal, c.wi);
        let t_max = (c.lens - origin).length() * (1.0 - SHADOW_EPSILON);
        if visible_along(scene, Ray::new(origin, c.wi), t_max, sampler, ctx) {
            splats.push(Splat::new(c.pos, value));
        }
    }
}
