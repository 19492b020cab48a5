//! Rough plastic: a diffuse base under a rough dielectric coating, Mitsuba's `roughplastic`
//! (after Weidlich and Wilkie 2007). Light entering and leaving the coating is weighted by the
//! coating's rough transmittance `T(θ) = 1 - albedo of its microfacet reflection`, tabulated at
//! load time over `cos θ`; the base's internal reflections use the hemispherical average of the
//! internal microfacet reflection.

use super::fresnel::{fresnel_dielectric, reflect_about, refract_about};
use super::microfacet::{Microfacet, MicrofacetKind};
use super::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use super::{AnyBsdf, Phong, Bsdf, BsdfFlags, BsdfSample};
use crate::math::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;
use std::sync::{Mutex, OnceLock};
use super::{ior_ratio, texture_mean, BsdfMaterial, TextureSource};
use crate::error::{Error, Result};
use crate::description::RoughPlasticDesc;
use crate::shading::texture::{TexPoint, Texture};

/// Entries of the rough transmittance table over `cos θ ∈ [0, 1]` (Mitsuba's
/// `MI_ROUGH_TRANSMITTANCE_RES`).
pub const TRANSMITTANCE_RES: usize = 64;

type Table = [f32; TRANSMITTANCE_RES];

/// What a rough plastic material computes once at scene load from its constants. Small and
/// `Copy`: the table is shared, interned per distinct `(distribution, eta)` for the life of the
/// process (a few hundred bytes each; the same material loaded twice reuses its table).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughPlasticParams {
    /// Isotropic (Mitsuba's `roughplastic` refuses anisotropy).
    pub distribution: Microfacet,
    pub eta: f32,
    pub nonlinear: bool,
    pub specular_sampling_weight: f32,
    /// Hemispherical average of the coating's reflectance seen from inside.
    pub internal_reflectance: f32,
    /// Transmittance of the coating from outside, at `cos θ = i / (TRANSMITTANCE_RES - 1)`.
    pub external_transmittance: &'static Table,
    /// The coating [`Bsdf::regularized`] widens this one to; `None` where the rule leaves the
    /// roughness as it is.
    pub regularized_coating: Option<&'static CoatingTables>,
}

impl RoughPlasticParams {
    /// `distribution` must be isotropic (`alpha_v` is ignored); `eta` is the coating's interior
    /// IOR over the exterior's; the means are those of the reflectance textures, as for
    /// [`super::PlasticParams::precompute`]. Costs up to a few tens of milliseconds the first time
    /// a `(distribution, eta)` is seen (Gauss-Legendre quadrature of the coating's albedo, as
    /// Mitsuba computes it at load time), nothing after.
    pub fn precompute(
        distribution: Microfacet,
        eta: f32,
        nonlinear: bool,
        diffuse_mean: f32,
        specular_mean: f32,
    ) -> Self {
        let alpha = distribution.alpha_u.max(Microfacet::MIN_ALPHA);
        let distribution = Microfacet {
            alpha_v: alpha,
            alpha_u: alpha,
            ..distribution
        };
        let (external_transmittance, internal_reflectance) = tables(distribution.kind, alpha, eta);
        RoughPlasticParams {
            distribution,
            eta,
            nonlinear,
            specular_sampling_weight: specular_mean / (diffuse_mean + specular_mean),
            internal_reflectance,
            external_transmittance,
            regularized_coating: CoatingTables::of(distribution.kind, alpha, eta).regularized,
        }
    }
}

/// The transmittance table of one rough coating `(kind, alpha, eta)`, computed on first use:
/// what a material keeps for the coating of its regularized twin ([`Bsdf::regularized`]), which
/// a renderer may ask for at any hit, without paying the quadrature at load for the many
/// materials that are never regularized. Interned for the life of the process, like the tables
/// themselves, and linked to the coating it regularizes to in turn, so that building a
/// regularized BSDF at a hit takes no lock once the table exists (the first such hit computes
/// it, up to a few tens of milliseconds, while other threads needing it wait).
pub struct CoatingTables {
    /// Isotropic: `alpha_u` is the roughness.
    pub distribution: Microfacet,
    pub eta: f32,
    /// The coating of the regularized roughness, where it differs.
    pub regularized: Option<&'static CoatingTables>,
    tables: OnceLock<&'static Table>,
}

impl CoatingTables {
    /// The interned entry of `(kind, alpha, eta)` and of the chain of coatings regularization
    /// leads to from it (at most three: 0.1, 0.2, 0.3).
    pub fn of(kind: MicrofacetKind, alpha: f32, eta: f32) -> &'static CoatingTables {
        static ENTRIES: Mutex<Vec<&'static CoatingTables>> = Mutex::new(Vec::new());
        let mut entries = ENTRIES.lock().unwrap_or_else(|e| e.into_inner());
        Self::interned(&mut entries, kind, alpha, eta)
    }

    fn interned(
        entries: &mut Vec<&'static CoatingTables>,
        kind: MicrofacetKind,
        alpha: f32,
        eta: f32,
    ) -> &'static CoatingTables {
        let key = |c: &CoatingTables| {
            (c.distribution.kind, c.distribution.alpha_u.to_bits(), c.eta.to_bits())
        };
        let distribution = Microfacet::isotropic(kind, alpha, true);
        let wanted = (kind, distribution.alpha_u.to_bits(), eta.to_bits());
        if let Some(&c) = entries.iter().find(|c| key(c) == wanted) {
            return c;
        }
        let widened = distribution.regularized();
        let regularized = (widened != distribution)
            .then(|| Self::interned(entries, kind, widened.alpha_u, eta));
        let entry: &'static CoatingTables = Box::leak(Box::new(CoatingTables {
            distribution,
            eta,
            regularized,
            tables: OnceLock::new(),
        }));
        entries.push(entry);
        entry
    }

    /// The coating's transmittance from outside, as [`RoughPlasticParams::precompute`] tabulates
    /// it.
    pub fn external_transmittance(&self) -> &'static Table {
        self.tables.get_or_init(|| {
            tables(self.distribution.kind, self.distribution.alpha_u, self.eta).0
        })
    }

    /// A rough plastic under this coating, the rest as given. `internal_reflectance` is the
    /// regularized plastic's own: regularization widens the coating's lobe, through which the
    /// base is seen, but should not change how bright the diffuse base is. (Mitsuba's estimate of
    /// it at roughness 0.1 and index 1.5, 0.55 against the smooth coating's exact 0.60, would
    /// darken a regularized plastic's diffuse light by a tenth.)
    pub(crate) fn rough_plastic(
        &self,
        sample_visible: bool,
        nonlinear: bool,
        specular_sampling_weight: f32,
        internal_reflectance: f32,
        diffuse_reflectance: Vec3,
        specular_reflectance: Vec3,
    ) -> RoughPlastic {
        let external_transmittance = self.external_transmittance();
        RoughPlastic {
            distribution: Microfacet {
                sample_visible,
                ..self.distribution
            },
            eta: self.eta,
            nonlinear,
            specular_sampling_weight,
            internal_reflectance,
            external_transmittance,
            regularized_coating: self.regularized,
            diffuse_reflectance,
            specular_reflectance,
        }
    }
}

/// The coating's parameters (not its tables, nor the chain).
impl std::fmt::Debug for CoatingTables {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CoatingTables")
            .field("kind", &self.distribution.kind)
            .field("alpha", &self.distribution.alpha_u)
            .field("eta", &self.eta)
            .finish()
    }
}

/// Interned: the same entry is the same coating.
impl PartialEq for CoatingTables {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self, other)
    }
}

/// The tables of `(kind, alpha, eta)`, computed once.
fn tables(kind: MicrofacetKind, alpha: f32, eta: f32) -> (&'static Table, f32) {
    type Entry = ((MicrofacetKind, u32, u32), &'static Table, f32);
    static CACHE: Mutex<Vec<Entry>> = Mutex::new(Vec::new());
    let key = (kind, alpha.to_bits(), eta.to_bits());
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(&(_, t, r)) = cache.iter().find(|(k, _, _)| *k == key) {
        return (t, r);
    }
    let dist = Microfacet::isotropic(kind, alpha, true);
    let mus = (0..TRANSMITTANCE_RES)
        .map(|i| (i as f32 / (TRANSMITTANCE_RES - 1) as f32).max(1e-6))
        .collect::<Vec<_>>();
    let mut table = [0.0; TRANSMITTANCE_RES];
    let mut internal = 0.0f64;
    for (t, &mu) in table.iter_mut().zip(&mus) {
        let w = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        *t = transmittance(&dist, w, eta);
        internal += (reflectance(&dist, w, 1.0 / eta) * mu) as f64;
    }
    // 2 ∫ R(μ) μ dμ by the mean over the table's nodes, as Mitsuba takes it.
    let internal = (2.0 * internal / TRANSMITTANCE_RES as f64) as f32;
    let table: &'static Table = Box::leak(Box::new(table));
    cache.push((key, table, internal));
    (table, internal)
}

/// Gauss-Legendre nodes and weights on [-1, 1] (roots of the Legendre polynomial by Newton's
/// method from Chebyshev guesses; Press et al., "Numerical Recipes", 4.6).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = vec![(0.0, 0.0); n];
    for i in 0..n.div_ceil(2) {
        let mut x = -(std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(x) and its derivative by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let p = if n == 0 { 1.0 } else { p1 };
            let pm1 = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (x * p - pm1) / (x * x - 1.0);
            let step = p / dp;
            x -= step;
            if step.abs() <= 4.0 * x.abs() * f64::EPSILON {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out[i] = (x, w);
        out[n - 1 - i] = (-x, w);
    }
    out
}

/// Quadrature points `(u, weight)` over the unit square: the product Gauss-Legendre rule of
/// Mitsuba's `eval_reflectance` and `eval_transmittance`, 32² nodes toward a denser medium and
/// 128² toward a lighter one, whose total internal reflection makes the integrand rougher.
fn square_rule(eta: f32) -> Vec<(Vec2, f32)> {
    let nodes = gauss_legendre(if eta > 1.0 { 32 } else { 128 });
    let mut out = Vec::with_capacity(nodes.len() * nodes.len());
    for &(y, wy) in &nodes {
        for &(x, wx) in &nodes {
            let u = Vec2::new((x * 0.5 + 0.5) as f32, (y * 0.5 + 0.5) as f32);
            out.push((u, (wx * wy * 0.25) as f32));
        }
    }
    out
}

/// Albedo of the microfacet reflection of a dielectric interface for direction `w` (outside,
/// relative IOR `eta`): the visible-normal estimate `∫ F(w·m) G1(wi, m) dP(m)`.
fn reflectance(dist: &Microfacet, w: Vec3, eta: f32) -> f32 {
    let mut sum = 0.0f64;
    for (u, weight) in square_rule(eta) {
        let m = dist.sample(w, u).0;
        let wi = reflect_about(w, m);
        if wi.z <= 0.0 || w.z <= 0.0 {
            continue;
        }
        let f = fresnel_dielectric(w.dot(m), eta).0;
        sum += (dist.smith_g1(wi, m) * f * weight) as f64;
    }
    sum as f32
}

/// Albedo of the microfacet refraction through a dielectric interface for direction `w`.
fn transmittance(dist: &Microfacet, w: Vec3, eta: f32) -> f32 {
    let mut sum = 0.0f64;
    for (u, weight) in square_rule(eta) {
        let m = dist.sample(w, u).0;
        let (f, cos_t, _, eta_ti) = fresnel_dielectric(w.dot(m), eta);
        let wi = refract_about(w, m, cos_t, eta_ti);
        if wi.z * w.z >= 0.0 {
            continue;
        }
        sum += (dist.smith_g1(wi, m) * (1.0 - f) * weight) as f64;
    }
    sum as f32
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughPlastic {
    pub distribution: Microfacet,
    pub eta: f32,
    pub nonlinear: bool,
    pub specular_sampling_weight: f32,
    pub internal_reflectance: f32,
    pub external_transmittance: &'static Table,
    /// See [`RoughPlasticParams::regularized_coating`].
    pub regularized_coating: Option<&'static CoatingTables>,
    pub diffuse_reflectance: Vec3,
    pub specular_reflectance: Vec3,
}

impl RoughPlastic {
    pub fn new(
        params: &RoughPlasticParams,
        diffuse_reflectance: Vec3,
        specular_reflectance: Vec3,
    ) -> Self {
        RoughPlastic {
            distribution: params.distribution,
            eta: params.eta,
            nonlinear: params.nonlinear,
            specular_sampling_weight: params.specular_sampling_weight,
            internal_reflectance: params.internal_reflectance,
            external_transmittance: params.external_transmittance,
            regularized_coating: params.regularized_coating,
            diffuse_reflectance,
            specular_reflectance,
        }
    }

    /// The table linearly interpolated at `cos_theta` in [0, 1].
    #[inline]
    fn transmittance(&self, cos_theta: f32) -> f32 {
        let x = cos_theta * (TRANSMITTANCE_RES - 1) as f32;
        let i = (x as usize).min(TRANSMITTANCE_RES - 2);
        let (v0, v1) = (
            self.external_transmittance[i],
            self.external_transmittance[i + 1],
        );
        v0 + (x - i as f32) * (v1 - v0)
    }

    #[inline]
    fn prob_specular(&self, t_o: f32) -> f32 {
        let s = (1.0 - t_o) * self.specular_sampling_weight;
        let d = t_o * (1.0 - self.specular_sampling_weight);
        s / (s + d)
    }

    #[inline]
    fn value(&self, wo: Vec3, wi: Vec3, h: Vec3, d: f32, g: f32, t_o: f32) -> Vec3 {
        let f = fresnel_dielectric(wo.dot(h), self.eta).0;
        let specular = self.specular_reflectance * (f * d * g / (4.0 * wo.z));
        let t_i = self.transmittance(wi.z);
        let base = self.diffuse_reflectance;
        let base = if self.nonlinear {
            base / (Vec3::ONE - base * self.internal_reflectance)
        } else {
            base / (1.0 - self.internal_reflectance)
        };
        specular + base * (FRAC_1_PI / (self.eta * self.eta) * wi.z * t_o * t_i)
    }

    #[inline]
    fn density(&self, wo: Vec3, wi: Vec3, h: Vec3, d: f32, g1_o: f32, t_o: f32) -> f32 {
        let dist = &self.distribution;
        let specular = if dist.sample_visible {
            d * g1_o / (4.0 * wo.z)
        } else {
            dist.pdf(wo, h) / (4.0 * wi.dot(h))
        };
        let p = self.prob_specular(t_o);
        p * specular + (1.0 - p) * square_to_cosine_hemisphere_pdf(wi)
    }
}

impl Bsdf for RoughPlastic {
    /// The diffuse base with the rough coating as a broad highlight.
    fn whitted(&self) -> Phong {
        Phong::coated(self.diffuse_reflectance, 30.0)
    }

    /// The coating's microfacet reflection plus the diffuse base seen through it.
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.eval_pdf(wo, wi).0
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = (wo + wi).normalize();
        let dist = &self.distribution;
        let t_o = self.transmittance(wo.z);
        self.density(wo, wi, h, dist.d(h), dist.smith_g1(wo, h), t_o)
    }

    #[inline]
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let h = (wo + wi).normalize();
        let dist = &self.distribution;
        let d = dist.d(h);
        let g1_o = dist.smith_g1(wo, h);
        let t_o = self.transmittance(wo.z);
        let value = self.value(wo, wi, h, d, g1_o * dist.smith_g1(wi, h), t_o);
        (value, self.density(wo, wi, h, d, g1_o, t_o))
    }

    /// The specular lobe with probability `(1 - T(θo)) w / ((1 - T(θo)) w + T(θo) (1 - w))`,
    /// `w` the sampling weight, else the cosine-weighted base; the weight is the whole BSDF over
    /// the mixture's density, as in Mitsuba.
    fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let t_o = self.transmittance(wo.z);
        let specular = u1 < self.prob_specular(t_o);
        let (wi, lobe) = if specular {
            let m = self.distribution.sample(wo, u2).0;
            (reflect_about(wo, m), BsdfFlags::GLOSSY_REFLECTION)
        } else {
            (
                square_to_cosine_hemisphere(u2),
                BsdfFlags::DIFFUSE_REFLECTION,
            )
        };
        let (value, pdf) = self.eval_pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: value / pdf,
            pdf,
            eta: 1.0,
            lobe,
        })
    }

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::DIFFUSE_REFLECTION
    }

    /// The coating widened by pbrt-v4's rule ([`Microfacet::regularized`]), with the
    /// transmittance of the wider coating and the base's internal reflectance kept (see
    /// [`CoatingTables::rough_plastic`]); unchanged from roughness 0.3 on.
    fn regularized(&self) -> AnyBsdf {
        AnyBsdf::RoughPlastic(match self.regularized_coating {
            None => *self,
            Some(c) => c.rough_plastic(
                self.distribution.sample_visible,
                self.nonlinear,
                self.specular_sampling_weight,
                self.internal_reflectance,
                self.diffuse_reflectance,
                self.specular_reflectance,
            ),
        })
    }
}

/// [`RoughPlastic`] with its reflectances textured and its coating's albedo precomputed.
#[derive(Clone, Debug)]
pub struct RoughPlasticMaterial {
    pub params: RoughPlasticParams,
    pub diffuse: Texture,
    pub specular: Texture,
}

impl BsdfMaterial for RoughPlasticMaterial {
    type Desc = RoughPlasticDesc;
    type Bsdf = RoughPlastic;

    fn build(d: &RoughPlasticDesc, textures: &mut dyn TextureSource) -> Result<Self> {
        let diffuse = textures.texture(&d.diffuse_reflectance)?;
        let specular = textures.texture(&d.specular_reflectance)?;
        let alpha = d.constant_alpha().map_err(|e| Error::Invalid(e.message))?;
        let distribution = Microfacet::new(d.distribution.into(), alpha, alpha, d.sample_visible);
        Ok(RoughPlasticMaterial {
            params: RoughPlasticParams::precompute(
                distribution,
                ior_ratio(&d.int_ior, &d.ext_ior)?,
                d.nonlinear,
                texture_mean(&diffuse),
                texture_mean(&specular),
            ),
            diffuse,
            specular,
        })
    }

    #[inline]
    fn at(&self, p: &TexPoint) -> RoughPlastic {
        RoughPlastic::new(&self.params, self.diffuse.eval_at(p), self.specular.eval_at(p))
    }
}
