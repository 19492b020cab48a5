//! The kd-tree's 8-byte node (pbrt's `KdAccelNode`, Pharr et al. 2016, section 4.4.1): depth-first
//! order, the below child right after its parent, so an interior node stores only the above child.

use bytemuck::{Pod, Zeroable};

/// Interior: `data` is the split position's bits, `flags` holds the axis (0-2) in its low two bits
/// and the above child's index above them. Leaf: low bits 3, `data` is the leaf's first triangle
/// block and the high bits its primitive count (its blocks are the next `count.div_ceil(4)`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct KdNode {
    pub(super) data: u32,
    pub(super) flags: u32,
}

const _: () = assert!(std::mem::size_of::<KdNode>() == 8);

impl KdNode {
    pub(super) fn leaf(first_block: u32, count: u32) -> Self {
        assert!(count < 1 << 30, "kd-tree leaf of {count} primitives");
        Self {
            data: first_block,
            flags: 3 | count << 2,
        }
    }

    pub(super) fn interior(axis: usize, split: f32, above: u32) -> Self {
        assert!(above < 1 << 30, "kd-tree of more than 2^30 nodes");
        Self {
            data: split.to_bits(),
            flags: axis as u32 | above << 2,
        }
    }

    #[inline(always)]
    pub(super) fn is_leaf(&self) -> bool {
        self.flags & 3 == 3
    }

    #[inline(always)]
    pub(super) fn axis(&self) -> usize {
        (self.flags & 3) as usize
    }

    /// Interior: the above child's index. Leaf: the primitive count.
    #[inline(always)]
    pub(super) fn high(&self) -> u32 {
        self.flags >> 2
    }

    #[inline(always)]
    pub(super) fn split(&self) -> f32 {
        f32::from_bits(self.data)
    }
}
