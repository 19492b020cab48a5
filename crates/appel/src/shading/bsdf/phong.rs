//! `phong`: the phenomenological model of Whitted (1980), Phong's (1975) ambient + diffuse +
//! specular local shading with Blinn's (1977) half-vector highlight, plus an ideal mirror and an
//! ideal refraction weighted by fixed coefficients or by the Fresnel reflectance.
//!
//! Its parameters are read directly by the `whitted` and `raycast` integrators, which evaluate the
//! lobes themselves (shadow rays to delta emitters, recursion along the delta directions): see
//! [`Bsdf::whitted`], the Whitted response every BSDF has (each BSDF's file defines its own). The model has no physically based counterpart (its highlight is not normalized, its
//! coefficients need not conserve energy), so the Monte Carlo integrators see it as its nearest
//! physically based BSDF: glass of its index where it transmits, a mirror of its reflection
//! coefficient where that is at least one half, otherwise Lambertian reflection of its diffuse
//! colour (documented in docs/scene-format.md).

use super::{AnyBsdf, Bsdf, BsdfFlags, BsdfMaterial, BsdfSample, Conductor, Dielectric, Diffuse};
use super::TextureSource;
use crate::description::PhongDesc;
use crate::error::Result;
use crate::math::{Vec2, Vec3};
use crate::shading::texture::TexPoint;

/// A `phong` material's constant parameters: the BSDF with the material's colour as its albedo,
/// and an optional procedural checkerboard that alternates that colour with another.
/// [`Self::at_uv`] gives the BSDF at a surface point; the integrators that read the lobes
/// themselves borrow [`Self::base`] and take only the albedo from the point ([`Self::albedo`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongParams {
    /// Everything but the checkerboard: `albedo` is the material's colour.
    pub base: Phong,
    pub checker: Option<Checker>,
}

/// Squares of side `size` alternating between the material's colour and `color`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checker {
    pub color: Vec3,
    pub size: f32,
}

/// The Phong BSDF at a surface point: the colour resolved, the coefficients as the material's.
/// Also the Whitted response of any BSDF ([`Bsdf::whitted`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phong {
    /// The diffuse (and ambient) colour at the point.
    pub albedo: Vec3,
    /// Weight of the scene's ambient light.
    pub ambient: f32,
    /// Weight of the Lambertian lobe, `albedo * cos` per light.
    pub diffuse: f32,
    /// Weight of the Blinn highlight, uncoloured.
    pub specular: f32,
    /// Exponent of the Blinn highlight.
    pub shininess: f32,
    /// Weight of the ideal mirror direction (a delta reflection).
    pub reflection: f32,
    /// Weight of the ideal refracted direction (a delta transmission).
    pub transmission: f32,
    /// Index of refraction of the inside, the outside being vacuum.
    pub ior: f32,
    /// Whether the Fresnel reflectance moves part of `transmission` to `reflection`.
    pub fresnel: bool,
}

impl PhongParams {
    /// A `phong` material's parameters as written.
    pub fn from_desc(d: &PhongDesc) -> PhongParams {
        PhongParams {
            base: Phong {
                albedo: d.color.into(),
                ambient: d.ambient,
                diffuse: d.diffuse,
                specular: d.specular,
                shininess: d.shininess,
                reflection: d.reflection,
                transmission: d.transmission,
                ior: d.ior,
                fresnel: d.fresnel,
            },
            checker: d.checker.as_ref().map(|c| Checker {
                color: c.color.into(),
                size: c.size,
            }),
        }
    }

    /// The BSDF at texture coordinates `uv` (read only when [`Self::needs_uv`]).
    #[inline(always)]
    pub fn at_uv(&self, uv: Vec2) -> Phong {
        Phong {
            albedo: self.albedo(uv),
            ..self.base
        }
    }

    /// The diffuse colour at texture coordinates `uv`: squares of side `checker.size` alternate
    /// between the material's colour (the square containing the origin's +u,+v corner) and
    /// `checker.color`.
    #[inline(always)]
    pub fn albedo(&self, uv: Vec2) -> Vec3 {
        match self.checker {
            Some(c) => {
                let cell = uv / c.size;
                if floor_parity(cell.x) == floor_parity(cell.y) {
                    self.base.albedo
                } else {
                    c.color
                }
            }
            None => self.base.albedo,
        }
    }

    /// Whether [`Self::at_uv`] depends on `uv`: surfaces may skip computing it otherwise.
    #[inline]
    pub fn needs_uv(&self) -> bool {
        self.checker.is_some()
    }
}

/// The Monte Carlo integrators' reading of a Phong BSDF (see the module's documentation).
enum Equivalent {
    Diffuse(Diffuse),
    Conductor(Conductor),
    Dielectric(Dielectric),
}

macro_rules! equivalent {
    ($self:ident, $b:ident => $e:expr) => {
        match $self.equivalent() {
            Equivalent::Diffuse($b) => $e,
            Equivalent::Conductor($b) => $e,
            Equivalent::Dielectric($b) => $e,
        }
    };
}

impl Phong {
    /// Lambertian reflection of `albedo` and nothing else: the response of a BSDF whose glossy
    /// or delta lobes Whitted's model has no counterpart for.
    pub fn matte(albedo: Vec3) -> Self {
        Phong {
            albedo,
            ambient: 0.0,
            diffuse: 1.0,
            specular: 0.0,
            shininess: 1.0,
            reflection: 0.0,
            transmission: 0.0,
            ior: 1.0,
            fresnel: false,
        }
    }

    /// An ideal mirror tinted by `tint`: the response of delta (or, for the recursion, rough)
    /// reflection.
    pub fn mirror(tint: Vec3) -> Self {
        Phong {
            diffuse: 0.0,
            reflection: 1.0,
            ..Phong::matte(tint)
        }
    }

    /// Fresnel-weighted reflection and refraction into a medium of relative index `eta`.
    pub fn glass(eta: f32) -> Self {
        Phong {
            diffuse: 0.0,
            transmission: 1.0,
            ior: eta,
            fresnel: true,
            ..Phong::matte(Vec3::ZERO)
        }
    }

    /// A diffuse `albedo` under a glossy coating, the coating as a Blinn highlight of exponent
    /// `shininess`.
    pub fn coated(albedo: Vec3, shininess: f32) -> Self {
        Phong {
            specular: 1.0,
            shininess,
            ..Phong::matte(albedo)
        }
    }

    /// Whether a reflected or refracted ray is traced from the point.
    #[inline(always)]
    pub fn is_specular(&self) -> bool {
        self.reflection > 0.0 || self.transmission > 0.0
    }

    fn equivalent(&self) -> Equivalent {
        if self.transmission > 0.0 {
            Equivalent::Dielectric(Dielectric::new(
                self.ior,
                Vec3::ONE,
                Vec3::splat(self.transmission.min(1.0)),
            ))
        } else if self.reflection >= 0.5 {
            Equivalent::Conductor(Conductor::new(
                Vec3::ZERO,
                Vec3::ONE,
                Vec3::splat(self.reflection.min(1.0)),
            ))
        } else {
            Equivalent::Diffuse(Diffuse::new(
                (self.albedo * self.diffuse).clamp(Vec3::ZERO, Vec3::ONE),
            ))
        }
    }
}

impl Bsdf for Phong {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        equivalent!(self, b => b.eval(wo, wi))
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        equivalent!(self, b => b.pdf(wo, wi))
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        equivalent!(self, b => b.eval_pdf(wo, wi))
    }

    #[inline]
    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        equivalent!(self, b => b.sample(wo, u1, u2))
    }

    fn flags(&self) -> BsdfFlags {
        equivalent!(self, b => b.flags())
    }

    /// What Whitted's integrator reads of this BSDF: itself.
    #[inline(always)]
    fn whitted(&self) -> Phong {
        *self
    }

    /// The Monte Carlo integrators see the model as its physically based equivalent, so that
    /// one is regularized: glass and mirrors become their rough twins, the Lambertian
    /// equivalent stays this BSDF.
    fn regularized(&self) -> AnyBsdf {
        match self.equivalent() {
            Equivalent::Dielectric(b) => b.regularized(),
            Equivalent::Conductor(b) => b.regularized(),
            Equivalent::Diffuse(_) => AnyBsdf::Phong(*self),
        }
    }
}

impl BsdfMaterial for PhongParams {
    type Desc = PhongDesc;
    type Bsdf = Phong;

    fn build(d: &PhongDesc, _: &mut dyn TextureSource) -> Result<Self> {
        Ok(PhongParams::from_desc(d))
    }

    #[inline(always)]
    fn at(&self, p: &TexPoint) -> Phong {
        self.at_uv(p.uv)
    }
}

/// `x.floor() as i64`, without `floor`: x86_64 without SSE4.1 has no rounding instruction, so
/// `floor` is a library call, costly on Whitted's checkerboard. The conversion truncates towards
/// zero (and saturates, NaN giving 0, as `floor() as i64` does); one step down fixes negative
/// non-integers.
#[inline]
fn floor_i64(x: f32) -> i64 {
    let i = x as i64;
    if (i as f32) > x {
        i.saturating_sub(1)
    } else {
        i
    }
}

/// `floor(x)` modulo 2 (0 or 1), as `floor_i64(x).rem_euclid(2)` for every `x`: the parity of
/// the sum of two floors, which decides the checkerboard's square, is that of the two parities.
/// Below 2^22 in magnitude, adding 1.5 * 2^23 rounds `x` to the nearest integer `n` and leaves
/// `n`'s parity in the lowest mantissa bit (the constant is even), and `floor(x)` is `n` or, when
/// `n > x`, `n - 1`. Those few exact float operations replace the saturating conversion and its
/// correction, which were most of the checkerboard's cost; larger values, infinities and NaN take
/// [`floor_i64`].
#[inline(always)]
fn floor_parity(x: f32) -> u32 {
    const SHIFT: f32 = 12_582_912.0;
    if x.abs() < 4_194_304.0 {
        let shifted = x + SHIFT;
        let n = shifted - SHIFT;
        (shifted.to_bits() & 1) ^ (n > x) as u32
    } else {
        (floor_i64(x) & 1) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::super::AnyBsdf;
    use super::*;

    fn params() -> PhongParams {
        PhongParams {
            base: Phong {
                albedo: Vec3::new(1.0, 0.0, 0.0),
                ambient: 0.1,
                diffuse: 0.9,
                specular: 0.0,
                shininess: 32.0,
                reflection: 0.0,
                transmission: 0.0,
                ior: 1.5,
                fresnel: false,
            },
            checker: Some(Checker {
                color: Vec3::new(1.0, 1.0, 0.0),
                size: 2.0,
            }),
        }
    }

    #[test]
    fn checker_alternates_between_neighbouring_squares() {
        let m = params();
        let red = Vec3::new(1.0, 0.0, 0.0);
        let yellow = Vec3::new(1.0, 1.0, 0.0);
        assert_eq!(m.at_uv(Vec2::new(0.5, 0.5)).albedo, red);
        assert_eq!(m.at_uv(Vec2::new(2.5, 0.5)).albedo, yellow);
        assert_eq!(m.at_uv(Vec2::new(-0.5, 0.5)).albedo, yellow);
        assert_eq!(m.at_uv(Vec2::new(-0.5, -0.5)).albedo, red);
        assert!(m.needs_uv());
    }

    /// The Monte Carlo integrators see glass where the material transmits, a mirror where it
    /// mostly reflects, Lambertian reflection of `albedo * diffuse` otherwise.
    #[test]
    fn monte_carlo_reading_is_the_nearest_physical_bsdf() {
        let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
        let wi = Vec3::new(-0.4, 0.1, 0.8).normalize();
        let matte = params().at_uv(Vec2::new(0.5, 0.5));
        let lambert = Diffuse::new(Vec3::new(0.9, 0.0, 0.0));
        assert_eq!(matte.eval(wo, wi), lambert.eval(wo, wi));
        assert_eq!(matte.pdf(wo, wi), lambert.pdf(wo, wi));
        assert_eq!(matte.flags(), BsdfFlags::DIFFUSE_REFLECTION);

        let mirror = Phong {
            reflection: 0.85,
            ..matte
        };
        let s = mirror.sample(wo, 0.5, Vec2::new(0.5, 0.5)).unwrap();
        assert_eq!(s.lobe, BsdfFlags::DELTA_REFLECTION);
        assert!((s.weight - Vec3::splat(0.85)).abs().max_element() < 1e-6);
        assert_eq!(mirror.eval(wo, wi), Vec3::ZERO);

        let glass = Phong {
            transmission: 1.0,
            ..matte
        };
        assert!(glass.flags().contains(BsdfFlags::DELTA_TRANSMISSION));
        let d = Dielectric::new(1.5, Vec3::ONE, Vec3::ONE);
        for u1 in [0.01, 0.5, 0.99] {
            assert_eq!(
                glass.sample(wo, u1, Vec2::ZERO),
                d.sample(wo, u1, Vec2::ZERO)
            );
        }
    }

    #[test]
    fn whitted_response_follows_the_bsdf() {
        let phong = params().at_uv(Vec2::new(2.5, 0.5));
        assert_eq!(AnyBsdf::Phong(phong).whitted(), phong);
        let grey = Vec3::splat(0.4);
        let d = AnyBsdf::Diffuse(Diffuse::new(grey)).whitted();
        assert_eq!((d.albedo, d.diffuse, d.specular), (grey, 1.0, 0.0));
        assert!(!d.is_specular());
        let g = AnyBsdf::Dielectric(Dielectric::new(1.33, Vec3::ONE, Vec3::ONE)).whitted();
        assert_eq!((g.transmission, g.reflection, g.ior), (1.0, 0.0, 1.33));
        assert!(g.fresnel && g.diffuse == 0.0);
        let m = AnyBsdf::Conductor(Conductor::new(Vec3::ONE, Vec3::ONE, Vec3::ONE)).whitted();
        assert_eq!((m.reflection, m.diffuse, m.transmission), (1.0, 0.0, 0.0));
    }

    #[test]
    fn floor_i64_is_floor_then_cast() {
        let specials = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -1.5,
            2.999_999_8,
            -2.999_999_8,
            8_388_607.5,
            -8_388_607.5,
            1.0e10,
            -1.0e10,
            1.0e30,
            -1.0e30,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        let mut s = 1u32;
        let random = (0..100_000).map(|_| {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            f32::from_bits(s)
        });
        for x in specials.into_iter().chain(random) {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
    }

    #[test]
    fn floor_parity_is_that_of_floor_i64() {
        let specials = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.499_999_97,
            -0.499_999_97,
            1.0 - f32::EPSILON / 2.0,
            -1.0 + f32::EPSILON / 2.0,
            2.999_999_8,
            -2.999_999_8,
            4_194_303.5,
            -4_194_303.5,
            4_194_304.0,
            -4_194_304.0,
            4_194_305.0,
            8_388_607.5,
            -8_388_607.5,
            1.0e10,
            -1.0e10,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        let mut s = 1u32;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            s
        };
        // Every bit pattern's kind of value, then values where the fast path applies, from
        // fractions of a square to the edge of its range.
        let random: Vec<f32> = (0..200_000)
            .map(|i| {
                let r = next();
                match i % 3 {
                    0 => f32::from_bits(r),
                    1 => (r as i32) as f32 / 256.0,
                    _ => (r as i32 >> 8) as f32 / 4.0,
                }
            })
            .collect();
        for x in specials.into_iter().chain(random) {
            assert_eq!(
                floor_parity(x),
                floor_i64(x).rem_euclid(2) as u32,
                "{x} ({:#x})",
                x.to_bits()
            );
        }
    }
}
