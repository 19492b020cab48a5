//! What the BVH builder moves around: a primitive's box and centroid in SIMD registers.
//!
//! The build spends its time taking unions of boxes (binning) and classifying centroids
//! (partitioning), once per primitive per tree level. `glam::Vec4` keeps each corner in one SSE
//! register, so a union is one `minps` and one `maxps`, where `Aabb`'s scalar, NaN-aware `f32::min`
//! needs a compare and a select per lane.
//! Primitive bounds are finite: the loaders and the scene validator reject NaN and infinite
//! coordinates, and unbounded shapes never reach a structure.

use crate::math::Aabb;
use glam::Vec4;

/// A box whose `w` lanes carry no geometry.
#[derive(Clone, Copy, Debug)]
pub(super) struct Box4 {
    pub lo: Vec4,
    pub hi: Vec4,
}

impl Box4 {
    pub const EMPTY: Box4 = Box4 {
        lo: Vec4::splat(f32::INFINITY),
        hi: Vec4::splat(f32::NEG_INFINITY),
    };

    #[inline(always)]
    pub fn union(self, o: Box4) -> Box4 {
        Box4 {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    #[inline(always)]
    pub fn include(self, p: Vec4) -> Box4 {
        Box4 {
            lo: self.lo.min(p),
            hi: self.hi.max(p),
        }
    }

    /// Surface area; 0 for an empty box.
    #[inline(always)]
    pub fn area(self) -> f32 {
        // `lo.w` may hold a subnormal id (see `BuildPrim::centroid`): clear it before subtracting.
        let d = (self.hi - xyz0(self.lo)).max(Vec4::ZERO);
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    pub fn to_aabb(self) -> Aabb {
        Aabb::new(self.lo.truncate(), self.hi.truncate())
    }
}

/// A primitive as the builder sees it (32 bytes): its bounds, with its id in the `w` lane of the
/// lower corner (as bits, never used as a number). The builder splits by the centre of the bounds,
/// as Embree does; keeping no separate centroid saves a third of the build's working memory and
/// of the bytes every pass streams through.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BuildPrim {
    pub bounds: Box4,
}

impl BuildPrim {
    pub fn new(bounds: Aabb, id: u32) -> Self {
        Self {
            bounds: Box4 {
                lo: bounds.min.extend(f32::from_bits(id)),
                hi: bounds.max.extend(0.0),
            },
        }
    }

    #[inline]
    pub fn id(&self) -> u32 {
        self.bounds.lo.w.to_bits()
    }

    /// The centre of the bounds, with `w` zero.
    ///
    /// The id in `lo.w` is, as a float, usually a subnormal number: an addition with a subnormal
    /// operand takes a microcode assist of about a hundred cycles on x86 CPUs, so the lane is
    /// cleared bitwise first. (Before, this one addition was half the build's time.)
    #[inline(always)]
    pub fn centroid(&self) -> Vec4 {
        (xyz0(self.bounds.lo) + self.bounds.hi) * 0.5
    }
}

/// `v` with its `w` lane cleared bitwise (never read as a number first). On x86_64 one `andps`
/// with a mask held in a register: `truncate().extend(0.0)` goes through a scalar `Vec3` and
/// rebuilds the vector lane by lane, and this runs once per primitive at every level of the build.
#[inline(always)]
pub(super) fn xyz0(v: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128, _mm_castsi128_ps, _mm_set_epi32};
        // SAFETY: SSE2 is part of x86_64; `andps` reads and writes registers only.
        unsafe {
            let mask = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
            let mut r: __m128 = v.into();
            // In assembly, because LLVM turns `_mm_and_ps` with this mask into a shuffle with a
            // zeroed register, four instructions instead of one in the binning loop.
            std::arch::asm!(
                "andps {r}, {m}",
                r = inout(xmm_reg) r,
                m = in(xmm_reg) mask,
                options(pure, nomem, nostack, preserves_flags)
            );
            r.into()
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        v.with_w(0.0)
    }
}

const _: () = assert!(std::mem::size_of::<BuildPrim>() == 32);
