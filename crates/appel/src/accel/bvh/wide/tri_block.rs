//! Four triangles gathered into one leaf block, structure of arrays, and a SIMD filter that runs the
//! watertight test's edge functions (Woop, Benthin & Wald 2013) on all four at once.
//!
//! The filter computes, lane by lane, exactly the floating-point operations of
//! [`crate::geometry::triangle::watertight`] in the same order (no fused multiply-adds), and rejects
//! a lane only where that function would certainly reject it: a ray outside the triangle's closed
//! edges with no edge function exactly zero (which that function re-evaluates in f64), or a `t`
//! outside its loosened range. Every surviving lane is decided by the scalar function itself, so a
//! block reports exactly the hits that testing its triangles one by one reports, bit for bit.

use super::mt_block::LaneTest;
#[cfg(target_arch = "x86_64")]
use super::simd;
use crate::accel::Primitives;
use crate::geometry::triangle::{
    watertight, watertight_filter_lane, watertight_finish, watertight_shear,
};
use crate::geometry::PrimHit;
use crate::math::{Ray, Vec3};
use std::mem::MaybeUninit;

/// Four triangles (`v[3 * k + axis]` is coordinate `axis` of vertex `k`, one lane per triangle;
/// in a tree of Moller-Trumbore blocks, of the first vertex and the two edges, `mt_block.rs`)
/// and their primitive ids. Lanes of other primitives have NaN vertices and are called back; a
/// leaf's last block repeats its lane 0 in its unused lanes, which traversal masks off by the
/// leaf's primitive count.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, bytemuck::Zeroable)]
pub struct TriBlock {
    pub v: [[f32; 4]; 9],
    pub id: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<TriBlock>() == 160);

impl TriBlock {
    /// A block of no primitives (zeros), to be overwritten.
    pub const PADDING: TriBlock = TriBlock {
        v: [[0.0; 4]; 9],
        id: [0; 4],
    };

    /// `lanes[i]` is a primitive id and its triangle, or `None` for a primitive that is called back.
    pub fn new(lanes: &[(u32, Option<[Vec3; 3]>)]) -> Self {
        assert!(!lanes.is_empty() && lanes.len() <= 4);
        let mut b = TriBlock {
            v: [[f32::NAN; 4]; 9],
            id: [0; 4],
        };
        for lane in 0..4 {
            let (id, tri) = lanes[if lane < lanes.len() { lane } else { 0 }];
            b.id[lane] = id;
            if let Some(tri) = tri {
                for (k, p) in tri.iter().enumerate() {
                    for a in 0..3 {
                        b.v[3 * k + a][lane] = p[a];
                    }
                }
            }
        }
        b
    }

    /// The block of up to four primitives `ids`, asking `prims` for their lanes of kind `test` (no allocation:
    /// builders call this once per block of millions).
    pub(crate) fn gather<P: Primitives>(prims: &P, test: LaneTest, ids: &[u32]) -> Self {
        let mut lanes = [(0u32, None); 4];
        for (lane, &id) in lanes.iter_mut().zip(ids) {
            *lane = (id, test.lane(prims, id as usize));
        }
        Self::new(&lanes[..ids.len()])
    }

    /// Copies lane 0 into lanes `used..4` (a leaf's last block).
    pub fn pad_from(&mut self, used: usize) {
        for lane in used..4 {
            self.id[lane] = self.id[0];
            for row in &mut self.v {
                row[lane] = row[0];
            }
        }
    }

    /// Whether any lane holds a triangle (rather than a called-back primitive).
    pub fn has_triangle(&self) -> bool {
        self.v[0].iter().any(|x| !x.is_nan())
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

/// The filter's body over any lane width: `$row(k, axis)` loads coordinate `axis` of the lanes'
/// vertex `k` (0, 1 or 2 of each lane's triangle). Each step is the scalar test's operation, in
/// its order. `$store(r, v)` is handed the intermediate rows of [`LaneValues`] when a lane is kept.
#[cfg(target_arch = "x86_64")]
macro_rules! filter {
    ($rt:expr, $t_max:expr, $row:expr, $store:expr) => {{
        let rt: &RayTri = $rt;
        let row = $row;
        let mut put = $store;
        let ld = |k: usize, a: usize| row(k, rt.k[a]);
        let [ox, oy, oz] = rt.o.map(|x| splat(x));
        let [sx, sy, sz] = rt.s.map(|x| splat(x));
        // Translate to the ray origin, permute, shear (pbrt-v4 eq. 6.5 onwards).
        let vert = |k: usize| {
            let z = sub(ld(k, 2), oz);
            let x = add(sub(ld(k, 0), ox), mul(sx, z));
            let y = add(sub(ld(k, 1), oy), mul(sy, z));
            (x, y, z)
        };
        let (x0, y0, z0) = vert(0);
        let (x1, y1, z1) = vert(1);
        let (x2, y2, z2) = vert(2);
        let edge = |ax, ay, bx, by| sub(mul(ax, by), mul(ay, bx));
        let e0 = edge(x1, y1, x2, y2);
        let e1 = edge(x2, y2, x0, y0);
        let e2 = edge(x0, y0, x1, y1);
        let zero = splat(0.0);
        let any_zero = or(or(eq(e0, zero), eq(e1, zero)), eq(e2, zero));
        let any_neg = or(or(lt(e0, zero), lt(e1, zero)), lt(e2, zero));
        let any_pos = or(or(gt(e0, zero), gt(e1, zero)), gt(e2, zero));
        let inside = or(any_zero, not(and(any_neg, any_pos)));
        // Most blocks a ray reaches miss it in every lane: stop before the distance test and
        // the stores (fewer instructions, at the price of a branch that is harder to predict).
        if mask(inside) == 0 {
            return 0;
        }
        let det = add(add(e0, e1), e2);
        let (z0, z1, z2) = (mul(z0, sz), mul(z1, sz), mul(z2, sz));
        let t_scaled = add(add(mul(e0, z0), mul(e1, z1)), mul(e2, z2));
        let loose = mul(mul(splat($t_max), det), splat(1.0 + 4.0 * f32::EPSILON));
        let reject_t = or(
            or(
                eq(det, zero),
                and(lt(det, zero), or(ge(t_scaled, zero), lt(t_scaled, loose))),
            ),
            and(gt(det, zero), or(le(t_scaled, zero), gt(t_scaled, loose))),
        );
        let kept = mask(and(inside, or(any_zero, not(reject_t))));
        if kept != 0 {
            for (r, v) in [x0, x1, x2, y0, y1, y2, z0, z1, z2, e0, e1, e2]
                .into_iter()
                .enumerate()
            {
                put(r, v);
            }
        }
        kept
    }};
}

/// The filter's intermediate values of up to eight lanes: rows 0-2 the sheared `x` of the three
/// vertices, 3-5 their `y`, 6-8 their scaled `z`, 9-11 the edge functions. Left uninitialised
/// until the filter writes them: zeroing its 384 bytes at every leaf would cost every ray, and only
/// the lanes the filter kept are read, after it has written every row.
#[derive(Clone, Copy)]
pub struct LaneValues {
    r: [[MaybeUninit<f32>; 8]; 12],
}

impl LaneValues {
    #[inline(always)]
    pub fn new() -> Self {
        Self {
            r: [[MaybeUninit::uninit(); 8]; 12],
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn row_ptr(&mut self, row: usize) -> *mut f32 {
        self.r[row].as_mut_ptr().cast()
    }

    #[inline(always)]
    fn set(&mut self, row: usize, lane: usize, v: f32) {
        self.r[row][lane] = MaybeUninit::new(v);
    }

    /// # Safety
    /// `lane` of `row` was written: the filter that filled `self` kept `lane`.
    #[inline(always)]
    unsafe fn get(&self, row: usize, lane: usize) -> f32 {
        self.r[row][lane].assume_init()
    }
}

impl Default for LaneValues {
    fn default() -> Self {
        Self::new()
    }
}

/// Decides a lane the filter kept: exactly [`watertight`] on the lane's triangle, finished from the
/// filter's values unless an edge function is exactly zero (which the scalar test re-evaluates in
/// f64, so it gets the whole scalar test).
///
/// # Safety
/// The last filter run into `v` kept `lane` (its bit was set in the returned mask): the filter
/// writes every row before it reports any lane kept.
#[inline(always)]
pub unsafe fn finish(
    v: &LaneValues,
    lane: usize,
    tri: [Vec3; 3],
    ray: &Ray,
    t_max: f32,
) -> Option<PrimHit> {
    let e = [v.get(9, lane), v.get(10, lane), v.get(11, lane)];
    if e.contains(&0.0) {
        return watertight(ray, t_max, tri[0], tri[1], tri[2]);
    }
    let row = |k: usize| [v.get(k, lane), v.get(k + 1, lane), v.get(k + 2, lane)];
    // The largest component of |dir| is |dir[kz]|, which the error bound needs (see
    // `watertight_finish`).
    let dz_abs = ray.dir.abs().max_element();
    watertight_finish(row(0), row(3), row(6), e, t_max, dz_abs)
}

/// What the filter needs of a ray, computed once per ray: the watertight test's permutation (`kz`
/// the axis of the largest direction component) and shear.
#[derive(Clone, Copy, Debug)]
pub struct RayTri {
    // Visible to `quad_block`, which runs the same filter macro.
    pub(super) k: [usize; 3],
    pub(super) o: [f32; 3],
    pub(super) s: [f32; 3],
}

impl RayTri {
    #[inline(always)]
    pub fn new(ray: &Ray) -> Self {
        // A zero direction gives NaN shears: every lane survives the filter and the scalar test
        // rejects it, as it rejects such a ray.
        let (k, o, s) = watertight_shear(ray);
        Self { k, o, s }
    }

    /// Bit `i` is set if lane `i` may hit in `(0, t_max)`: the lanes to finish one by one (with
    /// [`finish`]), whose intermediate values are left in `out`.
    #[inline(always)]
    pub fn candidates(&self, b: &TriBlock, t_max: f32, out: &mut LaneValues) -> u32 {
        #[cfg(target_arch = "x86_64")]
        {
            self.candidates_sse(b, t_max, out)
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self.candidates_scalar(b, t_max, out)
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn candidates_sse(&self, b: &TriBlock, t_max: f32, out: &mut LaneValues) -> u32 {
        // SAFETY: SSE and SSE2 are part of x86_64; the loads read 16-byte aligned `[f32; 4]` rows
        // (rows `3 k + axis` with `k` and `axis` below 3: `RayTri::k` holds axes), the stores
        // write the first four floats of `[f32; 8]` rows.
        unsafe {
            use simd::sse::*;
            filter!(
                self,
                t_max,
                // Unchecked: a checked index was a compare and branch per row.
                |k: usize, axis: usize| load(b.v.get_unchecked(3 * k + axis).as_ptr()),
                |r: usize, v| store(out.row_ptr(r), v)
            )
        }
    }

    /// [`Self::candidates`] of two blocks at once in AVX: bits 0-3 are `a`'s lanes, 4-7 `b`'s.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn candidates_pair_avx2(
        &self,
        a: &TriBlock,
        b: &TriBlock,
        t_max: f32,
        out: &mut LaneValues,
    ) -> u32 {
        use simd::avx::*;
        filter!(
            self,
            t_max,
            // SAFETY (the indexing): `3 k + axis < 9`, as in `candidates_sse`.
            |k: usize, axis: usize| load2(
                b.v.get_unchecked(3 * k + axis).as_ptr(),
                a.v.get_unchecked(3 * k + axis).as_ptr()
            ),
            |r: usize, v| store(out.row_ptr(r), v)
        )
    }

    /// The same filter one lane at a time, for targets without the SSE path.
    #[cfg_attr(target_arch = "x86_64", allow(dead_code))]
    fn candidates_scalar(&self, b: &TriBlock, t_max: f32, out: &mut LaneValues) -> u32 {
        self.candidates_scalar_at(b, t_max, out, 0)
    }

    /// [`Self::candidates_scalar`], the values written to lanes `first_lane..first_lane + 4`.
    #[cfg_attr(target_arch = "x86_64", allow(dead_code))]
    pub(super) fn candidates_scalar_at(
        &self,
        b: &TriBlock,
        t_max: f32,
        out: &mut LaneValues,
        first_lane: usize,
    ) -> u32 {
        let mut mask = 0;
        for lane in 0..4 {
            let v = [0, 1, 2].map(|k| [0, 1, 2].map(|a| b.v[3 * k + a][lane]));
            let (kept, values) = watertight_filter_lane((self.k, self.o, self.s), v, t_max);
            for (r, x) in values.into_iter().enumerate() {
                out.set(r, first_lane + lane, x);
            }
            mask |= (kept as u32) << lane;
        }
        mask
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::triangle::watertight;

    fn lcg(s: &mut u64) -> f32 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*s >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }

    /// The filter never drops a lane the scalar test hits, the SSE and scalar filters agree, and
    /// it rejects most misses (else it would be no filter).
    #[test]
    fn filter_keeps_every_hit_and_rejects_most_misses() {
        let mut s = 7u64;
        let (mut hits, mut kept, mut total) = (0, 0, 0);
        for i in 0..20_000 {
            let p = |s: &mut u64| Vec3::new(lcg(s), lcg(s), lcg(s));
            let tris: Vec<[Vec3; 3]> = (0..4).map(|_| [p(&mut s), p(&mut s), p(&mut s)]).collect();
            // Some rays along axes, some through shared vertices, most random.
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
            let lanes: Vec<_> = tris
                .iter()
                .enumerate()
                .map(|(k, t)| (k as u32, Some(*t)))
                .collect();
            let b = TriBlock::new(&lanes);
            let rt = RayTri::new(&ray);
            let t_max = if i % 3 == 0 { 1.5 } else { f32::INFINITY };
            let mut vals = LaneValues::default();
            let mut scalar_vals = LaneValues::default();
            let mask = rt.candidates(&b, t_max, &mut vals);
            assert_eq!(mask, rt.candidates_scalar(&b, t_max, &mut scalar_vals));
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                let other = TriBlock::new(&lanes[1..]);
                // SAFETY: the CPU has AVX2.
                let mut pair_vals = LaneValues::default();
                let pair = unsafe { rt.candidates_pair_avx2(&b, &other, t_max, &mut pair_vals) };
                let mut other_vals = LaneValues::default();
                assert_eq!(
                    pair,
                    mask | rt.candidates(&other, t_max, &mut other_vals) << 4
                );
            }
            for (k, t) in tris.iter().enumerate() {
                total += 1;
                kept += (mask >> k) & 1;
                if mask & (1 << k) != 0 {
                    // Finishing from the filter's values is the scalar test, bit for bit.
                    let want = watertight(&ray, t_max, t[0], t[1], t[2]);
                    // SAFETY: both filters kept lane `k`.
                    let (got, got_scalar) = unsafe {
                        (
                            finish(&vals, k, *t, &ray, t_max),
                            finish(&scalar_vals, k, *t, &ray, t_max),
                        )
                    };
                    assert_eq!(got, want, "ray {i} lane {k}");
                    assert_eq!(got_scalar, want);
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
        // Survivors are the hits and the rare exactly-zero edge; nearly every miss is filtered.
        assert!(
            kept < hits + total / 100,
            "kept {kept} of {total}, {hits} hits"
        );
    }

    #[test]
    fn padding_repeats_lane_zero_and_other_primitives_are_nan() {
        let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let b = TriBlock::new(&[(5, Some(t)), (9, None)]);
        assert_eq!(b.id, [5, 9, 5, 5]);
        assert_eq!(b.triangle(0), Some(t));
        assert_eq!(b.triangle(1), None);
        assert_eq!(b.triangle(3), Some(t));
        let r = Ray::new(Vec3::new(0.2, 0.2, -1.0), Vec3::Z);
        // The called-back lane always survives; the triangle lanes hit.
        let mut vals = LaneValues::default();
        assert_eq!(
            RayTri::new(&r).candidates(&b, f32::INFINITY, &mut vals),
            0b1111
        );
    }
}
