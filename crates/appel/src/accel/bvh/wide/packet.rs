//! Packets of eight rays through the 8-wide BVH: each node is fetched once for the packet and each
//! child's box is tested against all eight rays in one AVX2 slab test (ray-parallel, the transpose
//! of the single-ray path's child-parallel test), as in Wald, Slusallek, Benthin & Wagner 2001,
//! "Interactive rendering with coherent ray tracing", with Embree's per-ray masks of active rays
//! (Wald et al. 2014).
//!
//! Single-ray traversal stays the reference, and the packet's answers are its answers:
//! - A packet is traversed together only when its rays share a direction octant (the sign bits of
//!   all three components), so every ray picks the same near and far planes as it would alone, and
//!   each (ray, child) slab test runs exactly the single-ray test's operations in its order. Other
//!   packets, trees of one leaf, CPUs without AVX2 and trees deeper than the packet stack go ray by
//!   ray.
//! - Leaves are tested ray by ray with the single-ray leaf test (triangle filter and `finish`), and
//!   a child waiting on the stack is visited only by the rays whose entry distance is within their
//!   own current cull distance, the single-ray pop test. The closest hit is therefore the one the
//!   single ray finds, except that of two primitives hit at exactly the same `t` the one tested
//!   first wins, and the packet may visit them in another order.

use super::WideBvh;
use crate::accel::{Hit, Primitives, TraversalStats};
use crate::math::Ray;
#[cfg(target_arch = "x86_64")]
use {
    super::mt_block::LaneTest,
    super::node::{self, Child},
    super::traverse::{stack_need, BLOCKS, MOLLER, PAIRS},
    super::tri_block::RayTri,
    crate::accel::has_avx2,
    crate::math::far_scale,
    std::mem::MaybeUninit,
};

/// Rays per packet.
pub const PACKET: usize = 8;

/// Stack entries of a packet traversal; deeper trees go ray by ray.
#[cfg(target_arch = "x86_64")]
const STACK: usize = 128;

/// A subtree reached by fewer active rays than this is traversed ray by ray: for one or two rays
/// the packet's eight-lane tests cost more than single-ray ones, while a higher threshold gives
/// up sharing that still pays (docs/performance.md records the sweep).
#[cfg(target_arch = "x86_64")]
const SHARED: u32 = 3;

impl WideBvh<8> {
    /// Whether packets can take the packet path at all (a tree of more than one leaf with triangle
    /// blocks rather than compact leaves, not deeper than the packet stack, on a CPU with AVX2).
    pub fn has_packets(&self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            self.root_leaf.is_none()
                && !self.compact()
                && !self.nodes.is_empty()
                && stack_need::<8>(self.depth) <= STACK
                && has_avx2()
        }
        #[cfg(not(target_arch = "x86_64"))]
        false
    }

    /// Closest hits of up to [`PACKET`] rays in `(0, t_max)`, into `out[i]` for `rays[i]`: the hits
    /// of [`WideBvh::traverse`] on each ray (see the module's notes on ties).
    pub fn intersect_packet<P: Primitives>(
        &self,
        prims: &P,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<Hit>],
        stats: &mut TraversalStats,
    ) {
        assert!(rays.len() <= PACKET && out.len() >= rays.len());
        // SAFETY: `has_packets` checked for AVX2.
        #[cfg(target_arch = "x86_64")]
        if !rays.is_empty() && self.has_packets() {
            let done = if self.test == LaneTest::Moller {
                unsafe { self.packet_avx2::<P, MOLLER>(prims, rays, t_max, out, stats) }
            } else if self.quads.is_empty() {
                unsafe { self.packet_avx2::<P, BLOCKS>(prims, rays, t_max, out, stats) }
            } else {
                unsafe { self.packet_avx2::<P, PAIRS>(prims, rays, t_max, out, stats) }
            };
            if done {
                return;
            }
        }
        for (ray, o) in rays.iter().zip(out.iter_mut()) {
            *o = self.traverse::<P, false>(prims, ray, t_max, stats);
        }
    }

    /// The packet traversal, or `false` (having done nothing) when the rays' directions do not
    /// all share one octant.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn packet_avx2<P: Primitives, const LEAVES: u8>(
        &self,
        prims: &P,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<Hit>],
        stats: &mut TraversalStats,
    ) -> bool {
        use super::simd::avx::*;
        use std::arch::x86_64::{_mm256_div_ps, _mm256_movemask_ps};
        let n = rays.len();
        // Structure of arrays; unused lanes repeat ray 0 and are never active.
        let r0 = rays[0];
        let mut o = [
            [r0.origin.x; PACKET],
            [r0.origin.y; PACKET],
            [r0.origin.z; PACKET],
        ];
        let mut dir = [[r0.dir.x; PACKET], [r0.dir.y; PACKET], [r0.dir.z; PACKET]];
        for (i, r) in (0..PACKET).zip(rays) {
            (o[0][i], o[1][i], o[2][i]) = (r.origin.x, r.origin.y, r.origin.z);
            (dir[0][i], dir[1][i], dir[2][i]) = (r.dir.x, r.dir.y, r.dir.z);
        }
        let dv = dir.map(|x| loadu(x.as_ptr()));
        // One octant: every axis's sign bits (so `-0` counts as negative, as in the single-ray
        // test's choice of planes) all clear or all set.
        let signs = dv.map(|x| _mm256_movemask_ps(x) as u32);
        if signs.iter().any(|&m| m != 0 && m != 0xff) {
            return false;
        }
        stats.rays += n as u64;
        let ov = o.map(|x| loadu(x.as_ptr()));
        // The single-ray set-up's `1 / d` (`RayBoxes::new`), eight lanes per division: IEEE
        // division is correctly rounded, so the lanes hold the same bits.
        let iv = dv.map(|x| _mm256_div_ps(splat(1.0), x));
        // Near and far rows of every axis, from the octant all rays share.
        let neg = signs.map(|m| (m & 1) as usize);
        let near = [neg[0], 2 + neg[1], 4 + neg[2]];
        let far_row = [1 - neg[0], 3 - neg[1], 5 - neg[2]];
        let far = far_scale();
        // The far planes' reciprocals carry the Ize scale, as in the single-ray `RayBoxes`.
        let ivf = iv.map(|x| mul(x, splat(far)));
        let mut t_max_of = [t_max; PACKET];
        let mut t_cull = [t_max * far; PACKET];
        let mut best: [Option<Hit>; PACKET] = [None; PACKET];
        let mut rt: [Option<RayTri>; PACKET] = [None; PACKET];
        let mut stack = [const { MaybeUninit::<Entry>::uninit() }; STACK];
        let mut sp = 0usize;
        let mut cur: Child = 0;
        let mut active: u32 = (1u32 << n) - 1;
        // Per node: the children hit by at least one active ray, as (sort key, lane), their ray
        // masks and entry distances (declared once: only the first `k` entries are read).
        let mut hit: [(f32, usize); 8] = [(0.0, 0); 8];
        let mut masks = [0u32; 8];
        let mut dists = [[0.0f32; PACKET]; 8];
        'outer: loop {
            if !node::is_leaf(cur) && active.count_ones() < SHARED {
                // Too few rays left to share node visits: each goes on alone through this subtree
                // with the single-ray traversal, from its best hit so far (the hybrid scheme of
                // Benthin, Wald, Woop, Ernst & Mark 2012).
                let mut m = active;
                while m != 0 {
                    let i = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let h = self.traverse_from::<P, false, true, LEAVES, STACK>(
                        cur,
                        prims,
                        &rays[i],
                        t_max_of[i],
                        stats,
                    );
                    if let Some(h) = h {
                        best[i] = Some(h);
                        t_max_of[i] = h.t;
                        t_cull[i] = h.t * far;
                    }
                }
            } else if !node::is_leaf(cur) {
                let nd = &self.nodes[cur as usize];
                stats.nodes_visited += active.count_ones() as u64;
                let cull = loadu(t_cull.as_ptr());
                let mut k = 0;
                for c in 0..8 {
                    if nd.child[c] == node::EMPTY {
                        continue;
                    }
                    // The single-ray slab test (`slab_lanes!`), one child against eight rays.
                    let mut t0 = splat(0.0);
                    let mut t1 = cull;
                    for a in 0..3 {
                        let lo = splat(nd.bounds[near[a]][c]);
                        let hi = splat(nd.bounds[far_row[a]][c]);
                        t0 = max(mul(sub(lo, ov[a]), iv[a]), t0);
                        t1 = min(mul(sub(hi, ov[a]), ivf[a]), t1);
                    }
                    let m = mask(le(t0, t1)) & active;
                    if m != 0 {
                        store(dists[k].as_mut_ptr(), t0);
                        // Ordered by the entry distance of the packet's first ray that hits it:
                        // coherent rays agree on the order of a node's children.
                        hit[k] = (dists[k][m.trailing_zeros() as usize], c);
                        masks[k] = m;
                        k += 1;
                    }
                }
                if k > 0 {
                    // Farthest first onto the stack, so the nearest is visited next (insertion
                    // sort: at most eight keys).
                    let mut order = [0usize; 8];
                    for i in 1..k {
                        let mut j = i;
                        while j > 0 && hit[order[j - 1]].0 < hit[i].0 {
                            order[j] = order[j - 1];
                            j -= 1;
                        }
                        order[j] = i;
                    }
                    for &i in &order[..k - 1] {
                        stack[sp] = MaybeUninit::new(Entry {
                            child: nd.child[hit[i].1],
                            mask: masks[i],
                            dist: dists[i],
                        });
                        sp += 1;
                    }
                    let i = order[k - 1];
                    cur = nd.child[hit[i].1];
                    active = masks[i];
                    continue;
                }
            } else {
                let mut m = active;
                while m != 0 {
                    let i = m.trailing_zeros() as usize;
                    m &= m - 1;
                    self.leaf::<P, false, true, LEAVES>(
                        cur,
                        &mut rt[i],
                        prims,
                        &rays[i],
                        &mut t_max_of[i],
                        &mut best[i],
                        stats,
                    );
                    t_cull[i] = t_max_of[i] * far;
                }
            }
            // Pop the nearest waiting child that some ray can still find a nearer hit in.
            loop {
                if sp == 0 {
                    break 'outer;
                }
                sp -= 1;
                // SAFETY: entries below `sp` were written before.
                let e = unsafe { stack[sp].assume_init_ref() };
                let m = e.mask & mask(le(loadu(e.dist.as_ptr()), loadu(t_cull.as_ptr())));
                if m != 0 {
                    cur = e.child;
                    active = m;
                    break;
                }
            }
        }
        out[..n].copy_from_slice(&best[..n]);
        true
    }
}

#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct Entry {
    child: Child,
    mask: u32,
    /// Each ray's entry distance into the child's box.
    dist: [f32; PACKET],
}

/// Whether all rays' directions have the same sign bits (so `-0` and `+0` differ, as in the
/// single-ray test's choice of planes): the tests' independent statement of the packet condition.
#[cfg(test)]
fn one_octant(rays: &[Ray]) -> bool {
    let signs = |r: &Ray| {
        let d = r.dir;
        (d.x.to_bits() >> 31) | (d.y.to_bits() >> 31) << 1 | (d.z.to_bits() >> 31) << 2
    };
    let s0 = signs(&rays[0]);
    rays.iter().all(|r| signs(r) == s0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::testutil::{mesh, prims, soup, Rng};
    use crate::accel::{Brute, Bvh};
    use crate::math::Vec3;

    /// Camera-like packets: eight neighbouring directions through a pinhole, in every octant, plus
    /// packets that straddle an axis (mixed octants, which go ray by ray).
    fn packets(seed: u32) -> Vec<Vec<Ray>> {
        let mut r = Rng(seed);
        let mut out = vec![];
        for k in 0..400 {
            let eye = r.v(-3.0, 3.0) * 1.5;
            let target = r.v(-0.8, 0.8);
            let fwd = (target - eye).normalize();
            let side = fwd.cross(Vec3::Y).normalize();
            // Straddling packets cross the plane where a direction component changes sign.
            let spread = if k % 10 == 0 { 0.5 } else { 0.004 };
            let start = r.f() - 0.5;
            out.push(
                (0..PACKET)
                    .map(|i| {
                        let s = (start + i as f32 * spread) * 0.3;
                        Ray::new(eye, fwd + s * side)
                    })
                    .collect(),
            );
        }
        out
    }

    fn wide8(bvh: &Bvh) -> &WideBvh<8> {
        match &bvh.wide {
            crate::accel::bvh::Wide::W8(w) => w,
            _ => panic!("not 8 wide"),
        }
    }

    /// Every ray of a packet gets the single-ray traversal's hit, bit for bit, and brute force's
    /// distance; most packets take the packet path, and they hit something.
    #[test]
    fn packets_agree_with_single_rays_and_brute_force() {
        let m = soup(4000, 31);
        let p = prims(&m);
        let bvh = Bvh::build(&p);
        let w = wide8(&bvh);
        assert!(w.root_leaf.is_none());
        let brute = Brute::build(&p);
        let (mut hits, mut together, mut ties) = (0, 0, 0);
        for packet in packets(32) {
            if one_octant(&packet) {
                together += 1;
            }
            for t_max in [f32::INFINITY, 2.5] {
                let mut out = [None; PACKET];
                let mut s = TraversalStats::default();
                w.intersect_packet(&p, &packet, t_max, &mut out, &mut s);
                assert_eq!(s.rays, PACKET as u64);
                for (ray, got) in packet.iter().zip(out) {
                    let mut s = TraversalStats::default();
                    let single = w.traverse::<_, false>(&p, ray, t_max, &mut s);
                    let exact = brute.intersect(&p, ray, t_max, &mut s);
                    assert_eq!(got.map(|h| h.t), exact.map(|h| h.t), "{ray:?}");
                    if got != single {
                        // Only an exact tie may differ: both primitives hit at the same `t`.
                        let (g, s) = (got.unwrap(), single.unwrap());
                        assert_eq!(g.t, s.t);
                        ties += 1;
                    }
                    hits += got.is_some() as usize;
                }
            }
        }
        assert!(together > 300, "{together}");
        assert!(hits > 1000, "{hits}");
        assert!(ties < 3, "{ties}");
    }

    /// Short packets, a tree of one leaf and rays along the axes (zero components of both signs).
    #[test]
    fn short_packets_single_leaves_and_axis_rays() {
        let m = soup(2000, 41);
        let p = prims(&m);
        let bvh = Bvh::build(&p);
        let w = wide8(&bvh);
        let axis: Vec<Ray> = (0..5)
            .map(|i| Ray::new(Vec3::new(-0.5 + 0.2 * i as f32, 0.1, -3.0), Vec3::Z))
            .collect();
        let mut out = [None; PACKET];
        let mut s = TraversalStats::default();
        w.intersect_packet(&p, &axis, f32::INFINITY, &mut out, &mut s);
        for (ray, got) in axis.iter().zip(out) {
            assert_eq!(got, w.traverse::<_, false>(&p, ray, f32::INFINITY, &mut s));
        }
        assert!(out[5..].iter().all(|h| h.is_none()));
        let tiny = mesh(vec![[Vec3::ZERO, Vec3::X, Vec3::Y]]);
        let tp = prims(&tiny);
        let one = Bvh::build(&tp);
        let ray = Ray::new(Vec3::new(0.2, 0.2, -1.0), Vec3::Z);
        let mut out = [None; PACKET];
        wide8(&one).intersect_packet(&tp, &[ray; 3], f32::INFINITY, &mut out, &mut s);
        assert!(out[..3].iter().all(|h| h.is_some_and(|h| h.t == 1.0)));
    }
}
