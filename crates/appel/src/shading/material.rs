//! Materials of the Monte Carlo integrators: a BSDF's textured parameters, resolved at a surface
//! point into a BSDF of plain values ([`AnyBsdf`]) (pbrt-v4's Material -> BSDF split). What depends only on
//! constants (the plastics' precomputed albedos) is computed once, at scene load.

use super::bsdf::{AnyBsdf, BsdfFlags, BsdfMaterial, BsdfSample, Diffuse, Phong, TextureSource};
pub use super::bsdf::{PrincipledTextures, PrincipledThinTextures, Roughness};
use super::frame::ShadingFrame;
use super::perturb::{normal_from_bump, normal_from_map, Perturbation};
use super::texture::{AttributePoint, TexPoint, Texture};
use crate::description::{for_each_bsdf, MaterialDesc};
use crate::error::Result;
use crate::math::{Vec2, Vec3};

macro_rules! define_material {
    ($($(#[$attr:meta])* $Variant:ident($module:ident: $Desc:ident => $Bsdf:ident, $Material:ident)),* $(,)?) => {
        use super::bsdf::{$($Material,)*};

        /// A material of the Monte Carlo integrators: one of the BSDFs with its textures, or a
        /// wrapper around others (see [`crate::description::MaterialDesc`] for why the
        /// wrappers are not BSDFs of the registry).
        #[derive(Clone, Debug)]
        pub enum Material {
            $($Variant($Material),)*
            /// One-sided materials seen from both sides: `front` from the front, `back` from
            /// behind (both indices into the scene's materials).
            TwoSided {
                front: u32,
                back: u32,
            },
            /// The surface is present with probability `opacity` (Mitsuba's `mask`), as `inner`.
            Mask {
                opacity: Texture,
                inner: u32,
            },
            /// `inner` around the normal a tangent-space normal map gives (Mitsuba's
            /// `normalmap`).
            NormalMap {
                normals: Texture,
                inner: u32,
                flip_invalid: bool,
                shadowing: bool,
            },
            /// `first` and `second` mixed as `(1 - weight) first + weight second` (Mitsuba's
            /// `blendbsdf`); both are plain BSDFs, not wrappers.
            Blend {
                weight: Texture,
                first: u32,
                second: u32,
            },
            /// `inner` around the normal of a height field scaled by `scale` (Mitsuba's
            /// `bumpmap`).
            BumpMap {
                height: Texture,
                scale: f32,
                inner: u32,
                flip_invalid: bool,
                shadowing: bool,
            },
        }

        impl Material {
            /// The material of a described BSDF, its textures from `textures`; `None` for the
            /// wrappers, which the scene resolves itself.
            pub fn from_bsdf_desc(
                d: &MaterialDesc,
                textures: &mut dyn TextureSource,
            ) -> Option<Result<Material>> {
                Some(match d {
                    $(MaterialDesc::$Variant(x) => {
                        <$Material as BsdfMaterial>::build(x, textures).map(Material::$Variant)
                    })*
                    _ => return None,
                })
            }

            fn leaf_bsdf(&self, tp: &TexPoint) -> AnyBsdf {
                match self {
                    $(Material::$Variant(m) => AnyBsdf::$Variant(m.at(tp)),)*
                    // Resolved by `bsdf`; reached only past the nesting bound, as black.
                    Material::TwoSided { .. }
                    | Material::Mask { .. }
                    | Material::NormalMap { .. }
                    | Material::BumpMap { .. }
                    | Material::Blend { .. } => AnyBsdf::Diffuse(Diffuse::new(Vec3::ZERO)),
                }
            }
        }
    };
}
for_each_bsdf!(define_material);

/// What a material needs to know of the surface point, in the coordinates of its shading frame
/// (`z` = shading normal, `x` along dp/du).
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint<'a> {
    pub uv: Vec2,
    /// The mesh attributes at the point, where the surface has them.
    pub attributes: Option<AttributePoint<'a>>,
    /// Toward the viewer (or the previous path vertex).
    pub wo: Vec3,
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    /// The geometric normal.
    pub n: Vec3,
    /// +1 or -1: a normal map's y runs along this times `z × x` (see
    /// [`SurfaceInteraction::bitangent_sign`](crate::geometry::SurfaceInteraction::bitangent_sign)).
    pub bitangent_sign: f32,
}

impl<'a> SurfacePoint<'a> {
    /// The point `si` with its directions in `frame`, seen from world direction `wo`.
    pub fn new(
        si: &crate::geometry::SurfaceInteraction,
        frame: &ShadingFrame,
        wo: Vec3,
        attributes: Option<AttributePoint<'a>>,
    ) -> Self {
        SurfacePoint {
            uv: si.uv,
            attributes,
            wo: frame.to_local(wo),
            dpdu: frame.to_local(si.dpdu),
            dpdv: frame.to_local(si.dpdv),
            n: frame.to_local(si.n),
            bitangent_sign: si.bitangent_sign(),
        }
    }
}

/// The BSDF at a surface point with the wrappers around it resolved: a two-sided material seen
/// from behind mirrors directions through the surface (`flip_outer`, or `flip_inner` inside a
/// normal or bump map), a normal or bump map turns them into its perturbed frame. Directions in
/// and out are in the surface's shading frame.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceBsdf {
    pub bsdf: AnyBsdf,
    /// A blend: the second BSDF and its weight (`bsdf` is the first).
    blend: Option<(AnyBsdf, f32)>,
    flip_outer: bool,
    perturbation: Option<Perturbation>,
    flip_inner: bool,
}

/// The largest f32 below 1: a rescaled random number stays in [0, 1).
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[inline]
fn flip_if(flip: bool, mut w: Vec3) -> Vec3 {
    if flip {
        w.z = -w.z;
    }
    w
}

impl SurfaceBsdf {
    /// A BSDF with no wrapper.
    pub fn plain(bsdf: AnyBsdf) -> Self {
        SurfaceBsdf {
            bsdf,
            blend: None,
            flip_outer: false,
            perturbation: None,
            flip_inner: false,
        }
    }

    /// The BSDF with every leaf regularized ([`AnyBsdf::regularized`], pbrt-v4's
    /// `BSDF::Regularize`): both BSDFs of a blend, its weight, the two-sided flips and a normal
    /// or bump map's frame kept.
    pub fn regularized(&self) -> SurfaceBsdf {
        SurfaceBsdf {
            bsdf: self.bsdf.regularized(),
            blend: self.blend.map(|(second, w)| (second.regularized(), w)),
            ..*self
        }
    }

    pub fn flags(&self) -> BsdfFlags {
        match &self.blend {
            Some((second, _)) => self.bsdf.flags() | second.flags(),
            None => self.bsdf.flags(),
        }
    }

    /// The BSDF, or the blend of two, in its own frame.
    fn leaf_eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let (f, pdf) = self.bsdf.eval_pdf(wo, wi);
        match &self.blend {
            None => (f, pdf),
            Some((second, w)) => {
                let (f2, pdf2) = second.eval_pdf(wo, wi);
                (f * (1.0 - w) + f2 * *w, pdf * (1.0 - w) + pdf2 * w)
            }
        }
    }

    /// A blend samples one of its BSDFs, the second with probability `weight`, and keeps that
    /// one's weight (`f_i / pdf_i`: its expectation over the choice is the blend's value), as
    /// Mitsuba's `blendbsdf` does. Unlike Mitsuba, a smooth sample reports the blend's density,
    /// so that the MIS weight of an emitter it hits matches the density emitter sampling uses.
    fn leaf_sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        let Some((second, w)) = &self.blend else {
            return self.bsdf.sample(wo, u1, u2);
        };
        let (chosen, other, u1, p_other) = if u1 > *w {
            (&self.bsdf, second, (u1 - w) / (1.0 - w), *w)
        } else {
            (second, &self.bsdf, u1 / w, 1.0 - w)
        };
        let mut s = chosen.sample(wo, u1.min(ONE_MINUS_EPSILON), u2)?;
        if !s.lobe.is_delta() {
            s.pdf = (1.0 - p_other) * s.pdf + p_other * other.pdf(wo, s.wi);
        }
        Some(s)
    }

    /// [`AnyBsdf::null_transmission`] through the wrappers: a blend's is the blend of its two
    /// (the straight-through direction is the same in any frame).
    pub fn null_transmission(&self, wo: Vec3) -> Vec3 {
        let wo = flip_if(self.flip_outer, wo);
        let first = self.bsdf.null_transmission(wo);
        match &self.blend {
            None => first,
            Some((second, w)) => first * (1.0 - w) + second.null_transmission(wo) * *w,
        }
    }

    /// [`AnyBsdf::eval_pdf`] through the wrappers. A perturbed frame gives nothing where `wi` lies on
    /// different sides of the two frames' surfaces, and its value (not its pdf) carries the
    /// terminator shadowing.
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let (wo, wi) = (flip_if(self.flip_outer, wo), flip_if(self.flip_outer, wi));
        let Some(p) = &self.perturbation else {
            return self.leaf_eval_pdf(wo, wi);
        };
        let (pwo, pwi) = (p.frame.to_local(wo), p.frame.to_local(wi));
        if wi.z * pwi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let (pwo, pwi) = (flip_if(self.flip_inner, pwo), flip_if(self.flip_inner, pwi));
        let (f, pdf) = self.leaf_eval_pdf(pwo, pwi);
        (f * p.attenuation(wi), pdf)
    }

    /// [`AnyBsdf::sample`] through the wrappers; `None` also where a perturbed frame rejects the
    /// direction.
    pub fn sample(&self, wo: Vec3, u1: f32, u2: Vec2) -> Option<BsdfSample> {
        let wo = flip_if(self.flip_outer, wo);
        let Some(p) = &self.perturbation else {
            let mut s = self.leaf_sample(wo, u1, u2)?;
            s.wi = flip_if(self.flip_outer, s.wi);
            return Some(s);
        };
        let pwo = flip_if(self.flip_inner, p.frame.to_local(wo));
        let mut s = self.leaf_sample(pwo, u1, u2)?;
        let pwi = flip_if(self.flip_inner, s.wi);
        let wi = p.frame.to_world(pwi);
        if wi.z * pwi.z <= 0.0 {
            return None;
        }
        s.weight *= p.attenuation(wi);
        s.wi = flip_if(self.flip_outer, wi);
        Some(s)
    }
}

/// How deep two-sided and mask materials may nest (validation rejects cycles; this bounds the
/// walk regardless).
const MAX_NESTING: u32 = 16;

impl Material {
    /// The BSDF of material `index` of `materials` at surface point `at`. Masks are not resolved
    /// here: see [`Self::opacity`].
    pub fn bsdf(materials: &[Material], index: u32, at: &SurfacePoint) -> SurfaceBsdf {
        let tp = TexPoint {
            uv: at.uv,
            attributes: at.attributes,
        };
        let mut m = &materials[index as usize];
        let mut out = SurfaceBsdf::plain(AnyBsdf::Diffuse(Diffuse::new(Vec3::ZERO)));
        // `wo` as the wrapper being resolved sees it.
        let mut wo = at.wo;
        for _ in 0..MAX_NESTING {
            match m {
                Material::TwoSided { front, back } => {
                    // Mitsuba's twosided: below the surface, the back material with directions
                    // mirrored.
                    if wo.z < 0.0 {
                        if out.perturbation.is_some() {
                            out.flip_inner = !out.flip_inner;
                        } else {
                            out.flip_outer = !out.flip_outer;
                        }
                        wo.z = -wo.z;
                        m = &materials[*back as usize];
                    } else {
                        m = &materials[*front as usize];
                    }
                }
                Material::Mask { inner, .. } => m = &materials[*inner as usize],
                // Validation allows one map in a chain; a second would be passed through.
                Material::NormalMap { inner, .. } | Material::BumpMap { inner, .. }
                    if out.perturbation.is_some() =>
                {
                    m = &materials[*inner as usize]
                }
                Material::NormalMap {
                    normals,
                    inner,
                    flip_invalid,
                    shadowing,
                } => {
                    // The map's normal is relative to the unmirrored shading frame, as Mitsuba's
                    // adapter reads it from the surface interaction a two-sided BSDF leaves as it
                    // is (only the directions are mirrored).
                    let mut n = normal_from_map(normals.eval_at(&tp));
                    n.y *= at.bitangent_sign;
                    let p = Perturbation::new(n, wo, *flip_invalid, *shadowing);
                    wo = p.frame.to_local(wo);
                    out.perturbation = Some(p);
                    m = &materials[*inner as usize];
                }
                Material::BumpMap {
                    height,
                    scale,
                    inner,
                    flip_invalid,
                    shadowing,
                } => {
                    let grad = *scale * height.eval_1_grad(at.uv);
                    let n = normal_from_bump(grad, at.dpdu, at.dpdv, at.n);
                    let p = Perturbation::new(n, wo, *flip_invalid, *shadowing);
                    wo = p.frame.to_local(wo);
                    out.perturbation = Some(p);
                    m = &materials[*inner as usize];
                }
                Material::Blend {
                    weight,
                    first,
                    second,
                } => {
                    // Validation keeps blends' components plain BSDFs.
                    let w = weight.eval_1_at(&tp).clamp(0.0, 1.0);
                    out.bsdf = materials[*first as usize].leaf_bsdf(&tp);
                    out.blend = Some((materials[*second as usize].leaf_bsdf(&tp), w));
                    return out;
                }
                _ => break,
            }
        }
        out.bsdf = m.leaf_bsdf(&tp);
        out
    }

    /// The probability that the surface is there at `uv` (1 unless a mask wraps the material).
    pub fn opacity(materials: &[Material], index: u32, uv: Vec2) -> f32 {
        match &materials[index as usize] {
            Material::Mask { opacity, .. } => opacity.eval_1(uv).clamp(0.0, 1.0),
            _ => 1.0,
        }
    }

    pub fn has_mask(&self) -> bool {
        matches!(self, Material::Mask { .. })
    }

    /// Whether the material reads texture coordinates: surfaces may skip computing them
    /// otherwise (a `phong` material without a checkerboard, as most of Whitted's are).
    #[inline(always)]
    pub fn needs_uv(&self) -> bool {
        match self {
            Material::Phong(p) => p.needs_uv(),
            _ => true,
        }
    }

    /// What the `whitted` and `raycast` integrators read of material `index` at `uv`: its Phong
    /// lobes and its albedo at the point. A `phong` material's lobes are borrowed from the
    /// material itself (only its colour varies over the surface), so that the shading reads them
    /// in place instead of from a copy made at every hit; any other BSDF's
    /// [`super::bsdf::Bsdf::whitted`] response is evaluated into `other`, which the lobes then
    /// borrow. `attributes` (asked only for the latter) are the mesh attributes of the point.
    #[inline(always)]
    pub fn whitted<'a>(
        materials: &'a [Material],
        index: u32,
        uv: Vec2,
        attributes: impl FnOnce() -> Option<AttributePoint<'a>>,
        other: &'a mut Option<Phong>,
    ) -> (&'a Phong, Vec3) {
        match &materials[index as usize] {
            Material::Phong(p) => (&p.base, p.albedo(uv)),
            _ => {
                let m = other.insert(Self::whitted_of_bsdf(
                    materials,
                    index,
                    &TexPoint {
                        uv,
                        attributes: attributes(),
                    },
                ));
                (m, m.albedo)
            }
        }
    }

    /// [`Self::whitted`] of a material other than `phong`, out of line. Whitted's surfaces are
    /// two-sided and are not cut out, and its rays follow the geometric surface: a two-sided
    /// material is seen as its front, a mask or a normal or bump map as the material inside it, a
    /// blend as its first BSDF.
    #[inline(never)]
    fn whitted_of_bsdf(materials: &[Material], index: u32, tp: &TexPoint) -> Phong {
        let mut m = &materials[index as usize];
        for _ in 0..MAX_NESTING {
            m = match m {
                Material::TwoSided { front, .. } => &materials[*front as usize],
                Material::Mask { inner, .. }
                | Material::NormalMap { inner, .. }
                | Material::BumpMap { inner, .. } => &materials[*inner as usize],
                Material::Blend { first, .. } => &materials[*first as usize],
                _ => break,
            };
        }
        m.leaf_bsdf(tp).whitted()
    }
}

#[cfg(test)]
#[path = "material_tests.rs"]
mod tests;
