//! The kd-tree's leaves: triangles in blocks of eight (structure of arrays, one AVX2 register per
//! coordinate row) and a filter that runs the watertight test's edge functions (Woop, Benthin &
//! Wald 2013) on a whole block.
//!
//! The kd-tree's leaves are large (about 28 triangles on the meshes, since its SAH makes a triangle
//! a tenth of a traversal step), so its blocks are eight wide: one full-width load per row rather
//! than two half blocks joined (the BVH's `TriBlock` pairs), the ray's constants broadcast once per
//! ray instead of once per pair, and the filter inlined into the traversal. The filter computes,
//! lane by lane, exactly the floating-point operations of [`watertight`] in its order (no fused
//! multiply-adds), as the BVH's filter does, and rejects a lane only where that function would
//! certainly reject it: outside the triangle's closed edges with no edge function exactly zero
//! (which the scalar test re-evaluates in f64), or a `t` outside its loosened range. Surviving lanes
//! (nearly always hits, and primitives that are called back) are decided by [`watertight`] itself,
//! so a leaf reports exactly the hits that testing its triangles one by one reports.

use crate::accel::{test_primitive, Hit, Primitives, TraversalStats};
use crate::geometry::triangle::{watertight, watertight_filter_lane, watertight_shear};
use crate::geometry::PrimHit;
use crate::math::{Ray, Vec3};

/// Lanes per block.
pub const LANES: usize = 8;

/// Eight triangles (`v[3 * k + axis]` is coordinate `axis` of vertex `k`, one lane per triangle)
/// and their primitive ids. Lanes of primitives that are not watertight-tested triangles have NaN
/// vertices (every filter keeps them) and are called back; a leaf's last block repeats its lane 0
/// in its unused lanes, which traversal masks off by the leaf's primitive count.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug)]
pub struct KdBlock {
    pub v: [[f32; LANES]; 9],
    pub id: [u32; LANES],
}

const _: () = assert!(std::mem::size_of::<KdBlock>() == 320);

impl KdBlock {
    /// The block of up to eight primitives `ids`, asking `prims` for their vertices.
    pub fn gather<P: Primitives>(prims: &P, ids: &[u32]) -> Self {
        assert!(!ids.is_empty() && ids.len() <= LANES);
        let mut b = KdBlock {
            v: [[f32::NAN; LANES]; 9],
            id: [0; LANES],
        };
        for lane in 0..LANES {
            let id = ids[if lane < ids.len() { lane } else { 0 }];
            b.id[lane] = id;
            if let Some(tri) = prims.watertight_triangle(id as usize) {
                for (k, p) in tri.iter().enumerate() {
                    for a in 0..3 {
                        b.v[3 * k + a][lane] = p[a];
                    }
                }
            }
        }
        b
    }

    /// The triangle in `lane`, or `None` for a called-back primitive.
    #[inline(always)]
    pub fn triangle(&self, lane: usize) -> Option<[Vec3; 3]> {
        let v = |k: usize| {
            Vec3::new(
                self.v[3 * k][lane],
                self.v[3 * k + 1][lane],
                self.v[3 * k + 2][lane],
            )
        };
        let p0 = v(0);
        (!p0.x.is_nan()).then(|| [p0, v(1), v(2)])
    }
}

/// What the filter needs of a ray, computed once per ray: [`watertight`]'s permutation (`kz` the
/// axis of the largest direction component) and shear, with the same operations.
#[derive(Clone, Copy, Debug)]
pub struct LeafRay {
    k: [usize; 3],
    o: [f32; 3],
    s: [f32; 3],
}

impl LeafRay {
    #[inline(always)]
    pub fn new(ray: &Ray) -> Self {
        // A zero direction gives NaN shears: every lane survives the filter and the scalar test
        // rejects it, as it rejects such a ray.
        let (k, o, s) = watertight_shear(ray);
        Self { k, o, s }
    }

    /// Bit `i` is set if lane `i` of `b` may hit in `(0, t_max)`, one lane at a time: the portable
    /// filter.
    pub fn candidates_scalar(&self, b: &KdBlock, t_max: f32) -> u32 {
        let mut mask = 0;
        for lane in 0..LANES {
            let v = [0, 1, 2].map(|k| [0, 1, 2].map(|a| b.v[3 * k + a][lane]));
            let (kept, _) = watertight_filter_lane((self.k, self.o, self.s), v, t_max);
            mask |= (kept as u32) << lane;
        }
        mask
    }
}

/// The ray's constants broadcast to eight lanes, once per ray.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
pub struct LeafRay8 {
    k: [usize; 3],
    o: [std::arch::x86_64::__m256; 3],
    s: [std::arch::x86_64::__m256; 3],
}

#[cfg(target_arch = "x86_64")]
impl LeafRay8 {
    /// # Safety
    /// The CPU must have AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn new(r: &LeafRay) -> Self {
        use std::arch::x86_64::*;
        Self {
            k: r.k,
            o: r.o.map(|x| _mm256_set1_ps(x)),
            s: r.s.map(|x| _mm256_set1_ps(x)),
        }
    }

    /// [`LeafRay::candidates_scalar`] of a whole block in AVX2, with the same operations per lane.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn candidates(&self, b: &KdBlock, t_max: f32) -> u32 {
        use std::arch::x86_64::*;
        // `3 k + axis < 9`: `k` holds axes.
        let ld = |k: usize, a: usize| _mm256_load_ps(b.v.get_unchecked(3 * k + self.k[a]).as_ptr());
        let [ox, oy, oz] = self.o;
        let [sx, sy, sz] = self.s;
        // Translate to the ray origin, permute, shear (pbrt-v4 eq. 6.5 onwards).
        let vert = |k: usize| {
            let z = _mm256_sub_ps(ld(k, 2), oz);
            let x = _mm256_add_ps(_mm256_sub_ps(ld(k, 0), ox), _mm256_mul_ps(sx, z));
            let y = _mm256_add_ps(_mm256_sub_ps(ld(k, 1), oy), _mm256_mul_ps(sy, z));
            (x, y, z)
        };
        let (x0, y0, z0) = vert(0);
        let (x1, y1, z1) = vert(1);
        let (x2, y2, z2) = vert(2);
        let edge = |ax, ay, bx, by| _mm256_sub_ps(_mm256_mul_ps(ax, by), _mm256_mul_ps(ay, bx));
        let e0 = edge(x1, y1, x2, y2);
        let e1 = edge(x2, y2, x0, y0);
        let e2 = edge(x0, y0, x1, y1);
        let zero = _mm256_setzero_ps();
        let or3 = |a, b, c| _mm256_or_ps(_mm256_or_ps(a, b), c);
        let any_zero = or3(
            _mm256_cmp_ps::<_CMP_EQ_OQ>(e0, zero),
            _mm256_cmp_ps::<_CMP_EQ_OQ>(e1, zero),
            _mm256_cmp_ps::<_CMP_EQ_OQ>(e2, zero),
        );
        let any_neg = or3(
            _mm256_cmp_ps::<_CMP_LT_OQ>(e0, zero),
            _mm256_cmp_ps::<_CMP_LT_OQ>(e1, zero),
            _mm256_cmp_ps::<_CMP_LT_OQ>(e2, zero),
        );
        let any_pos = or3(
            _mm256_cmp_ps::<_CMP_GT_OQ>(e0, zero),
            _mm256_cmp_ps::<_CMP_GT_OQ>(e1, zero),
            _mm256_cmp_ps::<_CMP_GT_OQ>(e2, zero),
        );
        // Inside (or on an edge the scalar test re-evaluates): not both signs present.
        let outside = _mm256_andnot_ps(any_zero, _mm256_and_ps(any_neg, any_pos));
        // Most blocks a ray reaches miss it in every lane: stop before the distance test.
        if _mm256_movemask_ps(outside) == 0xff {
            return 0;
        }
        let det = _mm256_add_ps(_mm256_add_ps(e0, e1), e2);
        let (z0, z1, z2) = (
            _mm256_mul_ps(z0, sz),
            _mm256_mul_ps(z1, sz),
            _mm256_mul_ps(z2, sz),
        );
        let t_scaled = _mm256_add_ps(
            _mm256_add_ps(_mm256_mul_ps(e0, z0), _mm256_mul_ps(e1, z1)),
            _mm256_mul_ps(e2, z2),
        );
        let loose = _mm256_mul_ps(
            _mm256_mul_ps(_mm256_set1_ps(t_max), det),
            _mm256_set1_ps(1.0 + 4.0 * f32::EPSILON),
        );
        let neg = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_LT_OQ>(det, zero),
            _mm256_or_ps(
                _mm256_cmp_ps::<_CMP_GE_OQ>(t_scaled, zero),
                _mm256_cmp_ps::<_CMP_LT_OQ>(t_scaled, loose),
            ),
        );
        let pos = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(det, zero),
            _mm256_or_ps(
                _mm256_cmp_ps::<_CMP_LE_OQ>(t_scaled, zero),
                _mm256_cmp_ps::<_CMP_GT_OQ>(t_scaled, loose),
            ),
        );
        let reject_t = _mm256_or_ps(
            _mm256_or_ps(_mm256_cmp_ps::<_CMP_EQ_OQ>(det, zero), neg),
            pos,
        );
        let rejected = _mm256_or_ps(outside, _mm256_andnot_ps(any_zero, reject_t));
        !_mm256_movemask_ps(rejected) as u32 & 0xff
    }
}

/// Tests a leaf's blocks (`count` primitives), narrowing `t_max` and setting `best` at each nearer
/// hit; with `ANY`, returns at the first. `filter` gives a block's candidate lanes for the current
/// `t_max`; `seen` is asked about each candidate before it is decided (the traversal's mailbox: a
/// primitive copied into several leaves along the ray is decided once).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn test_leaf<P: Primitives, const ANY: bool>(
    blocks: &[KdBlock],
    count: usize,
    prims: &P,
    ray: &Ray,
    t_max: &mut f32,
    best: &mut Option<Hit>,
    stats: &mut TraversalStats,
    mut filter: impl FnMut(&KdBlock, f32) -> u32,
    mut seen: impl FnMut(u32) -> bool,
) {
    let Some((last, full)) = blocks.split_last() else {
        return;
    };
    // Returns whether an any-hit query is done.
    let mut decide = |b: &KdBlock, mut m: u32, t_max: &mut f32, best: &mut Option<Hit>| {
        while m != 0 {
            let lane = m.trailing_zeros() as usize;
            m &= m - 1;
            let id = b.id[lane];
            if seen(id) {
                continue;
            }
            let h: Option<PrimHit> = match b.triangle(lane) {
                Some([p0, p1, p2]) => watertight(ray, *t_max, p0, p1, p2),
                None => test_primitive::<P, ANY>(prims, id as usize, ray, *t_max, stats),
            };
            if let Some(h) = h {
                *best = Some(Hit::new(id as usize, h));
                if ANY {
                    return true;
                }
                *t_max = h.t;
            }
        }
        false
    };
    for b in full {
        let m = filter(b, *t_max);
        if m != 0 && decide(b, m, t_max, best) {
            return;
        }
    }
    // The last block's unused lanes repeat lane 0: skip them (a called-back primitive there
    // would be tested twice).
    let lanes = count - LANES * full.len();
    let m = filter(last, *t_max) & (u32::MAX >> (32 - lanes));
    decide(last, m, t_max, best);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(s: &mut u64) -> f32 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*s >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }

    struct Tris(Vec<[Vec3; 3]>);

    impl Primitives for Tris {
        fn count(&self) -> usize {
            self.0.len()
        }
        fn bounds(&self, i: usize) -> crate::math::Aabb {
            let [a, b, c] = self.0[i];
            crate::math::Aabb::new(a.min(b).min(c), a.max(b).max(c))
        }
        fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit> {
            let [a, b, c] = self.0[i];
            watertight(ray, t_max, a, b, c)
        }
        fn watertight_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
            Some(self.0[i])
        }
    }

    /// The filters never drop a lane the scalar test hits, the AVX2 and portable filters agree,
    /// and they reject most misses.
    #[test]
    fn filter_keeps_every_hit_and_rejects_most_misses() {
        let mut s = 11u64;
        let (mut hits, mut kept, mut total) = (0, 0, 0);
        for i in 0..20_000 {
            let p = |s: &mut u64| Vec3::new(lcg(s), lcg(s), lcg(s));
            let mut tris: Vec<[Vec3; 3]> =
                (0..8).map(|_| [p(&mut s), p(&mut s), p(&mut s)]).collect();
            // A degenerate triangle and two sharing an edge in some blocks.
            if i % 4 == 0 {
                tris[3] = [tris[3][0], tris[3][0], tris[3][1]];
                tris[5] = [tris[4][1], tris[4][0], p(&mut s)];
            }
            let dir = match i % 5 {
                0 => Vec3::X,
                1 => -Vec3::Z,
                _ => p(&mut s),
            };
            let origin = if i % 7 == 0 {
                tris[0][1] - dir
            } else {
                p(&mut s) * 2.0
            };
            let ray = Ray::new(origin, dir);
            let prims = Tris(tris.clone());
            let ids: Vec<u32> = (0..8).collect();
            let b = KdBlock::gather(&prims, &ids);
            let r = LeafRay::new(&ray);
            let t_max = if i % 3 == 0 { 1.5 } else { f32::INFINITY };
            let mask = r.candidates_scalar(&b, t_max);
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2.
                let m = unsafe { LeafRay8::new(&r).candidates(&b, t_max) };
                assert_eq!(m, mask, "ray {i}");
            }
            for (k, t) in tris.iter().enumerate() {
                // The degenerate lane has zero edge functions, which the filter always keeps
                // for the scalar test to decide: leave it out of the rejection count.
                if !(i % 4 == 0 && k == 3) {
                    total += 1;
                    kept += (mask >> k) & 1;
                }
                if watertight(&ray, t_max, t[0], t[1], t[2]).is_some() {
                    hits += 1;
                    assert!(
                        mask & (1 << k) != 0,
                        "ray {i} lane {k}: a hit was filtered out"
                    );
                }
            }
        }
        assert!(hits > 1000, "{hits}");
        assert!(
            kept < hits + total / 100,
            "kept {kept} of {total}, {hits} hits"
        );
    }

    #[test]
    fn padding_repeats_lane_zero_and_other_primitives_are_nan() {
        struct Two;
        impl Primitives for Two {
            fn count(&self) -> usize {
                10
            }
            fn bounds(&self, _: usize) -> crate::math::Aabb {
                crate::math::Aabb::new(Vec3::ZERO, Vec3::ONE)
            }
            fn intersect(&self, _: usize, _: &Ray, _: f32) -> Option<PrimHit> {
                None
            }
            fn watertight_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
                (i == 5).then_some([Vec3::ZERO, Vec3::X, Vec3::Y])
            }
        }
        let b = KdBlock::gather(&Two, &[5, 9]);
        assert_eq!(b.id, [5, 9, 5, 5, 5, 5, 5, 5]);
        assert!(b.triangle(0).is_some() && b.triangle(1).is_none() && b.triangle(7).is_some());
        let r = Ray::new(Vec3::new(0.2, 0.2, -1.0), Vec3::Z);
        // The called-back lane always survives; the triangle lanes hit.
        assert_eq!(LeafRay::new(&r).candidates_scalar(&b, f32::INFINITY), 0xff);
    }
}
