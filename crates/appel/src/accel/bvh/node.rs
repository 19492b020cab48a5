//! The flattened BVH node: 32 bytes, two to a 64-byte cache line.

use bytemuck::{Pod, Zeroable};

/// One node of the flattened tree, in depth-first order: an interior node's first child is the next
/// node in memory, so only the second child's index is stored (the layout of pbrt's
/// `LinearBVHNode`, Pharr et al. 2023, section 7.3.4).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub min: [f32; 3],
    /// Leaf: index of the first primitive in the reordered index array. Interior: the second child.
    pub offset: u32,
    pub max: [f32; 3],
    /// Number of primitives; 0 marks an interior node.
    pub count: u16,
    /// Interior: the split axis, which orders the children front to back for a given ray.
    pub axis: u16,
}

const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

impl BvhNode {
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}
