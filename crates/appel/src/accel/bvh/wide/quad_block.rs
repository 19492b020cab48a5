//! Two triangles that share an edge, stored once as the four vertices of their quad (the layout of
//! Embree's `Quad4v`, Wald et al. 2014): four pairs in a block of 208 bytes, where their eight
//! triangles take 320 in two [`TriBlock`](super::TriBlock)s, and three vertices to load per
//! triangle pair fewer.
//!
//! Only pairs whose second triangle is `(p0, p2, p3)` of the first's `(p0, p1, p2)` are stored so
//! (see `accel/bvh/pairs.rs`): the order in which a fan triangulates a quad (the OBJ and PLY
//! loaders, the generated scenes). Each triangle is then filtered and finished from exactly its
//! own vertices in its own order, so a block reports the very hits, bit for bit, that testing its
//! triangles one by one with [`crate::geometry::triangle::watertight`] reports.

#[cfg(target_arch = "x86_64")]
use super::simd;
use super::tri_block::{LaneValues, RayTri};
use crate::math::Vec3;

/// Set in [`QuadBlock::id`] where the lane holds the pair of triangles `id` and `id + 1`, clear
/// where it holds triangle `id` alone (or a primitive that is called back).
pub const PAIR: u32 = 1 << 31;
/// Set beside [`PAIR`] where the pair comes in the other order: `id` is `(p0, p2, p3)` and `id + 1`
/// is `(p0, p1, p2)` (the terrain of `appel gen ecosystem` is triangulated so).
pub const SWAP: u32 = 1 << 30;
/// The primitive id in a [`QuadBlock::id`] entry.
pub const ID: u32 = !(PAIR | SWAP);

/// Which of a lane's four vertices make its first (`CORNERS[0]`) and second triangle.
const CORNERS: [[usize; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

/// Four lanes, each a pair of triangles, a lone triangle (its fourth vertex a copy of its third,
/// never tested: [`QuadBlock::pair_mask`] masks it off) or a primitive that is called back (NaN
/// vertices). `v[3 * k + axis]` is coordinate `axis` of vertex `k`. A leaf's last block repeats
/// its lane 0 in its unused lanes, which traversal masks off by the leaf's count.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, bytemuck::Zeroable)]
pub struct QuadBlock {
    pub v: [[f32; 4]; 12],
    /// The lane's smaller primitive id, with [`PAIR`] set when it holds `id + 1` too, and
    /// [`SWAP`] when `id + 1` is its first triangle `(p0, p1, p2)` rather than its second.
    pub id: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<QuadBlock>() == 208);

impl QuadBlock {
    /// `lanes[i]` is a lane's first primitive id (with [`PAIR`] for a pair) and its vertices:
    /// four for a pair, the first three for a lone triangle, `None` for a primitive called back.
    /// Unused lanes repeat lane 0.
    pub fn new(lanes: &[(u32, Option<[Vec3; 4]>)]) -> Self {
        assert!(!lanes.is_empty() && lanes.len() <= 4);
        let mut b = QuadBlock {
            v: [[f32::NAN; 4]; 12],
            id: [0; 4],
        };
        for lane in 0..4 {
            let (id, quad) = lanes[if lane < lanes.len() { lane } else { 0 }];
            // SAFETY: `lane < 4`.
            unsafe { b.write_lane(lane, id, quad) };
        }
        b
    }

    /// Writes one lane through a raw pointer, so that threads may fill disjoint lanes of the same
    /// block (the builder's scatter). A lone triangle's fourth vertex is its third.
    ///
    /// # Safety
    /// `lane < 4`, `this` points into a live block, and no other thread touches this lane meanwhile.
    #[inline(always)]
    pub unsafe fn write_lane_raw(
        this: *mut QuadBlock,
        lane: usize,
        id: u32,
        quad: Option<[Vec3; 4]>,
    ) {
        std::ptr::addr_of_mut!((*this).id)
            .cast::<u32>()
            .add(lane)
            .write(id);
        let v = std::ptr::addr_of_mut!((*this).v).cast::<f32>();
        for k in 0..4 {
            for a in 0..3 {
                let x = quad.map_or(f32::NAN, |q| q[k][a]);
                v.add(4 * (3 * k + a) + lane).write(x);
            }
        }
    }

    /// # Safety
    /// `lane < 4`.
    #[inline(always)]
    unsafe fn write_lane(&mut self, lane: usize, id: u32, quad: Option<[Vec3; 4]>) {
        Self::write_lane_raw(self, lane, id, quad);
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

    /// Bit `lane` is set where the lane holds a pair.
    #[inline(always)]
    pub fn pair_mask(&self) -> u32 {
        // The sign bits of the ids, gathered by one instruction where there is SSE.
        #[cfg(target_arch = "x86_64")]
        // SAFETY: SSE is part of x86_64; `id` is 16-byte aligned (the block is).
        unsafe {
            use std::arch::x86_64::*;
            _mm_movemask_ps(_mm_load_ps(self.id.as_ptr().cast())) as u32
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            (0..4).map(|l| (self.id[l] >> 31) << l).sum()
        }
    }

    /// The primitive id of filter lane `bit` (bits 0-3 the lanes' first triangles, 4-7 their
    /// second).
    #[inline(always)]
    pub fn prim(&self, bit: usize) -> u32 {
        let id = self.id[bit & 3];
        (id & ID) + ((bit >> 2) as u32 ^ (id & SWAP) >> 30)
    }

    /// The triangle of filter lane `bit`, or `None` for a called-back primitive.
    #[inline(always)]
    pub fn triangle(&self, bit: usize) -> Option<[Vec3; 3]> {
        let lane = bit & 3;
        let v = |k: usize| {
            Vec3::new(
                self.v[3 * k][lane],
                self.v[3 * k + 1][lane],
                self.v[3 * k + 2][lane],
            )
        };
        let [a, b, c] = CORNERS[bit >> 2];
        let p0 = v(a);
        (!p0.x.is_nan()).then(|| [p0, v(b), v(c)])
    }

    /// Whether any lane holds a triangle.
    pub fn has_triangle(&self) -> bool {
        self.v[0].iter().any(|x| !x.is_nan())
    }
}

impl RayTri {
    /// The triangle filter of [`RayTri::candidates`] on a block of pairs: bit `lane` for the
    /// lane's first triangle, bit `4 + lane` for its second (whatever the lane holds: callers mask
    /// the second triangles by [`QuadBlock::pair_mask`]).
    #[inline(always)]
    pub fn candidates_quads(&self, q: &QuadBlock, t_max: f32, out: &mut LaneValues) -> u32 {
        #[cfg(target_arch = "x86_64")]
        {
            let first = self.quad_half_sse::<0>(q, t_max, out);
            // Lone triangles only: no second run.
            if q.pair_mask() == 0 {
                return first;
            }
            first | self.quad_half_sse::<1>(q, t_max, out) << 4
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let half = |h: usize| {
                let mut t = super::TriBlock::PADDING;
                for lane in 0..4 {
                    for (k, &c) in CORNERS[h].iter().enumerate() {
                        for a in 0..3 {
                            t.v[3 * k + a][lane] = q.v[3 * c + a][lane];
                        }
                    }
                }
                t
            };
            self.candidates_scalar_at(&half(0), t_max, out, 0)
                | self.candidates_scalar_at(&half(1), t_max, out, 4) << 4
        }
    }

    /// One half (`H`: the lanes' first or second triangles) in SSE, its values in lanes `4 H` to
    /// `4 H + 3` of `out`.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn quad_half_sse<const H: usize>(
        &self,
        q: &QuadBlock,
        t_max: f32,
        out: &mut LaneValues,
    ) -> u32 {
        // SAFETY: SSE and SSE2 are part of x86_64; the loads read 16-byte aligned rows
        // `3 c + axis < 12`, the stores write four floats at lane `4 H <= 4` of `[f32; 8]` rows.
        unsafe {
            use simd::sse::*;
            filter!(
                self,
                t_max,
                |k: usize, axis: usize| load(q.v.get_unchecked(3 * CORNERS[H][k] + axis).as_ptr()),
                |r: usize, v| store(out.row_ptr(r).add(4 * H), v)
            )
        }
    }

    /// [`Self::candidates_quads`] in one AVX filter run: the first triangles in lanes 0-3, the
    /// second in 4-7.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn candidates_quads_avx2(
        &self,
        q: &QuadBlock,
        t_max: f32,
        out: &mut LaneValues,
    ) -> u32 {
        use simd::avx::*;
        filter!(
            self,
            t_max,
            // SAFETY (the indexing): `3 c + axis < 12`.
            |k: usize, axis: usize| load2(
                q.v.get_unchecked(3 * CORNERS[1][k] + axis).as_ptr(),
                q.v.get_unchecked(3 * CORNERS[0][k] + axis).as_ptr()
            ),
            |r: usize, v| store(out.row_ptr(r), v)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::bvh::wide::tri_block::finish;
    use crate::geometry::triangle::watertight;
    use crate::math::Ray;

    fn lcg(s: &mut u64) -> f32 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*s >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }

    /// Every lane the scalar test hits survives the filter (SSE and AVX alike, which agree), and
    /// finishing a kept lane from the filter's values is the scalar test on that triangle, bit for
    /// bit, for pairs, lone triangles and rays through the shared edge.
    #[test]
    fn quad_filter_keeps_every_hit_and_finishes_like_the_scalar_test() {
        let mut s = 11u64;
        let (mut hits, mut second_hits) = (0, 0);
        for i in 0..20_000 {
            let p = |s: &mut u64| Vec3::new(lcg(s), lcg(s), lcg(s));
            let quads: Vec<[Vec3; 4]> = (0..4)
                .map(|_| [p(&mut s), p(&mut s), p(&mut s), p(&mut s)])
                .collect();
            let dir = match i % 5 {
                0 => Vec3::Y,
                1 => -Vec3::X,
                _ => p(&mut s),
            };
            // Some rays aimed at the shared edge's midpoint.
            let origin = p(&mut s) * 2.0;
            let dir = if i % 6 == 0 {
                (quads[1][0] + quads[1][2]) * 0.5 - origin
            } else {
                dir
            };
            let ray = Ray::new(origin, dir);
            let lanes: Vec<(u32, Option<[Vec3; 4]>)> = quads
                .iter()
                .enumerate()
                .map(|(k, q)| {
                    // Lane 3 a lone triangle.
                    let id = (10 * k as u32) | if k == 3 { 0 } else { PAIR };
                    (id, Some(*q))
                })
                .collect();
            let b = QuadBlock::new(&lanes);
            assert_eq!(b.pair_mask(), 0b0111);
            let rt = RayTri::new(&ray);
            let t_max = if i % 3 == 0 { 1.5 } else { f32::INFINITY };
            let mut vals = LaneValues::default();
            let mask = rt.candidates_quads(&b, t_max, &mut vals) & (0b1111 | b.pair_mask() << 4);
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                let mut avx_vals = LaneValues::default();
                // SAFETY: the CPU has AVX2.
                let avx = unsafe { rt.candidates_quads_avx2(&b, t_max, &mut avx_vals) };
                assert_eq!(avx & (0b1111 | b.pair_mask() << 4), mask);
            }
            for bit in 0..8 {
                if bit >= 4 && b.pair_mask() & (1 << (bit - 4)) == 0 {
                    continue;
                }
                let tri = b.triangle(bit).unwrap();
                let q = quads[bit & 3];
                let want_tri = if bit < 4 {
                    [q[0], q[1], q[2]]
                } else {
                    [q[0], q[2], q[3]]
                };
                assert_eq!(tri, want_tri);
                assert_eq!(b.prim(bit), 10 * (bit as u32 & 3) + (bit as u32 >> 2));
                let want = watertight(&ray, t_max, tri[0], tri[1], tri[2]);
                if want.is_some() {
                    hits += 1;
                    second_hits += (bit >= 4) as usize;
                    assert!(
                        mask & (1 << bit) != 0,
                        "ray {i} bit {bit}: hit filtered out"
                    );
                }
                if mask & (1 << bit) != 0 {
                    // SAFETY: the filter kept `bit`.
                    let got = unsafe { finish(&vals, bit, tri, &ray, t_max) };
                    assert_eq!(got, want, "ray {i} bit {bit}");
                }
            }
        }
        assert!(hits > 1000 && second_hits > 300, "{hits} {second_hits}");
    }

    #[test]
    fn padding_repeats_lane_zero_and_called_back_lanes_are_nan() {
        let q = [Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y];
        let b = QuadBlock::new(&[(5 | PAIR, Some(q)), (9, None), (12 | PAIR | SWAP, Some(q))]);
        assert_eq!(b.id, [5 | PAIR, 9, 12 | PAIR | SWAP, 5 | PAIR]);
        assert_eq!(b.pair_mask(), 0b1101);
        assert_eq!(b.triangle(1), None);
        assert_eq!(b.triangle(4), Some([q[0], q[2], q[3]]));
        assert_eq!([b.prim(0), b.prim(4), b.prim(1)], [5, 6, 9]);
        // Swapped: the first triangle `(p0, p1, p2)` is the later id.
        assert_eq!([b.prim(2), b.prim(6)], [13, 12]);
        assert!(b.has_triangle());
        assert!(!QuadBlock::new(&[(1, None)]).has_triangle());
    }
}
