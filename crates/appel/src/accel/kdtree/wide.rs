//! Three levels of the binary kd-tree in one node: seven split planes and the eight cells they cut
//! the node's cell into. A ray's interval in all eight cells comes from one 8-lane computation, so
//! traversal takes a third of the steps of the binary tree, and the steps are no longer chains of
//! dependent loads and coin-toss branches, which dominate the binary tree's incoherent rays.
//!
//! A cell's interval along the ray is the intersection of the three half-spaces on its path: the
//! side of a plane the ray is on before crossing at `t_split` is `[-inf, t_split]`, the other side
//! `[t_split, inf]`. Cells sharing a plane read the same `t_split`, so neighbouring cells meet
//! exactly, with no gap for rounding to open. The cells are disjoint and convex, so visiting them
//! by entry distance is visiting them in the order the ray crosses them, as the binary traversal
//! does (pbrt's `KdTreeAccel::Intersect`, Pharr et al. 2016, section 4.4.4).

use super::node::KdNode;

/// A cell's child: a node index, or a leaf (`LEAF` set, the primitive count in bits 32-61, the
/// first triangle block in the low 32 bits). Empty cells are left out of [`KdNode8::occupied`].
pub type Cell = u64;
pub const LEAF: Cell = 1 << 63;

#[inline(always)]
pub fn is_leaf(c: Cell) -> bool {
    c & LEAF != 0
}

/// A leaf's first block and primitive count.
#[inline(always)]
pub fn leaf_range(c: Cell) -> (usize, usize) {
    (c as u32 as usize, ((c & !LEAF) >> 32) as usize)
}

fn leaf(first_block: u32, count: u32) -> Cell {
    LEAF | (count as u64) << 32 | first_block as u64
}

/// Levels of the binary tree in one node.
pub const LEVELS: usize = 3;

/// Plane `k` is slot `k` of a binary heap: plane 0 splits the node's cell, planes `1 + b0` split its
/// halves, planes `3 + 2 b0 + b1` their halves. Cell `c = 4 b0 + 2 b1 + b2` lies on side `b0` of
/// plane 0, `b1` of plane `1 + b0` and `b2` of plane `3 + 2 b0 + b1` (0 below, 1 above). Where the
/// binary tree ends above the third level, the missing planes are pass-through ones (axis 0 at
/// `+inf`: everything is below), so the cell below them continues the leaf and those above are empty.
/// Aligned to a cache line, so that a node is two lines, never three.
#[repr(C, align(64))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KdNode8 {
    pub split: [f32; 8],
    /// The planes' axes in lanes 0-6; lane 7 holds the mask of non-empty cells (as a permutation
    /// index it is read modulo 8 and only lands in an unused lane).
    pub axis: [u32; 8],
    pub cell: [Cell; 8],
}

const _: () = assert!(std::mem::size_of::<KdNode8>() == 128);

impl KdNode8 {
    #[inline(always)]
    pub fn occupied(&self) -> u32 {
        self.axis[7]
    }
}

/// For each cell, the plane of each level on its path and the side it lies on.
pub const LEVEL_PLANE: [[u32; 8]; 3] = [[0; 8], [1, 1, 1, 1, 2, 2, 2, 2], [3, 3, 4, 4, 5, 5, 6, 6]];
pub const LEVEL_SIDE: [[u32; 8]; 3] = [
    [0, 0, 0, 0, 1, 1, 1, 1],
    [0, 0, 1, 1, 0, 0, 1, 1],
    [0, 1, 0, 1, 0, 1, 0, 1],
];

/// Collapses the binary tree (depth-first, below child after its parent) into three-level nodes;
/// returns the root's cell (a leaf when the whole tree is one) or `None` when the tree holds nothing.
pub(super) fn collapse(binary: &[KdNode], out: &mut Vec<KdNode8>) -> Option<Cell> {
    let root = binary.first()?;
    if root.is_leaf() {
        return (root.high() > 0).then(|| leaf(root.data, root.high()));
    }
    Some(collapse_at(binary, 0, out))
}

fn collapse_at(binary: &[KdNode], at: usize, out: &mut Vec<KdNode8>) -> Cell {
    let me = out.len();
    out.push(KdNode8::default());
    let mut node = KdNode8::default();
    let mut cells = [None; 8];
    place(binary, Some(at), 0, &mut node, &mut cells);
    let mut occupied = 0;
    for (c, sub) in cells.iter().enumerate() {
        let Some(i) = *sub else { continue };
        let n = binary[i];
        node.cell[c] = if n.is_leaf() {
            if n.high() == 0 {
                continue;
            }
            leaf(n.data, n.high())
        } else {
            collapse_at(binary, i, out)
        };
        occupied |= 1 << c;
    }
    node.axis[7] = occupied;
    out[me] = node;
    me as Cell
}

/// Fills heap slot `slot` (planes 0-6; cells are slots 7-14) from binary node `at`.
fn place(
    binary: &[KdNode],
    at: Option<usize>,
    slot: usize,
    node: &mut KdNode8,
    cells: &mut [Option<usize>; 8],
) {
    if slot >= 7 {
        cells[slot - 7] = at;
        return;
    }
    match at.map(|i| (i, binary[i])) {
        Some((i, n)) if !n.is_leaf() => {
            node.split[slot] = n.split();
            node.axis[slot] = n.axis() as u32;
            place(binary, Some(i + 1), 2 * slot + 1, node, cells);
            place(binary, Some(n.high() as usize), 2 * slot + 2, node, cells);
        }
        _ => {
            node.split[slot] = f32::INFINITY;
            node.axis[slot] = 0;
            place(binary, at, 2 * slot + 1, node, cells);
            place(binary, None, 2 * slot + 2, node, cells);
        }
    }
}

/// A ray prepared for the node test: origin and reciprocal direction in lanes 0-2 (the lanes the
/// planes' axes pick).
pub struct RayPlanes {
    pub o: [f32; 8],
    pub inv: [f32; 8],
}

impl RayPlanes {
    /// From the ray's origin and reciprocal direction (already computed for the root's slab test).
    pub fn new(o: [f32; 3], inv: [f32; 3]) -> Self {
        Self {
            o: [o[0], o[1], o[2], 0.0, 0.0, 0.0, 0.0, 0.0],
            inv: [inv[0], inv[1], inv[2], 1.0, 1.0, 1.0, 1.0, 1.0],
        }
    }
}

/// The ray's interval in each occupied cell of `n`, clipped to `[t0, t1]`: returns the mask of
/// cells it crosses and writes their entry and exit distances. A NaN `t_split` (origin on the
/// plane, direction parallel to it) constrains neither side, so both are visited: it is taken as
/// the first operand of `max`/`min`, which keep the second when either is NaN, as the SIMD versions
/// do.
#[inline(always)]
pub fn cells_portable(
    n: &KdNode8,
    r: &RayPlanes,
    t0: f32,
    t1: f32,
    near: &mut [f32; 8],
    far: &mut [f32; 8],
) -> u32 {
    let mut ts = [0.0f32; 8];
    let mut flip = [false; 8];
    for k in 0..7 {
        let a = n.axis[k] as usize;
        ts[k] = (n.split[k] - r.o[a]) * r.inv[a];
        flip[k] = r.inv[a].is_sign_negative();
    }
    let mut mask = 0;
    for c in 0..8 {
        let (mut lo, mut hi) = (t0, t1);
        for level in 0..3 {
            let k = LEVEL_PLANE[level][c] as usize;
            let t = ts[k];
            // Below a plane, a ray with a positive direction is on `[-inf, t]`; a negative
            // direction or the above side flips it, both flip it back.
            if (LEVEL_SIDE[level][c] == 1) != flip[k] {
                lo = if t > lo { t } else { lo };
            } else {
                hi = if t < hi { t } else { hi };
            }
        }
        near[c] = lo;
        far[c] = hi;
        mask |= ((lo <= hi) as u32) << c;
    }
    mask & n.occupied()
}

/// [`cells_portable`] in AVX2, with the same operations per lane.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn cells_avx2(
    n: &KdNode8,
    r: &RayPlanes,
    t0: f32,
    t1: f32,
    near: &mut [f32; 8],
    far: &mut [f32; 8],
) -> u32 {
    use std::arch::x86_64::*;
    let axis = _mm256_load_si256(n.axis.as_ptr().cast());
    let o = _mm256_permutevar8x32_ps(_mm256_loadu_ps(r.o.as_ptr()), axis);
    let inv = _mm256_permutevar8x32_ps(_mm256_loadu_ps(r.inv.as_ptr()), axis);
    let ts = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.split.as_ptr()), o), inv);
    let mut lo = _mm256_set1_ps(t0);
    let mut hi = _mm256_set1_ps(t1);
    let neg_inf = _mm256_set1_ps(f32::NEG_INFINITY);
    let pos_inf = _mm256_set1_ps(f32::INFINITY);
    for level in 0..3 {
        let idx = _mm256_loadu_si256(LEVEL_PLANE[level].as_ptr().cast());
        let t = _mm256_permutevar8x32_ps(ts, idx);
        // The sign bit of `inv` for the lane's plane, flipped on the above side: set where the
        // cell begins at `t`, clear where it ends there.
        let side = _mm256_slli_epi32::<31>(_mm256_loadu_si256(LEVEL_SIDE[level].as_ptr().cast()));
        let starts = _mm256_xor_ps(
            _mm256_permutevar8x32_ps(inv, idx),
            _mm256_castsi256_ps(side),
        );
        lo = _mm256_max_ps(_mm256_blendv_ps(neg_inf, t, starts), lo);
        hi = _mm256_min_ps(_mm256_blendv_ps(t, pos_inf, starts), hi);
    }
    _mm256_storeu_ps(near.as_mut_ptr(), lo);
    _mm256_storeu_ps(far.as_mut_ptr(), hi);
    _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(lo, hi)) as u32 & n.occupied()
}
