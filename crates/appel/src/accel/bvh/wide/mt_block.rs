//! Moller-Trumbore leaves: a [`TriBlock`] whose rows hold, per lane, a triangle's first vertex and
//! its two edges `e1 = p1 - p0`, `e2 = p2 - p0` (Embree's `Triangle4` without the normal, Wald et
//! al. 2014), tested four at a time in SSE or eight (two blocks) in AVX2.
//!
//! The test computes, lane by lane, exactly the floating-point operations of
//! [`crate::geometry::triangle::moller_trumbore_edges`] in the same order (no fused multiply-adds),
//! and, as that function and Embree's default test do, divides by nothing: `U`, `V` and `T` with
//! the determinant's sign flipped into them are compared with `|det|`. A lane is kept only where
//! the scalar function's checks before its division pass (`T' > 0` added, which its check of `t`
//! after the division implies) or a value is NaN (ordered comparisons): the lanes of called-back
//! primitives, whose vertices are NaN, are kept that way. A kept lane is then decided from the
//! stored `|det|`, `U'`, `V'` and `T'` by the scalar function's own last step
//! ([`moller_decide`], one division), so a block reports exactly the hits that testing its
//! triangles one by one reports, bit for bit, with no second pass over the triangle.

#[cfg(target_arch = "x86_64")]
use super::simd;
use super::TriBlock;
use crate::accel::Primitives;
use crate::geometry::triangle::{moller_decide, moller_edges};
use crate::geometry::PrimHit;
use crate::math::{Ray, Vec3};
use std::mem::MaybeUninit;

/// Which ray-triangle test a tree's triangle blocks are laid out for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum LaneTest {
    /// Three vertices per lane, [`crate::geometry::triangle::watertight`] (`tri_block.rs`).
    #[default]
    Watertight,
    /// A vertex and two edges per lane ([`moller_edges`]), tested here.
    Moller,
}

impl LaneTest {
    /// Moller-Trumbore blocks when any primitive is a Moller-Trumbore triangle (a scene's meshes
    /// all take one test), else watertight ones. Watertight triangles in a Moller-Trumbore tree are
    /// called back, and the other way round.
    pub(crate) fn of<P: Primitives>(prims: &P) -> Self {
        use rayon::prelude::*;
        let any = (0..prims.count())
            .into_par_iter()
            .with_min_len(4096)
            .any(|i| prims.moller_triangle(i).is_some());
        if any {
            LaneTest::Moller
        } else {
            LaneTest::Watertight
        }
    }

    /// What a lane of this kind holds for primitive `id`, or `None` for a primitive called back.
    #[inline(always)]
    pub(crate) fn lane<P: Primitives>(self, prims: &P, id: usize) -> Option<[Vec3; 3]> {
        match self {
            LaneTest::Watertight => prims.watertight_triangle(id),
            LaneTest::Moller => prims.moller_triangle(id).map(moller_edges),
        }
    }
}

/// The test's `|det|`, `U'`, `V'` and `T'` of up to eight lanes (rows 0-3). Left uninitialised
/// until a test writes them, as [`super::tri_block::LaneValues`]: only the lanes it kept are read,
/// after it has written every row.
#[derive(Clone, Copy)]
pub struct MtValues {
    r: [[MaybeUninit<f32>; 8]; 4],
}

impl MtValues {
    #[inline(always)]
    pub fn new() -> Self {
        Self {
            r: [[MaybeUninit::uninit(); 8]; 4],
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn row_ptr(&mut self, row: usize) -> *mut f32 {
        self.r[row].as_mut_ptr().cast()
    }

    #[cfg_attr(target_arch = "x86_64", allow(dead_code))]
    #[inline(always)]
    fn set(&mut self, row: usize, lane: usize, v: f32) {
        self.r[row][lane] = MaybeUninit::new(v);
    }
}

impl Default for MtValues {
    fn default() -> Self {
        Self::new()
    }
}

/// Decides a lane the test kept, against the current `t_max`: exactly the end of
/// [`crate::geometry::triangle::moller_trumbore_edges`] on the lane's triangle.
///
/// # Safety
/// The last test run into `v` kept `lane`.
#[inline(always)]
pub unsafe fn finish_moller(v: &MtValues, lane: usize, t_max: f32) -> Option<PrimHit> {
    let get = |row: usize| v.r[row][lane].assume_init();
    moller_decide(get(0), get(1), get(2), get(3), t_max)
}

/// The test's body over any lane width: `$row(r)` loads row `r` of the lanes (0-2 the vertex,
/// 3-5 `e1`, 6-8 `e2`), `$store(r, x)` receives rows `|det|`, `U'`, `V'`, `T'` when a lane is
/// kept. Each step is the scalar test's operation, in its order.
#[cfg(target_arch = "x86_64")]
macro_rules! moller_filter {
    ($ray:expr, $t_max:expr, $row:expr, $store:expr) => {{
        let ray: &Ray = $ray;
        let row = $row;
        let mut put = $store;
        let [dx, dy, dz] = ray.dir.to_array().map(|x| splat(x));
        let [ox, oy, oz] = ray.origin.to_array().map(|x| splat(x));
        let (e2x, e2y, e2z) = (row(6), row(7), row(8));
        // pvec = d x e2, det = e1 . pvec
        let px = sub(mul(dy, e2z), mul(e2y, dz));
        let py = sub(mul(dz, e2x), mul(e2z, dx));
        let pz = sub(mul(dx, e2y), mul(e2x, dy));
        let (e1x, e1y, e1z) = (row(3), row(4), row(5));
        let det = add(add(mul(e1x, px), mul(e1y, py)), mul(e1z, pz));
        // The determinant's sign, flipped into `U`, `V`, `T` (exact), and its magnitude.
        let sign = and(det, splat(-0.0));
        let abs_det = xor(det, sign);
        // tvec = o - p0, U' = (tvec . pvec) ^ sign
        let (tx, ty, tz) = (sub(ox, row(0)), sub(oy, row(1)), sub(oz, row(2)));
        let u = xor(add(add(mul(tx, px), mul(ty, py)), mul(tz, pz)), sign);
        let zero = splat(0.0);
        // `det == 0` is left to the decision: such a lane passes only with `U' = 0`.
        let out_u = or(lt(u, zero), gt(u, abs_det));
        // Most blocks a ray reaches miss it in every lane by `U'` already.
        if mask(out_u) == 0xff >> (8 - LANES) {
            return 0;
        }
        // qvec = tvec x e1, V' = (d . qvec) ^ sign, T' = (e2 . qvec) ^ sign
        let qx = sub(mul(ty, e1z), mul(e1y, tz));
        let qy = sub(mul(tz, e1x), mul(e1z, tx));
        let qz = sub(mul(tx, e1y), mul(e1x, ty));
        let v = xor(add(add(mul(dx, qx), mul(dy, qy)), mul(dz, qz)), sign);
        let t = xor(add(add(mul(e2x, qx), mul(e2y, qy)), mul(e2z, qz)), sign);
        let out_v = or(lt(v, zero), gt(add(u, v), abs_det));
        let out_t = or(le(t, zero), gt(t, mul(abs_det, splat($t_max))));
        let kept = mask(not(or(out_u, or(out_v, out_t))));
        if kept != 0 {
            put(0, abs_det);
            put(1, u);
            put(2, v);
            put(3, t);
        }
        kept
    }};
}

/// Bit `i` is set if lane `i` of `b` may be hit in `(0, t_max)` (or is called back); its `u`, `v`
/// and `t` are left in `out` for [`finish_moller`].
#[inline(always)]
pub fn moller_candidates(b: &TriBlock, ray: &Ray, t_max: f32, out: &mut MtValues) -> u32 {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE and SSE2 are part of x86_64; the loads read 16-byte aligned `[f32; 4]` rows
    // below 9, the stores the first four floats of `[f32; 8]` rows.
    unsafe {
        use simd::sse::*;
        const LANES: u32 = 4;
        moller_filter!(
            ray,
            t_max,
            |r: usize| load(b.v.get_unchecked(r).as_ptr()),
            |r: usize, x| store(out.row_ptr(r), x)
        )
    }
    #[cfg(not(target_arch = "x86_64"))]
    moller_candidates_scalar(b, ray, t_max, out, 0)
}

/// [`moller_candidates`] of two blocks at once in AVX: bits 0-3 are `a`'s lanes, 4-7 `b`'s.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn moller_candidates_pair_avx2(
    a: &TriBlock,
    b: &TriBlock,
    ray: &Ray,
    t_max: f32,
    out: &mut MtValues,
) -> u32 {
    use simd::avx::*;
    const LANES: u32 = 8;
    moller_filter!(
        ray,
        t_max,
        // SAFETY (the indexing): rows below 9.
        |r: usize| load2(b.v.get_unchecked(r).as_ptr(), a.v.get_unchecked(r).as_ptr()),
        |r: usize, x| store(out.row_ptr(r), x)
    )
}

/// The same test one lane at a time (targets without SSE, and the SIMD paths' check), its values
/// written to lanes `first_lane..first_lane + 4`.
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
pub(super) fn moller_candidates_scalar(
    b: &TriBlock,
    ray: &Ray,
    t_max: f32,
    out: &mut MtValues,
    first_lane: usize,
) -> u32 {
    let mut mask = 0;
    for lane in 0..4 {
        let row = |r: usize| Vec3::new(b.v[r][lane], b.v[r + 1][lane], b.v[r + 2][lane]);
        let vals = crate::geometry::triangle::moller_values(ray, row(0), row(3), row(6));
        let [abs_det, u, v, t] = vals;
        // Not `!(0.0..=abs_det).contains(&u)`: a NaN `u` is kept, as the SIMD comparisons keep it.
        #[allow(clippy::manual_range_contains)]
        let out_u = u < 0.0 || u > abs_det;
        let out_v = v < 0.0 || u + v > abs_det;
        let out_t = t <= 0.0 || t > abs_det * t_max;
        for (r, x) in vals.into_iter().enumerate() {
            out.set(r, first_lane + lane, x);
        }
        mask |= (!(out_u || out_v || out_t) as u32) << lane;
    }
    mask
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::triangle::moller_trumbore;

    fn lcg(s: &mut u64) -> f32 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*s >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }

    /// A block of Moller-Trumbore lanes (`None`: a called-back primitive).
    fn block(tris: &[Option<[Vec3; 3]>]) -> TriBlock {
        let lanes: Vec<_> = tris
            .iter()
            .enumerate()
            .map(|(k, t)| (k as u32, t.map(moller_edges)))
            .collect();
        TriBlock::new(&lanes)
    }

    /// Every lane the scalar reference hits is kept, every kept lane finishes as the reference
    /// does (bit for bit, for any narrower `t_max` too), SSE, AVX and scalar agree, called-back
    /// lanes are always kept, and most misses are rejected. Rays along axes, through vertices and
    /// shared edges, with infinite components, and degenerate triangles included.
    #[test]
    fn moller_blocks_hit_exactly_what_the_scalar_test_hits() {
        let mut s = 5u64;
        let (mut hits, mut kept, mut total) = (0, 0, 0);
        for i in 0..20_000 {
            let p = |s: &mut u64| Vec3::new(lcg(s), lcg(s), lcg(s));
            let mut tris: Vec<Option<[Vec3; 3]>> = (0..4)
                .map(|_| Some([p(&mut s), p(&mut s), p(&mut s)]))
                .collect();
            match i % 11 {
                // Degenerate: collinear, and a point.
                3 => {
                    let [a, b, _] = tris[2].unwrap();
                    tris[2] = Some([a, b, a + 2.0 * (b - a)]);
                    tris[3] = Some([a; 3]);
                }
                // Called back.
                5 => tris[1] = None,
                // Sharing an edge with lane 0.
                7 => {
                    let [a, b, _] = tris[0].unwrap();
                    tris[1] = Some([b, a, p(&mut s)]);
                }
                _ => {}
            }
            let dir = match i % 6 {
                0 => Vec3::X,
                1 => -Vec3::Z,
                2 if i % 12 == 2 => Vec3::new(f32::INFINITY, 0.1, 0.2),
                _ => p(&mut s),
            };
            let origin = p(&mut s) * 2.0;
            let dir = if i % 7 == 0 {
                // Toward lane 0's first vertex, or the midpoint of its edge shared with lane 1.
                let [a, b, _] = tris[0].unwrap();
                if i % 14 == 0 {
                    a - origin
                } else {
                    (a + b) * 0.5 - origin
                }
            } else {
                dir
            };
            let ray = Ray::new(origin, dir);
            let b = block(&tris);
            let t_max = if i % 3 == 0 { 1.5 } else { f32::INFINITY };
            let mut vals = MtValues::default();
            let mask = moller_candidates(&b, &ray, t_max, &mut vals);
            let mut scalar_vals = MtValues::default();
            assert_eq!(
                mask,
                moller_candidates_scalar(&b, &ray, t_max, &mut scalar_vals, 0),
                "ray {i}"
            );
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                let other = block(&tris[1..]);
                let mut pair_vals = MtValues::default();
                let mut other_vals = MtValues::default();
                // SAFETY: the CPU has AVX2.
                let pair =
                    unsafe { moller_candidates_pair_avx2(&b, &other, &ray, t_max, &mut pair_vals) };
                let other_mask = moller_candidates(&other, &ray, t_max, &mut other_vals);
                assert_eq!(pair, mask | other_mask << 4, "ray {i}");
                for k in 0..8 {
                    if pair & (1 << k) != 0 {
                        let (single, lane) = if k < 4 {
                            (&vals, k)
                        } else {
                            (&other_vals, k - 4)
                        };
                        // SAFETY: both tests kept the lane.
                        unsafe {
                            assert_eq!(
                                finish_moller(&pair_vals, k, t_max),
                                finish_moller(single, lane, t_max)
                            )
                        };
                    }
                }
            }
            for (k, t) in tris.iter().enumerate() {
                let Some(t) = t else {
                    assert!(mask & (1 << k) != 0, "ray {i}: a called-back lane dropped");
                    continue;
                };
                // Infinite directions give NaN values, which are kept: not counted.
                if ray.dir.is_finite() {
                    total += 1;
                    kept += ((mask >> k) & 1) as usize;
                }
                for limit in [t_max, 0.8] {
                    let want = moller_trumbore(&ray, limit, t[0], t[1], t[2]);
                    if want.is_some() && limit == t_max {
                        hits += ray.dir.is_finite() as usize;
                        assert!(mask & (1 << k) != 0, "ray {i} lane {k}: a hit filtered out");
                    }
                    if mask & (1 << k) != 0 {
                        // SAFETY: both tests kept lane `k`.
                        let (got, got_scalar) = unsafe {
                            (
                                finish_moller(&vals, k, limit.min(t_max)),
                                finish_moller(&scalar_vals, k, limit.min(t_max)),
                            )
                        };
                        let want = moller_trumbore(&ray, limit.min(t_max), t[0], t[1], t[2]);
                        assert_eq!(got, want, "ray {i} lane {k}");
                        assert_eq!(got_scalar, want, "ray {i} lane {k}");
                    }
                }
            }
        }
        assert!(hits > 1000, "{hits}");
        // Kept lanes are the hits (and the rare NaN): nearly every miss is rejected.
        assert!(
            kept < hits + total / 100,
            "kept {kept} of {total}, {hits} hits"
        );
    }

    #[test]
    fn degenerate_triangles_get_zero_edges() {
        let [p, e1, e2] = moller_edges([Vec3::ZERO, Vec3::X, 2.0 * Vec3::X]);
        assert_eq!((p, e1, e2), (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO));
        let t = [
            Vec3::ONE,
            Vec3::new(2.0, 1.0, 1.0),
            Vec3::new(1.0, 3.0, 1.0),
        ];
        assert_eq!(moller_edges(t), [Vec3::ONE, Vec3::X, 2.0 * Vec3::Y]);
    }
}
