//! Closest-hit and any-hit queries over arrays of rays, written into the caller's arrays.

use super::{SceneHandle, MISS};
use crate::accel::bvh::PACKET;
use crate::accel::TraversalStats;
use crate::math::{Ray, Vec3};
use crate::scene::{Scene, SceneHit};
use rayon::prelude::*;

/// Points or vectors, `x, y, z` after one another, in f32 or f64 (converted to f32, as the
/// renderer's rays are).
#[derive(Clone, Copy, Debug)]
pub enum Coords<'a> {
    F32(&'a [f32]),
    F64(&'a [f64]),
}

impl Coords<'_> {
    pub fn len(&self) -> usize {
        match self {
            Coords::F32(c) => c.len() / 3,
            Coords::F64(c) => c.len() / 3,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    #[inline]
    pub fn get(&self, i: usize) -> Vec3 {
        match self {
            Coords::F32(c) => Vec3::new(c[3 * i], c[3 * i + 1], c[3 * i + 2]),
            Coords::F64(c) => Vec3::new(c[3 * i] as f32, c[3 * i + 1] as f32, c[3 * i + 2] as f32),
        }
    }

    /// The index of the first non-finite coordinate's point, if any.
    pub fn first_non_finite(&self) -> Option<usize> {
        match self {
            Coords::F32(c) => first_point_where(c, |x| !x.is_finite()),
            Coords::F64(c) => first_point_where(c, |x| !x.is_finite()),
        }
    }

    /// The index of the first point with a NaN coordinate, if any.
    pub fn first_nan(&self) -> Option<usize> {
        match self {
            Coords::F32(c) => first_point_where(c, |x| x.is_nan()),
            Coords::F64(c) => first_point_where(c, |x| x.is_nan()),
        }
    }
}

/// The point (three coordinates) holding the first coordinate for which `bad` holds. Every array
/// of rays is scanned before it is traced, so blocks are tested without an early exit, which
/// the compiler vectorizes; `position` stopping at each element is several times slower.
#[inline]
fn first_point_where<T: Copy>(c: &[T], bad: impl Fn(T) -> bool) -> Option<usize> {
    const BLOCK: usize = 3 * 64;
    c.chunks(BLOCK).enumerate().find_map(|(k, b)| {
        b.iter()
            .fold(false, |any, &x| any | bad(x))
            .then(|| (k * BLOCK + b.iter().position(|&x| bad(x)).unwrap_or(0)) / 3)
    })
}

/// Where the closest hits go: one entry per ray (`uv` two, `normal` and `position` three).
pub struct RayHits<'a> {
    pub t: &'a mut [f32],
    pub prim_ids: &'a mut [u32],
    pub shape_ids: &'a mut [u32],
    pub instance_ids: &'a mut [u32],
    pub uv: &'a mut [f32],
    pub normal: &'a mut [f32],
    pub position: &'a mut [f32],
}

/// Where the closest hits of [`SceneHandle::intersect_geometric`] go: those of [`RayHits`] that
/// the traversal itself gives, and the unit geometric normal only when asked for.
pub struct GeometricHits<'a> {
    pub t: &'a mut [f32],
    pub prim_ids: &'a mut [u32],
    pub shape_ids: &'a mut [u32],
    pub instance_ids: &'a mut [u32],
    pub uv: &'a mut [f32],
    pub normal: Option<&'a mut [f32]>,
}

/// A coordinate as the caller's array holds it; rays are traced in f32.
trait Coord: Copy + Send + Sync {
    fn f32(self) -> f32;
}

impl Coord for f32 {
    #[inline(always)]
    fn f32(self) -> f32 {
        self
    }
}

impl Coord for f64 {
    #[inline(always)]
    fn f32(self) -> f32 {
        self as f32
    }
}

#[inline(always)]
fn vec3<C: Coord>(c: &[C]) -> Vec3 {
    Vec3::new(c[0].f32(), c[1].f32(), c[2].f32())
}

/// `$call` with `$o` and `$d` bound to the coordinates' slices in their own types: one
/// instance of the loop per pair of types, so that no ray pays for a match on them.
macro_rules! typed {
    ($origins:expr, $directions:expr, |$o:ident, $d:ident| $call:expr) => {{
        use Coords::{F32, F64};
        match ($origins, $directions) {
            (F32($o), F32($d)) => $call,
            (F32($o), F64($d)) => $call,
            (F64($o), F32($d)) => $call,
            (F64($o), F64($d)) => $call,
        }
    }};
}

/// Rays per parallel task.
const CHUNK: usize = 1024;

impl SceneHandle {
    /// The closest hit of each ray in `(tnear, tfar)` (`t` in units of the direction's length):
    /// `t` (inf on a miss), the `primid`, `shapeid` and `instanceid` AOVs' ids ([`MISS`] on a
    /// miss), the hit's surface parameters (barycentric for triangles), the unit geometric normal
    /// and the hit point.
    pub fn intersect(
        &self,
        origins: Coords,
        directions: Coords,
        tnear: f32,
        tfar: f32,
        out: RayHits,
    ) {
        let scene = self.read();
        let chunks: Vec<RayHits> = split(out);
        chunks.into_par_iter().enumerate().for_each(|(k, mut c)| {
            let mut stats = TraversalStats::default();
            for j in 0..c.t.len() {
                let i = k * CHUNK + j;
                let ray = Ray::new(origins.get(i), directions.get(i));
                let hit = if tnear > 0.0 {
                    self.closest_beyond(&scene, &ray, tnear, tfar)
                } else {
                    scene.intersect(&ray, tfar, &mut stats)
                };
                write_hit(&scene, &ray, hit, j, &mut c);
            }
        });
    }

    /// Whether anything lies on each ray in `(tnear, tfar)`.
    pub fn occluded(
        &self,
        origins: Coords,
        directions: Coords,
        tnear: f32,
        tfar: f32,
        out: &mut [bool],
    ) {
        typed!(origins, directions, |o, d| self
            .occluded_typed(o, d, tnear, tfar, out))
    }

    fn occluded_typed<A: Coord, B: Coord>(
        &self,
        origins: &[A],
        directions: &[B],
        tnear: f32,
        tfar: f32,
        out: &mut [bool],
    ) {
        let scene = self.read();
        let scene = &*scene;
        origins
            .par_chunks(3 * CHUNK)
            .zip(directions.par_chunks(3 * CHUNK))
            .zip(out.par_chunks_mut(CHUNK))
            .for_each(|((o, d), out)| {
                let mut stats = TraversalStats::default();
                let rays = o.chunks_exact(3).zip(d.chunks_exact(3));
                for ((o, d), out) in rays.zip(out) {
                    let ray = Ray::new(vec3(o), vec3(d));
                    *out = if tnear > 0.0 {
                        self.closest_beyond(scene, &ray, tnear, tfar).is_some()
                    } else {
                        scene.occluded(&ray, tfar, &mut stats)
                    };
                }
            });
    }
}

impl SceneHandle {
    /// The closest hit of each ray in `(tnear, tfar)`, as [`Self::intersect`] finds it, with only
    /// what the traversal gives: `t`, the three ids and the barycentrics (the unit geometric
    /// normal too when `out.normal` is given). Without the surface interaction and with the
    /// coordinates read in their own type, it costs little more than the traversal.
    pub fn intersect_geometric(
        &self,
        origins: Coords,
        directions: Coords,
        tnear: f32,
        tfar: f32,
        out: GeometricHits,
    ) {
        typed!(origins, directions, |o, d| self
            .geometric_hits(o, d, tnear, tfar, out))
    }

    fn geometric_hits<A: Coord, B: Coord>(
        &self,
        origins: &[A],
        directions: &[B],
        tnear: f32,
        tfar: f32,
        out: GeometricHits,
    ) {
        let scene = self.read();
        let scene = &*scene;
        let packets = scene.accel.has_packets();
        let GeometricHits {
            t,
            prim_ids,
            shape_ids,
            instance_ids,
            uv,
            normal,
        } = out;
        let chunks = origins
            .par_chunks(3 * CHUNK)
            .zip(directions.par_chunks(3 * CHUNK))
            .zip(t.par_chunks_mut(CHUNK))
            .zip(prim_ids.par_chunks_mut(CHUNK))
            .zip(shape_ids.par_chunks_mut(CHUNK))
            .zip(instance_ids.par_chunks_mut(CHUNK))
            .zip(uv.par_chunks_mut(2 * CHUNK));
        let trace = |o: &[A],
                     d: &[B],
                     t: &mut [f32],
                     p: &mut [u32],
                     s: &mut [u32],
                     i: &mut [u32],
                     uv: &mut [f32],
                     n: Option<&mut [f32]>| {
            let mut stats = TraversalStats::default();
            let mut n = n;
            let groups = o.chunks(3 * PACKET).zip(d.chunks(3 * PACKET));
            for (k, (o, d)) in groups.enumerate() {
                let mut rays = [Ray::new(Vec3::ZERO, Vec3::ZERO); PACKET];
                let rays = &mut rays[..o.len() / 3];
                for (r, (o, d)) in rays
                    .iter_mut()
                    .zip(o.chunks_exact(3).zip(d.chunks_exact(3)))
                {
                    *r = Ray::new(vec3(o), vec3(d));
                }
                let mut hits = [None; PACKET];
                let hits = &mut hits[..rays.len()];
                if tnear > 0.0 {
                    for (ray, h) in rays.iter().zip(hits.iter_mut()) {
                        *h = self.closest_beyond(scene, ray, tnear, tfar);
                    }
                } else if packets && coherent(rays) {
                    scene.intersect_coherent(rays, tfar, hits, &mut stats);
                } else {
                    for (ray, h) in rays.iter().zip(hits.iter_mut()) {
                        *h = scene.intersect(ray, tfar, &mut stats);
                    }
                }
                for (j, (ray, hit)) in rays.iter().zip(hits.iter()).enumerate() {
                    let j = k * PACKET + j;
                    match hit {
                        None => {
                            t[j] = f32::INFINITY;
                            (p[j], s[j], i[j]) = (MISS, MISS, MISS);
                            uv[2 * j..2 * j + 2].copy_from_slice(&[0.0; 2]);
                            if let Some(n) = n.as_deref_mut() {
                                n[3 * j..3 * j + 3].copy_from_slice(&[0.0; 3]);
                            }
                        }
                        Some(h) => {
                            let (shape, prim) = scene.geometry.source_ids(h);
                            t[j] = h.t;
                            (p[j], s[j], i[j]) = (prim, shape, h.instance);
                            uv[2 * j..2 * j + 2].copy_from_slice(&[h.u, h.v]);
                            if let Some(n) = n.as_deref_mut() {
                                let g = scene.geometry.geometric_normal(ray, h);
                                n[3 * j..3 * j + 3].copy_from_slice(&g.to_array());
                            }
                        }
                    }
                }
            }
        };
        match normal {
            Some(normal) => chunks.zip(normal.par_chunks_mut(3 * CHUNK)).for_each(
                |(((((((o, d), t), p), s), i), uv), n)| trace(o, d, t, p, s, i, uv, Some(n)),
            ),
            None => chunks
                .for_each(|((((((o, d), t), p), s), i), uv)| trace(o, d, t, p, s, i, uv, None)),
        }
    }
}

/// Whether rays look like a camera's (one origin, directions in one octant): such rays are
/// traced in packets, which give the same hits as single rays and cost less when the rays stay
/// together through the tree; rays from different origins would part at once.
#[inline]
fn coherent(rays: &[Ray]) -> bool {
    let first = rays[0];
    let octant = first.dir.is_negative_bitmask();
    rays.len() > 1
        && rays
            .iter()
            .all(|r| r.origin == first.origin && r.dir.is_negative_bitmask() == octant)
}

/// The outputs cut into chunks of [`CHUNK`] rays, one per parallel task.
fn split(out: RayHits) -> Vec<RayHits> {
    let RayHits {
        t,
        prim_ids,
        shape_ids,
        instance_ids,
        uv,
        normal,
        position,
    } = out;
    t.chunks_mut(CHUNK)
        .zip(prim_ids.chunks_mut(CHUNK))
        .zip(shape_ids.chunks_mut(CHUNK))
        .zip(instance_ids.chunks_mut(CHUNK))
        .zip(uv.chunks_mut(2 * CHUNK))
        .zip(normal.chunks_mut(3 * CHUNK))
        .zip(position.chunks_mut(3 * CHUNK))
        .map(
            |((((((t, prim_ids), shape_ids), instance_ids), uv), normal), position)| RayHits {
                t,
                prim_ids,
                shape_ids,
                instance_ids,
                uv,
                normal,
                position,
            },
        )
        .collect()
}

/// Fills entry `j` of chunk `c`.
fn write_hit(scene: &Scene, ray: &Ray, hit: Option<SceneHit>, j: usize, c: &mut RayHits) {
    let (t, prim, shape, instance, uv, n, p) = match hit {
        None => (
            f32::INFINITY,
            MISS,
            MISS,
            MISS,
            [0.0; 2],
            [0.0; 3],
            [f32::NAN; 3],
        ),
        Some(h) => {
            let (shape, prim) = scene.geometry.source_ids(&h);
            let si = scene.geometry.interaction_with(ray, &h, false);
            (
                h.t,
                prim,
                shape,
                h.instance,
                [h.u, h.v],
                si.n.into(),
                si.p.into(),
            )
        }
    };
    c.t[j] = t;
    c.prim_ids[j] = prim;
    c.shape_ids[j] = shape;
    c.instance_ids[j] = instance;
    c.uv[2 * j..2 * j + 2].copy_from_slice(&uv);
    c.normal[3 * j..3 * j + 3].copy_from_slice(&n);
    c.position[3 * j..3 * j + 3].copy_from_slice(&p);
}
