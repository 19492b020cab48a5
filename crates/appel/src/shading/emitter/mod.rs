//! Light sources of the path tracer, as Mitsuba 3's emitters: the interface integrators sample
//! (`sample_li`, `pdf_li`) and evaluate (`radiance_area`, `radiance_env`), and a power-based choice
//! among them.

mod area;
mod constant;
mod directional;
pub mod distribution;
mod envmap;
mod light_picker;
mod point;
mod projector;
pub mod shape_sampler;
mod spot;
mod sunsky;
pub mod warp;

#[cfg(test)]
mod chi2_sphere;

pub use area::AreaEmitter;
pub use constant::ConstantEnvironment;
pub use directional::DirectionalLight;
pub use envmap::EnvMap;
pub use light_picker::LightPicker;
pub use point::PointLight;
pub use projector::Projector;
pub use shape_sampler::{ShapeSampler, TriangleSet};
pub use spot::SpotLight;
pub use sunsky::{SunPlacement, SunSky, SunSkyParams, SunTime, SUN_APERTURE};

use glam::{Vec2, Vec3};

/// A direction toward a light, sampled from a reference point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmitterSample {
    /// Unit, world space, from the reference point toward the light.
    pub wi: Vec3,
    /// Distance to the sampled point (`f32::INFINITY` for infinite lights).
    pub dist: f32,
    /// Emitted radiance / pdf (for delta lights: intensity / dist², or the irradiance of a
    /// directional light).
    pub weight: Vec3,
    /// Solid-angle density (1 for delta lights).
    pub pdf: f32,
    pub delta: bool,
}

#[derive(Clone, Debug)]
pub enum Emitter {
    Point(PointLight),
    Spot(SpotLight),
    Projector(Projector),
    Directional(DirectionalLight),
    Area(AreaEmitter),
    Constant(ConstantEnvironment),
    EnvMap(EnvMap),
    SunSky(SunSky),
}

impl Emitter {
    /// A direction from `p` toward the light for the 2D sample `u`; `None` when the light sends
    /// nothing to `p` along it (behind a one-sided surface, outside a spot's cone, a degenerate
    /// sample).
    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<EmitterSample> {
        match self {
            Emitter::Point(l) => l.sample_li(p),
            Emitter::Spot(l) => l.sample_li(p),
            Emitter::Projector(l) => l.sample_li(p),
            Emitter::Directional(l) => l.sample_li(),
            Emitter::Area(l) => l.sample_li(p, u),
            Emitter::Constant(l) => l.sample_li(u),
            Emitter::EnvMap(l) => l.sample_li(u),
            Emitter::SunSky(l) => l.sample_li(u),
        }
    }

    /// Solid-angle pdf with which `sample_li` from `p` returns the direction `wi` reaching this
    /// emitter at `light_point` with normal `light_normal` (both ignored for infinite lights).
    /// Zero for delta lights, which no other sampling strategy can hit.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, light_point: Vec3, light_normal: Vec3) -> f32 {
        match self {
            Emitter::Point(_)
            | Emitter::Spot(_)
            | Emitter::Projector(_)
            | Emitter::Directional(_) => 0.0,
            Emitter::Area(l) => l.pdf_li(p, wi, light_point, light_normal),
            Emitter::Constant(l) => l.pdf_li(),
            Emitter::EnvMap(l) => l.pdf_li(wi),
            Emitter::SunSky(l) => l.pdf_li(wi),
        }
    }

    /// Radiance leaving an area emitter's surface at normal `n`, uv `uv`, toward `w` (unit, away
    /// from the surface): one-sided as Mitsuba's `area` (zero behind). Zero for other emitters.
    pub fn radiance_area(&self, n: Vec3, uv: Vec2, w: Vec3) -> Vec3 {
        match self {
            Emitter::Area(l) => l.radiance(n, uv, w),
            _ => Vec3::ZERO,
        }
    }

    /// Radiance arriving along a ray of world direction `d` that leaves the scene (infinite
    /// emitters only; zero otherwise).
    pub fn radiance_env(&self, d: Vec3) -> Vec3 {
        match self {
            Emitter::Constant(l) => l.radiance,
            Emitter::EnvMap(l) => l.radiance(d),
            Emitter::SunSky(l) => l.radiance(d),
            _ => Vec3::ZERO,
        }
    }

    /// Emitted power (flux), the mean of its R, G and B values. Infinite lights count what crosses
    /// the scene's bounding sphere (see [`set_scene_bounds`](Self::set_scene_bounds)).
    pub fn power(&self) -> f32 {
        let rgb = match self {
            Emitter::Point(l) => l.power(),
            Emitter::Spot(l) => l.power(),
            Emitter::Projector(l) => l.power(),
            Emitter::Directional(l) => l.power(),
            Emitter::Area(l) => l.power(),
            Emitter::Constant(l) => l.power(),
            Emitter::EnvMap(l) => l.power(),
            Emitter::SunSky(l) => l.power(),
        };
        (rgb.x + rgb.y + rgb.z) / 3.0
    }

    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Emitter::Point(_) | Emitter::Spot(_) | Emitter::Projector(_) | Emitter::Directional(_)
        )
    }

    pub fn is_infinite(&self) -> bool {
        matches!(
            self,
            Emitter::Directional(_)
                | Emitter::Constant(_)
                | Emitter::EnvMap(_)
                | Emitter::SunSky(_)
        )
    }

    /// Infinite lights need the scene's bounding sphere for their power.
    pub fn set_scene_bounds(&mut self, _center: Vec3, radius: f32) {
        match self {
            Emitter::Directional(l) => l.scene_radius = radius,
            Emitter::Constant(l) => l.scene_radius = radius,
            Emitter::EnvMap(l) => l.scene_radius = radius,
            Emitter::SunSky(l) => l.scene_radius = radius,
            _ => {}
        }
    }
}
