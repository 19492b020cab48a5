//! Closest-hit and any-hit queries over arrays of rays, written into the caller's arrays.

use super::{SceneHandle, MISS};
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
            Coords::F32(c) => c.iter().position(|x| !x.is_finite()).map(|i| i / 3),
            Coords::F64(c) => c.iter().position(|x| !x.is_finite()).map(|i| i / 3),
        }
    }
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
        let scene = self.read();
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(k, out)| {
            let mut stats = TraversalStats::default();
            for (j, o) in out.iter_mut().enumerate() {
                let i = k * CHUNK + j;
                let ray = Ray::new(origins.get(i), directions.get(i));
                *o = if tnear > 0.0 {
                    self.closest_beyond(&scene, &ray, tnear, tfar).is_some()
                } else {
                    scene.occluded(&ray, tfar, &mut stats)
                };
            }
        });
    }
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
