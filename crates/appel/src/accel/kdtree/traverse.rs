//! Front-to-back traversal (pbrt's `KdTreeAccel::Intersect`, Pharr et al. 2016, section 4.4.4) of
//! the three-level nodes (`wide.rs`): a node gives the ray's interval in each of its eight cells at
//! once; the cells it crosses wait on a small explicit stack, nearest on top, with their intervals;
//! no recursion; and the traversal ends as soon as the closest hit lies before the end of the
//! current cell. Leaves hold their triangles in SIMD blocks of eight (`leaf.rs`: the watertight
//! test's edge functions on a whole block in one AVX2 pass, the survivors decided by the scalar
//! test, so hits are bit-identical to it), with a per-ray mailbox in front of the scalar test.
//!
//! The node test uses AVX2 when the CPU has it (detected once, at run time), otherwise the same
//! operations lane by lane.

#[cfg(target_arch = "x86_64")]
use super::leaf::LeafRay8;
use super::leaf::{self, KdBlock, LeafRay, LANES};
use super::wide::{self, Cell, RayPlanes};
use super::{KdNode8, KdTree, WIDE_STACK};
use crate::accel::{Hit, Primitives, TraversalStats};
use crate::math::{far_scale, Ray, RayBox, Vec3};
use std::mem::MaybeUninit;

/// Direct-mapped per-ray mailbox (Amanatides & Woo 1987 mark primitives with a ray id; a per-ray
/// table on the stack needs no shared mutable marks, so it is thread-safe). A collision only costs a
/// repeated test, never a skipped one. Only the filter's survivors reach it - nearly always real
/// hits, or primitives called back - so it can be small.
const MAILBOX: usize = 32;

/// A cell waiting to be visited, with the ray's interval in it.
#[derive(Clone, Copy)]
struct Waiting {
    cell: Cell,
    t0: f32,
    t1: f32,
}

impl KdTree {
    /// Asks for a crossed cell's node, or its leaf's first two blocks, to be brought into the
    /// cache while the nearer cells are visited ([`crate::accel::PREFETCH_BYTES`]).
    #[inline(always)]
    fn prefetch_cell(&self, cell: Cell) {
        if wide::is_leaf(cell) {
            let (first, _) = wide::leaf_range(cell);
            let at = self.blocks.as_ptr().wrapping_add(first);
            crate::accel::prefetch(at, std::mem::size_of::<KdBlock>());
        } else {
            let at = self.nodes.as_ptr().wrapping_add(cell as usize);
            crate::accel::prefetch(at, std::mem::size_of::<KdNode8>());
        }
    }

    #[inline(always)]
    pub(super) fn traverse<P: Primitives, const ANY: bool>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        #[cfg(target_arch = "x86_64")]
        if crate::accel::has_avx2() {
            // SAFETY: the CPU has AVX2.
            return unsafe { self.traverse_avx2::<P, ANY>(prims, ray, t_max, stats) };
        }
        self.traverse_with::<P, ANY, false>(prims, ray, t_max, stats)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn traverse_avx2<P: Primitives, const ANY: bool>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        self.traverse_with::<P, ANY, true>(prims, ray, t_max, stats)
    }

    /// The traversal; `AVX` is true only when called from `traverse_avx2`. Public to the module's
    /// tests, which run the portable path on AVX2 machines too.
    #[inline(always)]
    pub(super) fn traverse_with<P: Primitives, const ANY: bool, const AVX: bool>(
        &self,
        prims: &P,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        stats.rays += 1;
        let mut cur = self.root?;
        let rb = RayBox::new(ray);
        let (mut t0, mut t1) =
            self.bounds
                .slab_intersect(ray, Vec3::from(rb.inv), t_max * far_scale())?;
        let planes = RayPlanes::new(rb.o, rb.inv);
        let rt = LeafRay::new(ray);
        // The filter's ray constants broadcast once per ray (not once per block).
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `AVX` is true only inside `traverse_avx2`.
        let rt8 = if AVX {
            Some(unsafe { LeafRay8::new(&rt) })
        } else {
            None
        };
        let mut stack = [const { MaybeUninit::<Waiting>::uninit() }; WIDE_STACK];
        let mut sp = 0usize;
        let (mut near, mut far) = ([0.0f32; 8], [0.0f32; 8]);
        let mut best = None;
        let mut mail = [u32::MAX; MAILBOX];
        loop {
            stats.nodes_visited += 1;
            if !wide::is_leaf(cur) {
                // SAFETY: node cells hold indices of nodes the collapse wrote (`wide.rs`).
                let n = unsafe { self.nodes.get_unchecked(cur as usize) };
                // Cells starting beyond the closest hit cannot hold a nearer one.
                // (Neither is NaN: a plain comparison, not `f32::min`'s NaN handling, which put
                // a compare and a blend on the step's path.)
                let t_end = if t_max < t1 { t_max } else { t1 };
                #[cfg(target_arch = "x86_64")]
                let mask = if AVX {
                    // SAFETY: `AVX` is true only inside `traverse_avx2`.
                    unsafe { wide::cells_avx2(n, &planes, t0, t_end, &mut near, &mut far) }
                } else {
                    wide::cells_portable(n, &planes, t0, t_end, &mut near, &mut far)
                };
                #[cfg(not(target_arch = "x86_64"))]
                let mask = wide::cells_portable(n, &planes, t0, t_end, &mut near, &mut far);
                if mask != 0 {
                    // Go on into the nearest crossed cell and push the others sorted, nearest on
                    // top. The nearest is kept in registers rather than taken back off the stack:
                    // the next node's address is on the traversal's critical path. An exit cut at
                    // the best hit is as good as the cell's own for the early exit: any later hit
                    // is nearer than both.
                    // `& 7`: the mask has eight bits; it lets the compiler drop the index checks.
                    let c = (mask.trailing_zeros() & 7) as usize;
                    let mut next = Waiting {
                        cell: n.cell[c],
                        t0: near[c],
                        t1: far[c],
                    };
                    let base = sp;
                    let mut m = mask & (mask - 1);
                    while m != 0 {
                        let c = (m.trailing_zeros() & 7) as usize;
                        m &= m - 1;
                        let mut e = Waiting {
                            cell: n.cell[c],
                            t0: near[c],
                            t1: far[c],
                        };
                        if self.prefetch {
                            self.prefetch_cell(e.cell);
                        }
                        if ANY {
                            // Any hit ends the query, so the order does not matter (sorting would
                            // only delay the first hit), and no cell beyond `t_max` was taken.
                            stack[sp] = MaybeUninit::new(e);
                            sp += 1;
                            continue;
                        }
                        if e.t0 < next.t0 {
                            std::mem::swap(&mut e, &mut next);
                        }
                        let mut j = sp;
                        // SAFETY: entries `base..sp` were written in this loop.
                        while j > base && unsafe { stack[j - 1].assume_init() }.t0 < e.t0 {
                            stack[j] = stack[j - 1];
                            j -= 1;
                        }
                        stack[j] = MaybeUninit::new(e);
                        sp += 1;
                    }
                    (cur, t0, t1) = (next.cell, next.t0, next.t1);
                    continue;
                }
            } else {
                let (first, count) = wide::leaf_range(cur);
                stats.prim_tests += count as u64;
                let blocks = &self.blocks[first..first + count.div_ceil(LANES)];
                // A primitive tested in an earlier leaf either missed or is already `best` (hits
                // beyond their leaf are kept, not discarded), so testing it again cannot help.
                let seen = |p: u32| {
                    let slot = (p.wrapping_mul(0x9E37_79B9) >> 27) as usize;
                    std::mem::replace(&mut mail[slot], p) == p
                };
                let filter = |b: &KdBlock, t_max: f32| {
                    #[cfg(target_arch = "x86_64")]
                    if let Some(r8) = &rt8 {
                        // SAFETY: `rt8` is set only inside `traverse_avx2`.
                        return unsafe { r8.candidates(b, t_max) };
                    }
                    rt.candidates_scalar(b, t_max)
                };
                leaf::test_leaf::<P, ANY>(
                    blocks, count, prims, ray, &mut t_max, &mut best, stats, filter, seen,
                );
                if ANY && best.is_some() {
                    return best;
                }
                // The closest hit lies in this cell (or before it): later cells cannot beat it. (An
                // any-hit query visits cells out of order, and has returned if it hit anything.)
                if !ANY && t_max <= t1 {
                    return best;
                }
            }
            // The waiting cells are in the order the ray crosses them: once one starts beyond the
            // closest hit, so do all the others. (An any-hit query pushed none beyond `t_max`.)
            if sp == 0 {
                return best;
            }
            sp -= 1;
            // SAFETY: entries below `sp` were written by the pushes above.
            let w = unsafe { stack[sp].assume_init() };
            if t_max < w.t0 {
                return best;
            }
            (cur, t0, t1) = (w.cell, w.t0, w.t1);
        }
    }
}
