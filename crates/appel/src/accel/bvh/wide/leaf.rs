//! A leaf's blocks of triangles (or of pairs of triangles, or of Moller-Trumbore triangles) against
//! one ray.

use super::mt_block::{finish_moller, moller_candidates, MtValues};
use super::quad_block::QuadBlock;
use super::tri_block::{finish, LaneValues, RayTri, TriBlock};
use crate::accel::{test_primitive, Hit, Primitives, TraversalStats};
use crate::math::{Ray, Vec3};

/// Tests a leaf's triangle blocks (and calls back its other primitives), narrowing `t_max` and
/// setting `best` at each nearer hit; with `ANY`, returns at the first. `count` is the leaf's
/// number of primitives (the last block's unused lanes are skipped).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn test_blocks<P: Primitives, const ANY: bool, const AVX: bool>(
    blocks: &[TriBlock],
    count: usize,
    rt: &RayTri,
    prims: &P,
    ray: &Ray,
    t_max: &mut f32,
    best: &mut Option<Hit>,
    stats: &mut TraversalStats,
) {
    let mut vals = LaneValues::new();
    let mut at = 0;
    while at < blocks.len() {
        // Two blocks per AVX filter where the leaf has them.
        #[cfg(target_arch = "x86_64")]
        let (mut m, step) = if AVX && at + 1 < blocks.len() {
            // SAFETY: callers pass `AVX` only from functions compiled for AVX2, entered after
            // detecting it.
            let m =
                unsafe { rt.candidates_pair_avx2(&blocks[at], &blocks[at + 1], *t_max, &mut vals) };
            (m, 2)
        } else {
            (rt.candidates(&blocks[at], *t_max, &mut vals), 1)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let (mut m, step) = (rt.candidates(&blocks[at], *t_max, &mut vals), 1);
        // The last block's unused lanes repeat lane 0: skip them (a called-back
        // primitive there would be tested twice).
        let lanes = count - 4 * at;
        if lanes < 8 {
            m &= (1 << lanes) - 1;
        }
        let pair = &blocks[at..at + step];
        at += step;
        let lane = |bit: usize| {
            let b = &pair[bit / 4];
            (b.id[bit % 4], b.triangle(bit % 4))
        };
        // SAFETY: the filter run into `vals` just kept the lanes of `m`.
        if unsafe { decide::<P, ANY>(m, &vals, lane, prims, ray, t_max, best, stats) } {
            return;
        }
    }
}

/// Decides the lanes in mask `m`, lowest first: `lane(bit)` is a lane's primitive and its
/// triangle (`None` for a primitive called back). Narrows `t_max` and sets `best` at each nearer hit; returns whether an any-hit query
/// (`ANY`) is answered.
///
/// # Safety
/// The filter run last into `vals` kept every lane of `m`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
unsafe fn decide<P: Primitives, const ANY: bool>(
    mut m: u32,
    vals: &LaneValues,
    lane: impl Fn(usize) -> (u32, Option<[Vec3; 3]>),
    prims: &P,
    ray: &Ray,
    t_max: &mut f32,
    best: &mut Option<Hit>,
    stats: &mut TraversalStats,
) -> bool {
    while m != 0 {
        let bit = m.trailing_zeros() as usize;
        m &= m - 1;
        let (id, tri) = lane(bit);
        let h = match tri {
            Some(tri) => finish(vals, bit, tri, ray, *t_max),
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
}

/// [`test_blocks`] for a leaf of [`QuadBlock`]s: `count` lanes in use (pairs, lone triangles or
/// called-back primitives), each pair's two triangles filtered together in one AVX run (two SSE
/// runs without AVX2). Adds the triangle lanes it reaches to `stats.prim_tests`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn test_quads<P: Primitives, const ANY: bool, const AVX: bool>(
    quads: &[QuadBlock],
    count: usize,
    rt: &RayTri,
    prims: &P,
    ray: &Ray,
    t_max: &mut f32,
    best: &mut Option<Hit>,
    stats: &mut TraversalStats,
) {
    let mut vals = LaneValues::new();
    for (at, q) in quads.iter().enumerate() {
        let used = count - 4 * at;
        let lanes = if used < 4 { (1u32 << used) - 1 } else { 0b1111 };
        let pairs = q.pair_mask() & lanes;
        stats.prim_tests += (lanes.count_ones() + pairs.count_ones()) as u64;
        #[cfg(target_arch = "x86_64")]
        let m = if AVX {
            // SAFETY: callers pass `AVX` only from functions compiled for AVX2, entered after
            // detecting it.
            unsafe { rt.candidates_quads_avx2(q, *t_max, &mut vals) }
        } else {
            rt.candidates_quads(q, *t_max, &mut vals)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let m = rt.candidates_quads(q, *t_max, &mut vals);
        // Unused lanes, and the second triangle of lanes that have none.
        let m = m & (lanes | pairs << 4);
        let lane = |bit: usize| (q.prim(bit), q.triangle(bit));
        // SAFETY: the filter run into `vals` just kept the lanes of `m`.
        if unsafe { decide::<P, ANY>(m, &vals, lane, prims, ray, t_max, best, stats) } {
            return;
        }
    }
}

/// [`test_blocks`] for a leaf of Moller-Trumbore blocks (`mt_block.rs`): two blocks per AVX test
/// where the leaf has them, each kept lane decided from the test's values against the current
/// `t_max` (or called back).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn test_moller_blocks<P: Primitives, const ANY: bool, const AVX: bool>(
    blocks: &[TriBlock],
    count: usize,
    prims: &P,
    ray: &Ray,
    t_max: &mut f32,
    best: &mut Option<Hit>,
    stats: &mut TraversalStats,
) {
    let mut vals = MtValues::new();
    let mut at = 0;
    while at < blocks.len() {
        #[cfg(target_arch = "x86_64")]
        let (mut m, step) = if AVX && at + 1 < blocks.len() {
            // SAFETY: callers pass `AVX` only from functions compiled for AVX2, entered after
            // detecting it.
            let m = unsafe {
                super::mt_block::moller_candidates_pair_avx2(
                    &blocks[at],
                    &blocks[at + 1],
                    ray,
                    *t_max,
                    &mut vals,
                )
            };
            (m, 2)
        } else {
            (moller_candidates(&blocks[at], ray, *t_max, &mut vals), 1)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let (mut m, step) = (moller_candidates(&blocks[at], ray, *t_max, &mut vals), 1);
        // The last block's unused lanes repeat lane 0: skip them.
        let lanes = count - 4 * at;
        if lanes < 8 {
            m &= (1 << lanes) - 1;
        }
        let pair = &blocks[at..at + step];
        at += step;
        while m != 0 {
            let bit = m.trailing_zeros() as usize;
            m &= m - 1;
            let (b, lane) = (&pair[bit / 4], bit % 4);
            let id = b.id[lane];
            let h = if b.v[0][lane].is_nan() {
                test_primitive::<P, ANY>(prims, id as usize, ray, *t_max, stats)
            } else {
                // SAFETY: the test run into `vals` just kept this lane.
                unsafe { finish_moller(&vals, bit, *t_max) }
            };
            if let Some(h) = h {
                *best = Some(Hit::new(id as usize, h));
                if ANY {
                    return;
                }
                *t_max = h.t;
            }
        }
    }
}
