//! The stochastic layered BSDF of pbrt-v4's `coateddiffuse` and `coatedconductor`: a dielectric
//! interface over an opaque base, with an optional homogeneous medium between them. Its value,
//! density and samples are Monte Carlo estimates from random walks between the two interfaces
//! (Guo, Hašan and Zhao 2018, "Position-free Monte Carlo simulation for arbitrary layered
//! BSDFs"), organised as in Pharr, Jakob and Humphreys, "Physically Based Rendering", 4th ed.,
//! section 14.3: `eval` walks from `wo` and connects each vertex to `wi` through a direction
//! sampled from `wi`'s side (next-event estimation, with MIS where both ends are rough),
//! `sample` follows one walk until it leaves, and `pdf` estimates the density of the paths that
//! reflect once off the base.
//!
//! The walks draw their random numbers from a generator seeded by a hash of the directions
//! (and of the sample's random numbers), so that a BSDF evaluated twice at the same directions
//! gives the same value and images stay reproducible for a seed.
//!
//! The layer is one-sided (black below its surface, like Mitsuba's plastics): scene readers wrap
//! it in `twosided` where both sides should be coated. The base is opaque, so the BSDF reflects
//! only. The medium's extinction is 1: `thickness` is in mean free paths.

use super::fresnel::fresnel_dielectric;
use super::microfacet::{Microfacet, MicrofacetKind};
use super::{mulsign, AnyBsdf, Bsdf, BsdfFlags, BsdfSample, Conductor, Dielectric, RoughConductor};
use super::{Diffuse, Phong, RoughDielectric};
use crate::math::{Vec2, Vec3};
use crate::shading::frame::ShadingFrame;
use std::f32::consts::PI;

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Below this roughness an interface is taken as perfectly smooth (pbrt-v4's
/// `TrowbridgeReitzDistribution::EffectivelySmooth`).
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// The medium between the interfaces and the walk's bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layer {
    /// In mean free paths (the extinction is 1); positive.
    pub thickness: f32,
    /// Single-scattering albedo; zero: a clear layer, crossed without scattering.
    pub albedo: Vec3,
    /// Henyey-Greenstein asymmetry, in (-1, 1).
    pub g: f32,
    pub max_depth: u16,
    pub samples: u16,
}

/// A scattering event at one interface, for a direction pair restricted to one lobe (pbrt's
/// `BxDFReflTransFlags`).
#[derive(Clone, Copy, Debug)]
struct Lobe {
    wi: Vec3,
    /// `f |cos θi| / pdf`.
    weight: Vec3,
    pdf: f32,
}

/// The dielectric interface on top: smooth (delta) below [`SMOOTH_ALPHA`], else rough GGX with
/// visible-normal sampling (pbrt-v4's Trowbridge-Reitz). Its inside is `z < 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interface {
    /// The coating's index over the outside's.
    pub eta: f32,
    pub distribution: Microfacet,
}

impl Interface {
    pub fn new(eta: f32, alpha_u: f32, alpha_v: f32) -> Self {
        Interface {
            eta,
            distribution: Microfacet::new(MicrofacetKind::Ggx, alpha_u, alpha_v, true),
        }
    }

    #[inline]
    fn is_specular(&self) -> bool {
        self.distribution.alpha_u.max(self.distribution.alpha_v) < SMOOTH_ALPHA
    }

    /// pbrt-v4's `DielectricBxDF::Regularize`: the roughness widened by
    /// [`Microfacet::regularized`], a smooth interface becoming rough GGX of 0.1; an
    /// index-matched one (`eta == 1`) stays as it is, as for [`Dielectric`].
    pub fn regularized(&self) -> Self {
        if self.eta == 1.0 {
            return *self;
        }
        Interface {
            distribution: self.distribution.regularized(),
            ..*self
        }
    }

    #[inline]
    fn smooth(&self) -> Dielectric {
        Dielectric::new(self.eta, Vec3::ONE, Vec3::ONE)
    }

    #[inline]
    fn rough(&self) -> RoughDielectric {
        RoughDielectric::new(self.distribution, self.eta, Vec3::ONE, Vec3::ONE)
    }

    #[inline]
    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        if self.is_specular() {
            self.smooth().sample(wo, u1, u2)
        } else {
            self.rough().sample(wo, u1, u2)
        }
    }

    /// `f |cos θi|`, radiance transport.
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if self.is_specular() {
            Vec3::ZERO
        } else {
            self.rough().eval(wo, wi)
        }
    }

    /// The density of [`Self::sample`], lobe choice included.
    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.is_specular() {
            0.0
        } else {
            self.rough().pdf(wo, wi)
        }
    }

    /// The Fresnel reflectance at the microfacet normal that takes `wo` to `wi` (the macro
    /// normal for a smooth interface).
    #[inline]
    fn fresnel(&self, wo: Vec3, wi: Vec3) -> f32 {
        let m = if self.is_specular() {
            Vec3::Z
        } else if wo.z * wi.z > 0.0 {
            (wo + wi).normalize()
        } else {
            let eta = if wo.z > 0.0 { self.eta } else { 1.0 / self.eta };
            (wo + wi * eta).normalize()
        };
        fresnel_dielectric(wo.dot(mulsign(m, m.z)), self.eta).0
    }

    /// Refraction only: the sampler forced to refract (`u1` above any Fresnel reflectance below
    /// 1), its weight and density then conditioned on having refracted. `importance` drops the
    /// radiance scaling of the crossing (pbrt's `!mode`: the walk from `wi`'s side carries
    /// importance). Also returns `1 - F`, the probability the full sampler would have refracted
    /// at this microfacet normal.
    #[inline]
    fn sample_transmission(&self, wo: Vec3, u2: Vec2, importance: bool) -> Option<(Lobe, f32)> {
        let s = self.sample(wo, ONE_MINUS_EPSILON, u2)?;
        if s.wi.z * wo.z >= 0.0 {
            return None;
        }
        let t = 1.0 - self.fresnel(wo, s.wi);
        if t <= 0.0 {
            return None;
        }
        let radiance = if importance { s.eta * s.eta } else { 1.0 };
        let lobe = Lobe {
            wi: s.wi,
            weight: s.weight * (t * radiance),
            pdf: s.pdf / t,
        };
        Some((lobe, t))
    }

    /// Reflection only, as [`Self::sample_transmission`] with the sampler forced to reflect.
    #[inline]
    fn sample_reflection(&self, wo: Vec3, u2: Vec2) -> Option<Lobe> {
        let s = self.sample(wo, 0.0, u2)?;
        if s.wi.z * wo.z <= 0.0 {
            return None;
        }
        let r = self.fresnel(wo, s.wi);
        if r <= 0.0 {
            return None;
        }
        Some(Lobe {
            wi: s.wi,
            weight: s.weight * r,
            pdf: s.pdf / r,
        })
    }

    /// The density of [`Self::sample_reflection`]: reflection's density given that the sampler
    /// reflects (pbrt's `PDF` restricted to `BxDFReflTransFlags::Reflection`).
    #[inline]
    fn pdf_reflection(&self, wo: Vec3, wi: Vec3) -> f32 {
        let r = self.fresnel(wo, wi);
        if r <= 0.0 {
            return 0.0;
        }
        self.pdf(wo, wi) / r
    }

    /// The density of [`Self::sample_transmission`].
    #[inline]
    fn pdf_transmission(&self, wo: Vec3, wi: Vec3) -> f32 {
        let t = 1.0 - self.fresnel(wo, wi);
        if t <= 0.0 {
            return 0.0;
        }
        self.pdf(wo, wi) / t
    }
}

/// An opaque base under the interface, seen from inside the layer (its normal is `+z`).
pub trait Base: Copy {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3;
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;
    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample>;
    /// Whether it scatters only into delta lobes (then `eval` and `pdf` are zero).
    fn is_specular(&self) -> bool;
    /// Its smooth lobe: diffuse or glossy.
    fn smooth_lobe(&self) -> BsdfFlags;
    /// Whitted's response of the base under its coating ([`Bsdf::whitted`]).
    fn whitted_coated(&self) -> Phong;
    /// The base as [`Bsdf::regularized`] widens it.
    fn regularized(&self) -> Self;
}

impl Base for Diffuse {
    /// The diffuse base with the coating as a sharp highlight, as `plastic`.
    fn whitted_coated(&self) -> Phong {
        Phong::coated(self.reflectance, 200.0)
    }
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        Bsdf::eval(self, wo, wi)
    }
    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        Bsdf::pdf(self, wo, wi)
    }
    #[inline]
    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        Bsdf::sample(self, wo, u1, u2)
    }
    fn is_specular(&self) -> bool {
        false
    }
    fn smooth_lobe(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    /// Nothing to widen (pbrt-v4's `DiffuseBxDF::Regularize` does nothing).
    fn regularized(&self) -> Self {
        *self
    }
}

/// A metal: a mirror below [`SMOOTH_ALPHA`], else rough GGX; its index is relative to the
/// coating's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metal {
    pub eta: Vec3,
    pub k: Vec3,
    pub distribution: Microfacet,
}

impl Metal {
    pub fn new(eta: Vec3, k: Vec3, alpha_u: f32, alpha_v: f32) -> Self {
        Metal {
            eta,
            k,
            distribution: Microfacet::new(MicrofacetKind::Ggx, alpha_u, alpha_v, true),
        }
    }

    #[inline]
    fn rough(&self) -> RoughConductor {
        RoughConductor::new(self.distribution, self.eta, self.k, Vec3::ONE)
    }
}

impl Base for Metal {
    /// A mirror: Whitted's recursion follows delta directions only.
    fn whitted_coated(&self) -> Phong {
        Phong::mirror(Vec3::ONE)
    }
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if self.is_specular() {
            Vec3::ZERO
        } else {
            self.rough().eval(wo, wi)
        }
    }
    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.is_specular() {
            0.0
        } else {
            self.rough().pdf(wo, wi)
        }
    }
    #[inline]
    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        if self.is_specular() {
            Conductor::new(self.eta, self.k, Vec3::ONE).sample(wo, u1, u2)
        } else {
            self.rough().sample(wo, u1, u2)
        }
    }
    #[inline]
    fn is_specular(&self) -> bool {
        self.distribution.alpha_u.max(self.distribution.alpha_v) < SMOOTH_ALPHA
    }
    fn smooth_lobe(&self) -> BsdfFlags {
        BsdfFlags::GLOSSY_REFLECTION
    }
    /// pbrt-v4's `ConductorBxDF::Regularize`: a mirror becomes rough GGX of 0.1.
    fn regularized(&self) -> Self {
        Metal {
            distribution: self.distribution.regularized(),
            ..*self
        }
    }
}

/// A dielectric interface over `base`, with `layer` between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layered<B> {
    pub top: Interface,
    pub base: B,
    pub layer: Layer,
}

/// Transmittance through the layer's medium over a height `dz` along `w`.
#[inline]
fn tr(dz: f32, w: Vec3) -> f32 {
    if dz.abs() <= f32::MIN_POSITIVE {
        1.0
    } else {
        (-(dz / w.z).abs()).exp()
    }
}

/// Veach's power heuristic (exponent 2) for one sample of each of two strategies.
#[inline]
fn power_heuristic(f: f32, g: f32) -> f32 {
    let (f2, g2) = (f * f, g * g);
    if f2.is_infinite() {
        1.0
    } else {
        f2 / (f2 + g2)
    }
}

/// The Henyey-Greenstein phase function for `wo` and `wi` both pointing away from the
/// scattering point (so forward scattering is `wi = -wo`).
#[inline]
fn hg(wo: Vec3, wi: Vec3, g: f32) -> f32 {
    let d = 1.0 + g * g + 2.0 * g * wo.dot(wi);
    (1.0 - g * g) / (4.0 * PI * d * d.max(0.0).sqrt())
}

/// A direction from the Henyey-Greenstein phase function for light arriving from `wo`, by
/// inverting its cumulative distribution in the angle to the propagation direction `-wo`, and
/// its density.
#[inline]
fn sample_hg(wo: Vec3, g: f32, u: Vec2) -> (Vec3, f32) {
    let cos_theta = if g.abs() < 1e-3 {
        1.0 - 2.0 * u.x
    } else {
        let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
        ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
    };
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let local = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
    let wi = ShadingFrame::from_normal(-wo).to_world(local).normalize();
    (wi, hg(wo, wi, g))
}

/// The walks' random numbers: PCG32 (O'Neill 2014) seeded from a hash of directions.
struct Rng {
    state: u64,
    inc: u64,
}

impl Rng {
    const MULTIPLIER: u64 = 0x5851_f42d_4c95_7f2d;

    fn new(seed: u64, stream: u64) -> Self {
        let mut r = Rng {
            state: 0,
            inc: (stream << 1) | 1,
        };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }

    #[inline]
    fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(Self::MULTIPLIER).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform in [0, 1).
    #[inline]
    fn uniform(&mut self) -> f32 {
        ((self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)).min(ONE_MINUS_EPSILON)
    }

    #[inline]
    fn vec2(&mut self) -> Vec2 {
        let x = self.uniform();
        Vec2::new(x, self.uniform())
    }
}

/// A 64-bit hash of floats' bit patterns (the finaliser of MurmurHash3 over each word).
fn hash(values: &[f32]) -> u64 {
    let mut h: u64 = 0x9e37_79b9_7f4a_7c15;
    for v in values {
        h ^= v.to_bits() as u64;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^= h >> 33;
    }
    h
}

impl<B: Base> Layered<B> {
    #[inline]
    fn scatters(&self) -> bool {
        self.layer.albedo != Vec3::ZERO
    }

    fn flags_of(&self) -> BsdfFlags {
        let mut flags = BsdfFlags::NONE;
        if self.top.is_specular() {
            flags = flags | BsdfFlags::DELTA_REFLECTION;
        }
        if self.scatters() {
            flags = flags | BsdfFlags::DIFFUSE_REFLECTION;
        }
        if !self.base.is_specular() {
            flags = flags | self.base.smooth_lobe();
        }
        if !self.top.is_specular() {
            flags = flags | BsdfFlags::GLOSSY_REFLECTION;
        }
        flags
    }

    /// The lobe a sample that left the layer after a non-delta event reports.
    fn smooth_lobe(&self) -> BsdfFlags {
        if self.scatters()
            || (!self.base.is_specular()
                && self.base.smooth_lobe() == BsdfFlags::DIFFUSE_REFLECTION)
        {
            BsdfFlags::DIFFUSE_REFLECTION
        } else {
            BsdfFlags::GLOSSY_REFLECTION
        }
    }

    /// The BSDF value without the cosine (pbrt's `f`), estimated from `samples` walks.
    ///
    /// Where the coat is rough, light leaves through it by two strategies combined by MIS: the
    /// connection through `wis`, sampled from `wi`'s side, and the base's (or the phase
    /// function's) own sample followed by the coat's transmission to `wi`. Both weights use the
    /// densities of the same inside direction. pbrt-v4 weights the second by the coat's density
    /// of `wi` given the inside direction instead, a density over outside directions that
    /// refraction's change of solid angle makes differ from the first's, so that the weights do
    /// not sum to one: for a rough coat (alpha 0.3) over a white Lambertian base its estimate
    /// integrated 8% above the sampled albedo.
    fn f(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let Layer {
            thickness,
            albedo,
            g,
            max_depth,
            samples,
        } = self.layer;
        let (top, base) = (&self.top, &self.base);
        let n = samples as f32;
        // Reflection at the entrance, counted once per walk to be averaged below.
        let mut f = top.eval(wo, wi) / wi.z * n;
        let mut rng = Rng::new(hash(&[wo.x, wo.y, wo.z]), hash(&[wi.x, wi.y, wi.z]));
        // The walk enters and leaves through the top, at z = thickness.
        let exit_z = thickness;
        for _ in 0..samples {
            let Some((wos, _)) = top.sample_transmission(wo, rng.vec2(), false) else {
                continue;
            };
            // A direction into the layer from `wi`'s side, for connections to `wi`.
            let Some((wis, _)) = top.sample_transmission(wi, rng.vec2(), true) else {
                continue;
            };
            // `wis`'s BSDF value over its density (pbrt's `wis.f / wis.pdf`), without its cosine.
            let wis_f_over_pdf = wis.weight / wis.wi.z.abs();
            let mut beta = wos.weight;
            let mut z = thickness;
            let mut w = wos.wi;
            for depth in 0..max_depth {
                // Russian roulette once the walk carries little.
                if depth > 3 && beta.max_element() < 0.25 {
                    let q = (1.0 - beta.max_element()).max(0.0);
                    if rng.uniform() < q {
                        break;
                    }
                    beta /= 1.0 - q;
                }
                if albedo == Vec3::ZERO {
                    // Straight to the other interface.
                    z = if z == thickness { 0.0 } else { thickness };
                    beta *= tr(thickness, w);
                } else {
                    let dz = -(1.0 - rng.uniform()).ln() * w.z.abs();
                    let zp = if w.z > 0.0 { z + dz } else { z - dz };
                    if zp == z {
                        continue;
                    }
                    if 0.0 < zp && zp < thickness {
                        // Scattering in the medium: connect to `wi` through `wis`, MIS against
                        // the phase function where the interface is rough.
                        let wt = if top.is_specular() {
                            1.0
                        } else {
                            power_heuristic(wis.pdf, hg(-w, -wis.wi, g))
                        };
                        f += beta
                            * albedo
                            * hg(-w, -wis.wi, g)
                            * wt
                            * tr(zp - exit_z, wis.wi)
                            * wis_f_over_pdf;
                        let (wn, phase_pdf) = sample_hg(-w, g, rng.vec2());
                        if phase_pdf == 0.0 || wn.z == 0.0 {
                            continue;
                        }
                        // The phase function is sampled exactly: its value over its density is 1.
                        beta *= albedo;
                        w = wn;
                        z = zp;
                        // The phase sample's own connection through the rough interface, MIS
                        // against the connection through `wis` above: `wis_density` is the
                        // density with which that strategy would have chosen `w`.
                        if z < exit_z && w.z > 0.0 && !top.is_specular() {
                            let f_exit = top.eval(-w, wi) / wi.z;
                            if f_exit != Vec3::ZERO {
                                let wis_density = top.pdf_transmission(wi, -w);
                                let wt = power_heuristic(phase_pdf, wis_density);
                                f += beta * tr(zp - exit_z, w) * f_exit * wt;
                            }
                        }
                        continue;
                    }
                    z = zp.clamp(0.0, thickness);
                }
                if z == exit_z {
                    // Reflection back into the layer at the top.
                    let Some(bs) = top.sample_reflection(-w, rng.vec2()) else {
                        break;
                    };
                    beta *= bs.weight;
                    w = bs.wi;
                } else {
                    // At the base: connect to `wi` through `wis`, then scatter.
                    if !base.is_specular() {
                        let wt = if top.is_specular() {
                            1.0
                        } else {
                            power_heuristic(wis.pdf, base.pdf(-w, -wis.wi))
                        };
                        f += beta
                            * base.eval(-w, -wis.wi)
                            * wt
                            * tr(thickness, wis.wi)
                            * wis_f_over_pdf;
                    }
                    let uc = rng.uniform();
                    let Some(bs) = base.sample(-w, uc, rng.vec2()) else {
                        break;
                    };
                    if bs.weight == Vec3::ZERO || bs.pdf == 0.0 || bs.wi.z == 0.0 {
                        break;
                    }
                    beta *= bs.weight;
                    w = bs.wi;
                    if !top.is_specular() {
                        // The base sample's own connection through the rough interface, MIS
                        // against the connection through `wis`, weighted by the density with
                        // which sampling `wis` from `wi` would have chosen `w`.
                        let f_exit = top.eval(-w, wi) / wi.z;
                        if f_exit != Vec3::ZERO {
                            let wt = if base.is_specular() {
                                1.0
                            } else {
                                power_heuristic(bs.pdf, top.pdf_transmission(wi, -w))
                            };
                            f += beta * tr(thickness, w) * f_exit * wt;
                        }
                    }
                }
            }
        }
        f / n
    }
}

impl<B: Base> Bsdf for Layered<B> {
    fn whitted(&self) -> Phong {
        self.base.whitted_coated()
    }

    /// Both interfaces regularized, the layer between them unchanged (pbrt-v4's
    /// `LayeredBxDF::Regularize`).
    fn regularized(&self) -> AnyBsdf
    where
        Self: Into<AnyBsdf>,
    {
        Layered {
            top: self.top.regularized(),
            base: self.base.regularized(),
            layer: self.layer,
        }
        .into()
    }

    /// A Monte Carlo estimate (unbiased) of `f(wo, wi) cos θi`, deterministic in the directions.
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.f(wo, wi) * wi.z
    }

    /// pbrt-v4's estimate of the density of [`Bsdf::sample`] (section 14.3.3): the entrance's
    /// reflection-only density, plus the paths that cross the coating, reflect once off the base
    /// and cross back (with MIS between sampling the base and the way out where both are rough),
    /// mixed with the uniform density on the sphere. It is an approximation, not the density of
    /// the walk: the crossing back out is estimated with a direction sampled from `wi`'s side, as
    /// though refraction's density were symmetric (it lacks the Jacobian of refraction and the
    /// Fresnel transmittance), and longer paths are left out; for a smooth coat over a
    /// Lambertian base it is `0.9 cos θt / π + 0.1 / (4π)`, which integrates to about 1.6 over
    /// the hemisphere. It only weights MIS, which stays unbiased for any density that is positive
    /// where the BSDF is and that [`Bsdf::sample`] reports for its samples.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let (top, base) = (&self.top, &self.base);
        let n = self.layer.samples as f32;
        let mut rng = Rng::new(hash(&[wi.x, wi.y, wi.z]), hash(&[wo.x, wo.y, wo.z]));
        let mut sum = n * top.pdf_reflection(wo, wi);
        for _ in 0..self.layer.samples {
            let wos = top.sample_transmission(wo, rng.vec2(), false);
            let wis = top.sample_transmission(wi, rng.vec2(), true);
            let (Some((wos, _)), Some((wis, _))) = (wos, wis) else {
                continue;
            };
            if top.is_specular() {
                sum += base.pdf(-wos.wi, -wis.wi);
                continue;
            }
            let uc = rng.uniform();
            let Some(rs) = base.sample(-wos.wi, uc, rng.vec2()) else {
                continue;
            };
            if rs.pdf == 0.0 || rs.weight == Vec3::ZERO {
                continue;
            }
            if base.is_specular() {
                sum += top.pdf(-rs.wi, wi);
            } else {
                let r_pdf = base.pdf(-wos.wi, -wis.wi);
                sum += power_heuristic(wis.pdf, r_pdf) * r_pdf;
                let t_pdf = top.pdf(-rs.wi, wi);
                sum += power_heuristic(rs.pdf, t_pdf) * t_pdf;
            }
        }
        let uniform = 1.0 / (4.0 * PI);
        0.1 * uniform + 0.9 * (sum / n)
    }

    /// One walk from `wo` until it leaves through the top. Its weight is the walk's throughput
    /// (an unbiased estimate of `f cos / pdf` in expectation); a smooth sample's `pdf` is
    /// [`Bsdf::pdf`]'s estimate, as pbrt-v4 uses for MIS (`pdfIsProportional`).
    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let Layer {
            thickness,
            albedo,
            g,
            max_depth,
            ..
        } = self.layer;
        let (top, base) = (&self.top, &self.base);
        let bs = top.sample(wo, u1, u2)?;
        if bs.wi.z > 0.0 {
            // Reflected at the entrance.
            if bs.lobe.is_delta() {
                return Some(bs);
            }
            let pdf = self.pdf(wo, bs.wi);
            return Some(BsdfSample {
                pdf,
                lobe: BsdfFlags::GLOSSY_REFLECTION,
                ..bs
            });
        }
        let mut specular_path = bs.lobe.is_delta();
        let mut beta = bs.weight;
        let mut delta_pdf = bs.pdf;
        let mut w = bs.wi;
        let mut z = thickness;
        let mut rng = Rng::new(hash(&[wo.x, wo.y, wo.z]), hash(&[u1, u2.x, u2.y]));
        for depth in 0..max_depth {
            if depth > 3 && beta.max_element() < 0.25 {
                let q = (1.0 - beta.max_element()).max(0.0);
                if rng.uniform() < q {
                    return None;
                }
                beta /= 1.0 - q;
                delta_pdf *= 1.0 - q;
            }
            if w.z == 0.0 {
                return None;
            }
            if albedo != Vec3::ZERO {
                let dz = -(1.0 - rng.uniform()).ln() * w.z.abs();
                let zp = if w.z > 0.0 { z + dz } else { z - dz };
                if zp == z {
                    return None;
                }
                if 0.0 < zp && zp < thickness {
                    let (wn, phase_pdf) = sample_hg(-w, g, rng.vec2());
                    if phase_pdf == 0.0 || wn.z == 0.0 {
                        return None;
                    }
                    beta *= albedo;
                    specular_path = false;
                    w = wn;
                    z = zp;
                    continue;
                }
                z = zp.clamp(0.0, thickness);
            } else {
                z = if z == thickness { 0.0 } else { thickness };
                beta *= tr(thickness, w);
            }
            let uc = rng.uniform();
            let s = if z == 0.0 {
                base.sample(-w, uc, rng.vec2())?
            } else {
                top.sample(-w, uc, rng.vec2())?
            };
            if s.weight == Vec3::ZERO || s.pdf == 0.0 || s.wi.z == 0.0 {
                return None;
            }
            beta *= s.weight;
            delta_pdf *= s.pdf;
            specular_path &= s.lobe.is_delta();
            w = s.wi;
            if z == thickness && w.z > 0.0 {
                // Left through the top.
                let (lobe, pdf) = if specular_path {
                    (BsdfFlags::DELTA_REFLECTION, delta_pdf)
                } else {
                    (self.smooth_lobe(), self.pdf(wo, w))
                };
                if pdf <= 0.0 || !pdf.is_finite() {
                    return None;
                }
                return Some(BsdfSample {
                    wi: w,
                    weight: beta,
                    pdf,
                    eta: 1.0,
                    lobe,
                });
            }
        }
        None
    }

    fn flags(&self) -> BsdfFlags {
        self.flags_of()
    }
}
