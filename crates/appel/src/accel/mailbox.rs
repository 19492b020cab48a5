//! The leaf test shared by the structures that list a primitive in every cell it overlaps (the
//! octree and the BSP tree): each listed primitive is tested through a per-ray mailbox, so that a
//! primitive met again in a later cell along the ray is not tested twice.

use super::{test_primitive, Hit, Primitives, TraversalStats};
use crate::math::Ray;

/// Direct-mapped per-ray mailbox (Amanatides & Woo 1987 mark each primitive with the id of the
/// last ray that tested it; that is shared mutable state, so each ray keeps a small table of the
/// ids it tested on its stack instead). A collision only costs a repeated test, never a skipped
/// one.
pub(crate) struct Mailbox([u32; 32]);

impl Mailbox {
    #[inline(always)]
    pub(crate) fn new() -> Self {
        Self([u32::MAX; 32])
    }

    /// Whether `p` was tested already; records it as tested.
    #[inline(always)]
    fn seen(&mut self, p: u32) -> bool {
        let slot = (p.wrapping_mul(0x9E37_79B9) >> 27) as usize;
        std::mem::replace(&mut self.0[slot], p) == p
    }
}

/// Tests the primitives `items` of a cell, narrowing `t_max` and replacing `best` at each nearer
/// hit (with `ANY`, stopping at the first). Hits beyond the cell are kept as candidates rather
/// than discarded: that is what makes the mailbox correct, since a primitive tested once either
/// missed or is `best` already, and what lets the caller end the walk once `t_max` lies within
/// the cells walked so far.
#[inline(always)]
pub(crate) fn test_items<P: Primitives, const ANY: bool>(
    items: &[u32],
    prims: &P,
    ray: &Ray,
    t_max: &mut f32,
    best: &mut Option<Hit>,
    mail: &mut Mailbox,
    stats: &mut TraversalStats,
) {
    for &p in items {
        if mail.seen(p) {
            continue;
        }
        stats.prim_tests += 1;
        if let Some(h) = test_primitive::<P, ANY>(prims, p as usize, ray, *t_max, stats) {
            *best = Some(Hit::new(p as usize, h));
            if ANY {
                return;
            }
            *t_max = h.t;
        }
    }
}
