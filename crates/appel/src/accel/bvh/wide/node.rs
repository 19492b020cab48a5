//! The wide node: the boxes of up to `W` children in structure-of-arrays order, so one SIMD
//! instruction computes one slab distance for all children (the layout of Embree's BVH4/BVH8 nodes,
//! Wald et al. 2014, "Embree: a kernel framework for efficient CPU ray tracing").

/// A child slot: an interior node's index, a leaf, or nothing.
pub(crate) type Child = u64;

/// Tag bit of a leaf slot: `LEAF | [NO_TRIANGLES | QUADS] | count << 32 | first_block`, `count` the
/// lanes of its blocks in use (primitives, or for `QUADS` pairs and lone triangles).
pub(crate) const LEAF: Child = 1 << 63;
/// Set on a leaf none of whose primitives is a gathered triangle: traversal calls each back without
/// running the triangle filter.
pub(crate) const NO_TRIANGLES: Child = 1 << 62;
/// Set on a leaf of [`super::quad_block::QuadBlock`]s (`first_block` indexes those), clear on one
/// of [`super::TriBlock`]s.
pub(crate) const QUADS: Child = 1 << 61;
/// An unused slot (its box is empty, so no ray ever reaches it).
pub(crate) const EMPTY: Child = u64::MAX;

#[inline(always)]
pub(crate) fn leaf(first_block: u32, count: u32) -> Child {
    debug_assert!(count < 1 << 29);
    LEAF | (count as u64) << 32 | first_block as u64
}

#[inline(always)]
pub(crate) fn is_leaf(c: Child) -> bool {
    c & LEAF != 0
}

/// `(first_block, primitive_count)` of a leaf slot.
#[inline(always)]
pub(crate) fn leaf_range(c: Child) -> (usize, usize) {
    (
        (c & 0xffff_ffff) as usize,
        ((c >> 32) & 0x1fff_ffff) as usize,
    )
}

/// `bounds[2 * axis]` holds the children's lower bounds along `axis`, `bounds[2 * axis + 1]` the
/// upper ones, so a ray picks its near and far planes per axis by the sign of its direction alone.
/// 256 bytes for `W = 8` (four cache lines), 128 for `W = 4`.
#[repr(C, align(64))]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WideNode<const W: usize> {
    pub bounds: [[f32; W]; 6],
    pub child: [Child; W],
}

impl<const W: usize> WideNode<W> {
    pub const EMPTY: Self = Self {
        bounds: [
            [f32::INFINITY; W],
            [f32::NEG_INFINITY; W],
            [f32::INFINITY; W],
            [f32::NEG_INFINITY; W],
            [f32::INFINITY; W],
            [f32::NEG_INFINITY; W],
        ],
        child: [EMPTY; W],
    };

    pub fn set(&mut self, lane: usize, min: [f32; 3], max: [f32; 3], child: Child) {
        for a in 0..3 {
            self.bounds[2 * a][lane] = min[a];
            self.bounds[2 * a + 1][lane] = max[a];
        }
        self.child[lane] = child;
    }
}

const _: () = assert!(std::mem::size_of::<WideNode<8>>() == 256);
const _: () = assert!(std::mem::size_of::<WideNode<4>>() == 128);
