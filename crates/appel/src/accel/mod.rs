//! Acceleration structures. Each builds over any [`Primitives`] (its builder sees only bounds and
//! centroids) and answers closest-hit and any-hit queries by calling back to intersect one primitive.
//! Every structure implements [`Structure`] and is listed once in `registry.rs`, from which
//! [`AccelKind`], [`AccelOptions`] and [`Accel`] (the enum the renderer holds: one match per ray, no
//! dynamic dispatch per node) are generated.

mod mailbox;
mod mesh_prims;
mod registry;
mod stats;
mod structure;
#[cfg(test)]
pub(crate) mod testutil;

pub use bsp::BspOptions;
pub use bvh::{BvhOptions, BvhSplit};
pub use grid::GridOptions;
pub use kdtree::{KdNode, KdOptions};
pub use mesh_prims::MeshPrimitives;
pub use octree::OctreeOptions;
use registry::define_structures;
pub(crate) use registry::for_each_structure;
pub use stats::{AccelStats, TraversalStats};
pub use structure::{same_name, BadOption, NoOptions, Structure};

for_each_structure!(define_structures);

use crate::geometry::PrimHit;
use crate::math::{Aabb, Ray, Vec3};

/// Structures of more bytes than this prefetch the nodes and leaves they push on their stacks: with
/// a tree far larger than the caches most visits wait for memory, and the prefetch overlaps that
/// wait with the nearer children's visits; small trees, which stay in the caches, only pay the
/// extra instructions (docs/performance.md records where the line was drawn).
pub(crate) const PREFETCH_BYTES: usize = 16 << 20;

/// Asks for the cache lines of `bytes` bytes at `p` to be brought into the cache. Never faults.
#[inline(always)]
pub(crate) fn prefetch<T>(p: *const T, bytes: usize) {
    #[cfg(target_arch = "x86_64")]
    for line in (0..bytes).step_by(64) {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: `_mm_prefetch` is part of SSE (every x86_64) and does not fault, whatever the
        // address.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>().wrapping_add(line)) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (p, bytes);
}

/// Whether the CPU has AVX2, detected once: the wide BVH and the kd-tree pick their traversal by it.
#[cfg(target_arch = "x86_64")]
pub(crate) fn has_avx2() -> bool {
    use std::sync::OnceLock;
    static AVX2: OnceLock<bool> = OnceLock::new();
    *AVX2.get_or_init(|| std::is_x86_feature_detected!("avx2"))
}

/// What an acceleration structure is built over. Builders see only bounds; where they need a
/// centroid they take the centre of the bounds (as Embree does).
pub trait Primitives: Sync {
    fn count(&self) -> usize;
    fn bounds(&self, i: usize) -> Aabb;
    /// Closest hit of primitive `i` with `t` in `(0, t_max)`.
    fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit>;
    /// Whether primitive `i` may overlap the box `cell` (which overlaps its bounds). Structures that
    /// put a primitive into every cell it touches ask this to skip cells only its bounds reach; the
    /// default, `true`, is always correct.
    fn clip_overlaps(&self, i: usize, cell: &Aabb) -> bool {
        let _ = (i, cell);
        true
    }
    /// Whether primitive `i` has any hit with `t` in `(0, t_max)`; structures ask this in their
    /// any-hit (shadow ray) queries. A primitive that holds a structure of its own (a mesh instance)
    /// can stop at its first hit instead of finding the closest.
    fn occluded(&self, i: usize, ray: &Ray, t_max: f32) -> bool {
        self.intersect(i, ray, t_max).is_some()
    }
    /// [`Self::intersect`], adding to `stats` the work of a primitive traced through a structure of
    /// its own (a mesh instance: its prototype's), which structures cannot see. The default has none.
    #[inline(always)]
    fn intersect_counted(
        &self,
        i: usize,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<PrimHit> {
        let _ = stats;
        self.intersect(i, ray, t_max)
    }
    /// [`Self::occluded`], counting as [`Self::intersect_counted`] does.
    #[inline(always)]
    fn occluded_counted(
        &self,
        i: usize,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> bool {
        let _ = stats;
        self.occluded(i, ray, t_max)
    }
    /// The vertices of primitive `i` if it is a triangle whose [`Primitives::intersect`] is exactly
    /// [`crate::geometry::triangle::watertight`] on them. Structures may then gather the vertices into SIMD
    /// blocks and test them without the call back; `None` (the default) always calls back.
    fn watertight_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
        let _ = i;
        None
    }
    /// The vertices of primitive `i` if it is a triangle whose [`Primitives::intersect`] is exactly
    /// [`crate::geometry::triangle::moller_trumbore`] on them: as [`Self::watertight_triangle`],
    /// for the other test. `None` (the default) always calls back.
    fn moller_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
        let _ = i;
        None
    }
    /// The closest hit among primitives `ids` in `(0, t_max)`, narrowing `t_max` at each nearer
    /// hit; with `ANY`, the first hit found (as [`test_primitive`] reports it). Structures ask this
    /// for a leaf of called-back primitives. The default tests them one by one; a set of
    /// primitives may override it to share per-ray work between the tests, with the same result.
    #[inline(always)]
    fn intersect_ids<const ANY: bool>(
        &self,
        ids: impl IntoIterator<Item = u32>,
        ray: &Ray,
        t_max: &mut f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit>
    where
        Self: Sized,
    {
        closest_of::<ANY>(ids, t_max, |id, t_max| {
            test_primitive::<Self, ANY>(self, id as usize, ray, t_max, stats)
        })
    }
    /// [`Self::intersect_ids`] of every primitive, in an order of the set's choosing (the hit is
    /// the same but for ties in `t`): what a structure that is a single leaf asks.
    #[inline(always)]
    fn intersect_all<const ANY: bool>(
        &self,
        ray: &Ray,
        t_max: &mut f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit>
    where
        Self: Sized,
    {
        self.intersect_ids::<ANY>(0..self.count() as u32, ray, t_max, stats)
    }
    /// [`Self::intersect_all`] of a packet of rays: lane `k` (where bit `k` of `active` is set)
    /// traces `rays[k]` against every primitive within its own `t_max[k]` (narrowed as
    /// `intersect_all` narrows it) into `out[k]`; inactive lanes are left alone. A leaf of
    /// everything is a packet's best case (Wald et al. 2001, "Interactive rendering with coherent
    /// ray tracing": each primitive's data is fetched once for the packet and tested on all its
    /// lanes at once). The default goes lane by lane; a set of primitives may override it with a
    /// SIMD test, with the same hits.
    #[inline(always)]
    fn intersect_all_packet<const ANY: bool>(
        &self,
        rays: &[Ray; LEAF_PACKET],
        active: u32,
        t_max: &mut [f32; LEAF_PACKET],
        out: &mut [Option<Hit>; LEAF_PACKET],
        stats: &mut TraversalStats,
    ) where
        Self: Sized,
    {
        for k in 0..LEAF_PACKET {
            if active & (1 << k) != 0 {
                out[k] = self.intersect_all::<ANY>(&rays[k], &mut t_max[k], stats);
            }
        }
    }
}

/// Rays in a packet of [`Primitives::intersect_all_packet`]: four f64 lanes of AVX2, the
/// precision in which spheres and rectangles are solved.
pub const LEAF_PACKET: usize = 4;

/// The loop of [`Primitives::intersect_ids`]: `test(id, t_max)` of each id in turn, keeping the
/// nearest hit (with `ANY`, stopping at the first).
#[inline(always)]
pub(crate) fn closest_of<const ANY: bool>(
    ids: impl IntoIterator<Item = u32>,
    t_max: &mut f32,
    mut test: impl FnMut(u32, f32) -> Option<PrimHit>,
) -> Option<Hit> {
    let mut best = None;
    for id in ids {
        if let Some(h) = test(id, *t_max) {
            best = Some(Hit::new(id as usize, h));
            if ANY {
                break;
            }
            *t_max = h.t;
        }
    }
    best
}

/// A structure's test of one primitive: its closest hit, or in an any-hit query (`ANY`) a stand-in
/// hit at `t_max` when [`Primitives::occluded`] says there is one (any-hit queries report only
/// whether). Work inside the primitive (an instance's structure) is added to `stats`.
#[inline(always)]
pub(crate) fn test_primitive<P: Primitives, const ANY: bool>(
    prims: &P,
    i: usize,
    ray: &Ray,
    t_max: f32,
    stats: &mut TraversalStats,
) -> Option<PrimHit> {
    if ANY {
        prims
            .occluded_counted(i, ray, t_max, stats)
            .then_some(PrimHit::any_hit(t_max))
    } else {
        prims.intersect_counted(i, ray, t_max, stats)
    }
}

/// A closest hit: which primitive, and where on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub prim: u32,
    pub t: f32,
    pub u: f32,
    pub v: f32,
    /// [`PrimHit::sub`]: the primitive hit inside primitive `prim` when that is a nested structure.
    pub sub: u32,
}

impl Hit {
    pub fn new(prim: usize, h: PrimHit) -> Self {
        Self {
            prim: prim as u32,
            t: h.t,
            u: h.u,
            v: h.v,
            sub: h.sub,
        }
    }
}

impl Default for AccelKind {
    fn default() -> Self {
        Self::Bvh
    }
}

impl Accel {
    /// A structure of `kind` with its default options.
    pub fn build<P: Primitives>(kind: AccelKind, prims: &P) -> Self {
        Self::build_with(kind, prims, &AccelOptions::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_bvh_is_the_default() {
        assert_eq!(
            AccelKind::NAMES,
            &["brute", "grid", "kdtree", "bvh", "octree", "bsp"]
        );
        for &n in AccelKind::NAMES {
            assert_eq!(AccelKind::from_name(n).unwrap().name(), n);
        }
        assert_eq!(AccelKind::from_name("bih"), None);
        assert_eq!(AccelKind::default(), AccelKind::Bvh);
    }

    /// Every registered structure's default options pass its own checks and read back the same
    /// from the TOML they write (a scene printed by `appel scenes --write` keeps its tables).
    #[test]
    fn default_options_are_valid_and_round_trip_through_toml() {
        fn check<S: Structure>() {
            let o = S::Options::default();
            assert_eq!(S::check_options(&o), Ok(()), "{}", S::NAME);
            let text = toml::to_string(&o).unwrap();
            let back: S::Options = toml::from_str(&text).unwrap();
            assert_eq!(back, o, "{}: {text}", S::NAME);
        }
        macro_rules! each {
            ($($Variant:ident($module:ident::$Type:ident)),* $(,)?) => {
                $(check::<$Type>();)*
            };
        }
        for_each_structure!(each);
    }

    /// Counts which question each structure asks a primitive.
    struct Asked<'a> {
        inner: MeshPrimitives<'a>,
        intersect: std::sync::atomic::AtomicUsize,
        occluded: std::sync::atomic::AtomicUsize,
    }

    impl Primitives for Asked<'_> {
        fn count(&self) -> usize {
            self.inner.count()
        }
        fn bounds(&self, i: usize) -> Aabb {
            self.inner.bounds(i)
        }
        fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit> {
            self.intersect
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            self.inner.intersect(i, ray, t_max)
        }
        fn occluded(&self, i: usize, ray: &Ray, t_max: f32) -> bool {
            self.occluded
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            self.inner.intersect(i, ray, t_max).is_some()
        }
    }

    /// Shadow rays ask `occluded` (so an instance can stop at its first hit), never `intersect`.
    #[test]
    fn any_hit_queries_ask_primitives_for_any_hit() {
        let m = testutil::soup(500, 2);
        for &n in AccelKind::NAMES {
            let p = Asked {
                // `Asked` gives no triangle vertices (it does not pass on
                // `moller_triangle`), so every structure calls each primitive back.
                inner: MeshPrimitives {
                    mesh: &m,
                    test: crate::geometry::TriangleTest::Moller,
                },
                intersect: Default::default(),
                occluded: Default::default(),
            };
            let a = Accel::build(AccelKind::from_name(n).unwrap(), &p);
            let mut s = TraversalStats::default();
            let blocked = testutil::rays(200, 4)
                .iter()
                .filter(|r| a.occluded(&p, r, f32::INFINITY, &mut s))
                .count();
            assert!(blocked > 20, "{n}: {blocked}");
            assert_eq!(
                p.intersect.load(std::sync::atomic::Ordering::Relaxed),
                0,
                "{n}"
            );
            assert!(p.occluded.load(std::sync::atomic::Ordering::Relaxed) >= blocked);
        }
    }

    #[test]
    fn accel_dispatches_to_the_structure_it_was_built_as() {
        let m = testutil::soup(200, 3);
        let p = testutil::prims(&m);
        for &n in AccelKind::NAMES {
            let a = Accel::build(AccelKind::from_name(n).unwrap(), &p);
            assert_eq!(a.stats().name, n);
            assert_eq!(a.stats().primitives, 200);
            let mut s = TraversalStats::default();
            let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
            a.intersect(&p, &r, f32::INFINITY, &mut s);
            a.occluded(&p, &r, f32::INFINITY, &mut s);
            assert_eq!(s.rays, 2);
        }
    }
}
