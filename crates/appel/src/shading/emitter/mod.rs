//! Light sources of the path tracer, as Mitsuba 3's emitters: the interface integrators sample
//! (`sample_li`, `pdf_li`) and evaluate (`radiance_area`, `radiance_env`), and a power-based choice
//! among them. Every emitter implements [`EmitterPlugin`] and is listed once in the registry
//! (`for_each_emitter!`, in the description layer), from which its module, the [`Emitter`] enum
//! and the enum's per-call match are generated.

pub mod distribution;
mod emission;
pub mod equal_area;
mod light_picker;
pub mod shape_sampler;
pub mod warp;

#[cfg(test)]
mod chi2_sphere;

pub use emission::{EmitterRay, PositionSample};
pub use light_picker::LightPicker;
pub use shape_sampler::{ShapeSampler, TriangleSet};
pub use sunsky::{SunPlacement, SunSkyParams, SunTime, SUN_APERTURE};

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

/// An emitter's model: how a light is sampled from a point and evaluated along a ray. The flags
/// are constants, so that the defaults below are checked when the registry instantiates them: a
/// default that does not fit the emitter's flags (an infinite emitter without `radiance_env`, a
/// surface without `radiance_area`) is a compile-time error, not a light that silently sends
/// nothing.
///
/// The methods take one shading point. A version over 8 SIMD lanes would keep these signatures
/// with the scalar types made generic (as Mitsuba 3 writes its emitters once over Dr.Jit's
/// `Float`): `p: Vec3x8`, `u: Vec2x8` and an active-lane mask in, an `EmitterSample` of 8-wide
/// arrays out, the flags staying per emitter (one emitter per call, its lanes the shading points
/// that picked it).
pub trait EmitterPlugin: Clone + std::fmt::Debug {
    /// Its name in the registry.
    const NAME: &'static str;
    /// Whether its light comes from a point or a single direction (a delta distribution), which
    /// no other sampling strategy can hit.
    const DELTA: bool;
    /// Whether it lies at infinity, reached by rays that leave the scene.
    const INFINITE: bool;

    /// A direction from `p` toward the light for the 2D sample `u`; `None` when the light sends
    /// nothing to `p` along it (behind a one-sided surface, outside a spot's cone, a degenerate
    /// sample).
    fn sample_li(&self, p: Vec3, u: Vec2) -> Option<EmitterSample>;

    /// Solid-angle pdf with which `sample_li` from `p` returns the direction `wi` reaching this
    /// emitter at `light_point` with normal `light_normal` (both ignored for infinite lights).
    /// The default, zero, is that of delta lights, and only theirs.
    fn pdf_li(&self, _p: Vec3, _wi: Vec3, _light_point: Vec3, _light_normal: Vec3) -> f32 {
        const { assert!(Self::DELTA, "an emitter that is not delta defines pdf_li") };
        0.0
    }

    /// Radiance leaving the emitter's surface at normal `n`, uv `uv`, toward `w` (unit, away from
    /// the surface). The default, zero, is that of emitters that are no surface (delta or
    /// infinite).
    fn radiance_area(&self, _n: Vec3, _uv: Vec2, _w: Vec3) -> Vec3 {
        const {
            assert!(
                Self::DELTA || Self::INFINITE,
                "a surface emitter defines radiance_area"
            )
        };
        Vec3::ZERO
    }

    /// Radiance arriving along a ray of world direction `d` that leaves the scene. The default,
    /// zero, is that of finite emitters and of infinite delta ones (a directional light, which
    /// no ray hits).
    fn radiance_env(&self, _d: Vec3) -> Vec3 {
        const {
            assert!(
                !Self::INFINITE || Self::DELTA,
                "an infinite emitter that is not delta defines radiance_env"
            )
        };
        Vec3::ZERO
    }

    /// Where a light at a point sits (points, spots, projectors): a shadow ray toward it ends
    /// there. The default, `None`, is that of lights with no single position.
    fn position(&self) -> Option<Vec3> {
        None
    }

    /// A ray leaving the light, for light tracing (Mitsuba's `Emitter::sample_ray`): a position
    /// from `u_pos`, a direction from `u_dir`. Infinite lights leave this default, `None`: their
    /// rays enter through the scene's bounding sphere, which [`Emitter::sample_ray`] builds from
    /// `sample_li` (see `emission.rs`).
    fn sample_ray(&self, _u_pos: Vec2, _u_dir: Vec2) -> Option<EmitterRay> {
        const { assert!(Self::INFINITE, "a finite emitter defines sample_ray") };
        None
    }

    /// The density by solid angle with which [`Self::sample_ray`] leaves a point of normal
    /// `normal` (zero for lights at a point) along unit `dir`: what bidirectional path tracing's
    /// weights need of a light's rays. The default is that of infinite lights, whose rays
    /// `Emitter::sample_ray` builds: the bidirectional integrator weighs them by `pdf_li` and the
    /// disk they enter through instead.
    fn pdf_ray_dir(&self, _normal: Vec3, _dir: Vec3) -> f32 {
        const { assert!(Self::INFINITE, "a finite emitter defines pdf_ray_dir") };
        0.0
    }

    /// The density by area of [`Self::sample_ray`]'s and [`Self::sample_position`]'s points:
    /// 1 for a light at a point (a delta distribution), which is the default.
    fn pdf_position(&self) -> f32 {
        const {
            assert!(
                Self::DELTA || Self::INFINITE,
                "a surface emitter defines pdf_position"
            )
        };
        1.0
    }

    /// A point of the light's surface by area (Mitsuba's `Emitter::sample_position`), which light
    /// tracing connects to the camera to show emitters seen directly. The default, `None`, is that
    /// of lights with no surface (delta or infinite), which no camera ray hits.
    fn sample_position(&self, _u: Vec2) -> Option<PositionSample> {
        const {
            assert!(
                Self::DELTA || Self::INFINITE,
                "a surface emitter defines sample_position"
            )
        };
        None
    }

    /// Emitted power (flux) per channel, by which the light picker chooses among emitters.
    /// Infinite lights count what crosses the scene's bounding sphere (see
    /// [`Self::set_scene_bounds`]).
    fn power(&self) -> Vec3;

    /// Tells an infinite light the scene's bounding sphere, which its power needs. The default,
    /// nothing, is that of finite emitters.
    fn set_scene_bounds(&mut self, _center: Vec3, _radius: f32) {
        const {
            assert!(
                !Self::INFINITE,
                "an infinite emitter defines set_scene_bounds"
            )
        };
    }
}

/// The items of `shading::emitter` generated from the emitter list.
macro_rules! define_emitters {
    ($($Variant:ident { name: $name:ident, runtime: $module:ident::$Type:ident, light: [$($Desc:ident)?] }),* $(,)?) => {
        $(mod $module;)*
        $(pub use $module::$Type;)*

        $(const _: () = assert!(
            crate::accel::same_name(<$Type as EmitterPlugin>::NAME, stringify!($name)),
            concat!("`", stringify!($Type), "::NAME` must be its name in the emitter list")
        );)*

        /// A light of the scene: one match per call, then the emitter's own code (no dynamic
        /// dispatch). The tag is a field of its own rather than a niche in a variant's fields,
        /// so that telling the variants apart is one comparison, not a decoding (the `whitted`
        /// and `raycast` integrators do it for every light at every shading point).
        #[derive(Clone, Debug)]
        #[repr(u32)]
        pub enum Emitter {
            $($Variant($Type),)*
        }

        impl Emitter {
            /// See [`EmitterPlugin::sample_li`].
            #[inline]
            pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<EmitterSample> {
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::sample_li(l, p, u),)*
                }
            }

            /// See [`EmitterPlugin::pdf_li`].
            #[inline]
            pub fn pdf_li(&self, p: Vec3, wi: Vec3, light_point: Vec3, light_normal: Vec3) -> f32 {
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::pdf_li(l, p, wi, light_point, light_normal),)*
                }
            }

            /// See [`EmitterPlugin::radiance_area`]: one-sided as Mitsuba's `area` (zero behind).
            #[inline]
            pub fn radiance_area(&self, n: Vec3, uv: Vec2, w: Vec3) -> Vec3 {
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::radiance_area(l, n, uv, w),)*
                }
            }

            /// See [`EmitterPlugin::radiance_env`].
            #[inline]
            pub fn radiance_env(&self, d: Vec3) -> Vec3 {
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::radiance_env(l, d),)*
                }
            }

            /// A ray leaving the light (see [`EmitterPlugin::sample_ray`]); an infinite light's
            /// enters the scene's bounding sphere `(centre, radius)` (see `emission.rs`).
            #[inline]
            pub fn sample_ray(&self, u_pos: Vec2, u_dir: Vec2, sphere: (Vec3, f32)) -> Option<EmitterRay> {
                if self.is_infinite() {
                    return emission::infinite_ray(self, u_pos, u_dir, sphere);
                }
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::sample_ray(l, u_pos, u_dir),)*
                }
            }

            /// See [`EmitterPlugin::pdf_ray_dir`].
            #[inline]
            pub fn pdf_ray_dir(&self, normal: Vec3, dir: Vec3) -> f32 {
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::pdf_ray_dir(l, normal, dir),)*
                }
            }

            /// See [`EmitterPlugin::pdf_position`].
            #[inline]
            pub fn pdf_position(&self) -> f32 {
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::pdf_position(l),)*
                }
            }

            /// See [`EmitterPlugin::sample_position`].
            #[inline]
            pub fn sample_position(&self, u: Vec2) -> Option<PositionSample> {
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::sample_position(l, u),)*
                }
            }

            /// Emitted power (flux), the mean of its R, G and B values.
            pub fn power(&self) -> f32 {
                let rgb = match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::power(l),)*
                };
                (rgb.x + rgb.y + rgb.z) / 3.0
            }

            /// See [`EmitterPlugin::position`].
            pub fn position(&self) -> Option<Vec3> {
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::position(l),)*
                }
            }

            pub fn is_delta(&self) -> bool {
                match self {
                    $(Emitter::$Variant(_) => <$Type as EmitterPlugin>::DELTA,)*
                }
            }

            pub fn is_infinite(&self) -> bool {
                match self {
                    $(Emitter::$Variant(_) => <$Type as EmitterPlugin>::INFINITE,)*
                }
            }

            /// Its name in the registry.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Emitter::$Variant(_) => <$Type as EmitterPlugin>::NAME,)*
                }
            }

            /// See [`EmitterPlugin::set_scene_bounds`].
            pub fn set_scene_bounds(&mut self, center: Vec3, radius: f32) {
                match self {
                    $(Emitter::$Variant(l) => EmitterPlugin::set_scene_bounds(l, center, radius),)*
                }
            }
        }
    };
}
crate::description::for_each_emitter!(define_emitters);
