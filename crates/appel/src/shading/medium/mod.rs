//! Participating media and phase functions, the runtime halves of `[media.NAME]`: Mitsuba 3's
//! `homogeneous` and `heterogeneous` media over its volumes (`constvolume`, `gridvolume`), and
//! its phase functions `isotropic`, `hg`, `rayleigh` and `blendphase`. Both sets are closed enums
//! generated from the lists in the description layer (`for_each_medium!`, `for_each_phase!`):
//! one match per call, then the plugin's own code.
//!
//! Directions follow the light's travel: a phase function takes the direction `d` a ray was
//! going and the direction `wo` it leaves in, and its angle is `cos θ = d · wo` (forward
//! scattering is `wo = d`). Mitsuba writes the same functions of its `wi = -d` with the sign of
//! the cosine's term flipped; the values agree.

mod build;
pub mod majorant_grid;
pub mod volume;

#[cfg(test)]
mod tests;

pub use build::build_medium;
pub use heterogeneous::Scattering;
pub use majorant_grid::{MajorantGrid, MajorantSegment, Majorants};
pub use volume::Volume;

use crate::math::{Ray, Vec2, Vec3};

/// A direction drawn from a phase function.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseSample {
    pub wo: Vec3,
    /// Solid-angle density of `wo`.
    pub pdf: f32,
    /// `p(d, wo) / pdf`: 1 for the phase functions sampled exactly.
    pub weight: f32,
}

/// A phase function: the angular distribution of light scattered at a point of a medium. Every
/// phase function here integrates to 1 over the sphere, so its value is a density of directions.
pub trait PhasePlugin {
    /// Its name in the phase list (Mitsuba's plugin name).
    const NAME: &'static str;

    /// The phase function for light travelling along `d` scattered into `wo` (both unit).
    fn eval(&self, d: Vec3, wo: Vec3) -> f32;

    /// Solid-angle density of [`PhasePlugin::sample`] returning `wo`.
    fn pdf(&self, d: Vec3, wo: Vec3) -> f32;

    /// A direction for light travelling along `d`: `u1` chooses a component (blends), `u2` the
    /// direction.
    fn sample(&self, d: Vec3, u1: f32, u2: Vec2) -> Option<PhaseSample>;
}

/// A participating medium: where along a ray it can interact, with majorants of its extinction
/// there, and its coefficients at a point (Woodcock et al. 1965's null-collision setting, as in
/// pbrt-v4 section 14.2 and Mitsuba 3's `Medium`).
pub trait MediumPlugin {
    /// Its name in the medium list (Mitsuba's plugin name).
    const NAME: &'static str;

    /// Whether the extinction is the same everywhere (then transmittance is `exp(-sigma_t d)`).
    const HOMOGENEOUS: bool;

    /// The parts of the ray's `[0, t_max]` where the medium may interact, in order, each with
    /// a bound on the extinction there (per channel); none if the ray misses the medium.
    fn majorants(&self, ray: &Ray, t_max: f32) -> Majorants<'_>;

    /// Extinction and scattering coefficients `(sigma_t, sigma_s)` at `p`.
    fn coefficients(&self, p: Vec3) -> (Vec3, Vec3);

    fn phase(&self) -> &Phase;
}

macro_rules! define_phases {
    ($($Variant:ident { name: $name:ident, desc: $Desc:ident, runtime: $module:ident::$Type:ident }),* $(,)?) => {
        $(mod $module;)*
        $(pub use $module::$Type;)*

        $(const _: () = assert!(
            crate::accel::same_name(<$Type as PhasePlugin>::NAME, stringify!($name)),
            concat!("`", stringify!($Type), "::NAME` must be its name in the phase list")
        );)*

        /// One of the phase functions, matched once per call.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Phase {
            $($Variant($Type),)*
        }

        impl Phase {
            /// See [`PhasePlugin::eval`].
            #[inline]
            pub fn eval(&self, d: Vec3, wo: Vec3) -> f32 {
                match self {
                    $(Phase::$Variant(p) => p.eval(d, wo),)*
                }
            }

            /// See [`PhasePlugin::pdf`].
            #[inline]
            pub fn pdf(&self, d: Vec3, wo: Vec3) -> f32 {
                match self {
                    $(Phase::$Variant(p) => p.pdf(d, wo),)*
                }
            }

            /// See [`PhasePlugin::sample`].
            #[inline]
            pub fn sample(&self, d: Vec3, u1: f32, u2: Vec2) -> Option<PhaseSample> {
                match self {
                    $(Phase::$Variant(p) => p.sample(d, u1, u2),)*
                }
            }

            /// The phase function's name.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Phase::$Variant(_) => <$Type as PhasePlugin>::NAME,)*
                }
            }
        }
    };
}
crate::description::for_each_phase!(define_phases);

macro_rules! define_media {
    ($($Variant:ident { name: $name:ident, desc: $Desc:ident, runtime: $module:ident::$Type:ident }),* $(,)?) => {
        $(mod $module;)*
        $(pub use $module::$Type;)*

        $(const _: () = assert!(
            crate::accel::same_name(<$Type as MediumPlugin>::NAME, stringify!($name)),
            concat!("`", stringify!($Type), "::NAME` must be its name in the medium list")
        );)*

        /// One of the media, matched once per call.
        #[derive(Clone, Debug)]
        pub enum Medium {
            $($Variant($Type),)*
        }

        impl Medium {
            /// See [`MediumPlugin::HOMOGENEOUS`].
            #[inline]
            pub fn is_homogeneous(&self) -> bool {
                match self {
                    $(Medium::$Variant(_) => <$Type as MediumPlugin>::HOMOGENEOUS,)*
                }
            }

            /// See [`MediumPlugin::majorants`].
            #[inline]
            pub fn majorants(&self, ray: &Ray, t_max: f32) -> Majorants<'_> {
                match self {
                    $(Medium::$Variant(m) => m.majorants(ray, t_max),)*
                }
            }

            /// See [`MediumPlugin::coefficients`].
            #[inline]
            pub fn coefficients(&self, p: Vec3) -> (Vec3, Vec3) {
                match self {
                    $(Medium::$Variant(m) => m.coefficients(p),)*
                }
            }

            /// See [`MediumPlugin::phase`].
            #[inline]
            pub fn phase(&self) -> &Phase {
                match self {
                    $(Medium::$Variant(m) => m.phase(),)*
                }
            }
        }
    };
}
crate::description::for_each_medium!(define_media);

/// The frame around unit `d`: two unit vectors orthogonal to it and to each other.
#[inline]
fn around(d: Vec3, cos_theta: f32, phi: f32) -> Vec3 {
    let (t, b) = crate::math::orthonormal_basis(d);
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let (s, c) = phi.sin_cos();
    (t * (sin_theta * c) + b * (sin_theta * s) + d * cos_theta).normalize()
}
