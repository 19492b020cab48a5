//! Every hit along a ray, in one traversal: a structure built over the scene's primitives with
//! every one called back (no triangles gathered into the structure's own blocks), queried with a
//! set of primitives that records each hit and answers "no hit", so the traversal never narrows
//! its interval and visits every node the ray passes through. An instance is collected the same
//! way through a callback structure of its prototype. The same structures answer closest hits
//! beyond a `tnear`, which the renderer's structures (hits in `(0, t_max)`) cannot.

use super::rays::Coords;
use super::{SceneHandle, MISS};
use crate::accel::{Accel, AccelKind, AccelOptions, BvhOptions, Hit, Primitives, TraversalStats};
use crate::geometry::PrimHit;
use crate::math::{offset_ray_origin, Aabb, Ray};
use crate::scene::{Geometry, Scene, SceneHit, ShapeKind};
use rayon::prelude::*;
use std::sync::Mutex;

/// Hits one analytic primitive may report along a ray (a torus has four, an implicit surface
/// more; the rest is cut off).
const MAX_HITS_PER_SHAPE: usize = 16;

/// The callback structures: the scene's and each prototype's.
pub struct MultiHit {
    top: Accel,
    prototypes: Vec<Accel>,
}

/// The scene's primitives as a structure's builder sees them, with nothing to gather.
struct CalledBack<'a>(&'a Geometry);

impl Primitives for CalledBack<'_> {
    fn count(&self) -> usize {
        self.0.count()
    }
    fn bounds(&self, i: usize) -> Aabb {
        Primitives::bounds(self.0, i)
    }
    fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit> {
        self.0.intersect(i, ray, t_max)
    }
}

fn build(g: &Geometry) -> Accel {
    let options = AccelOptions {
        bvh: BvhOptions {
            pairs: false,
            ..Default::default()
        },
        ..Default::default()
    };
    Accel::build_with(AccelKind::Bvh, &CalledBack(g), &options)
}

impl MultiHit {
    pub(super) fn new(g: &Geometry) -> Self {
        Self {
            top: build(g),
            prototypes: g.prototypes.iter().map(|p| build(&p.geometry)).collect(),
        }
    }
}

/// What the collecting primitives do with a primitive's hits.
#[derive(Clone, Copy, PartialEq)]
enum Mode {
    /// Record them all, report none.
    All,
    /// Report the nearest beyond `tnear` (the structure narrows its interval as usual).
    Closest,
}

/// The scene's primitives at query time, recording hits.
struct Collector<'a> {
    g: &'a Geometry,
    prototypes: &'a [Accel],
    mode: Mode,
    tnear: f32,
    hits: Mutex<Vec<Hit>>,
}

impl<'a> Collector<'a> {
    fn new(g: &'a Geometry, prototypes: &'a [Accel], mode: Mode, tnear: f32) -> Self {
        Self {
            g,
            prototypes,
            mode,
            tnear,
            hits: Mutex::new(Vec::new()),
        }
    }

    fn take(&self) -> Vec<Hit> {
        std::mem::take(&mut *self.hits.lock().unwrap_or_else(|e| e.into_inner()))
    }

    /// Every hit of primitive `i` in `(0, t_max)`, nearest first.
    fn primitive_hits(&self, i: usize, ray: &Ray, t_max: f32) -> Vec<PrimHit> {
        let r = self.g.prims.get(i);
        match &self.g.shapes[r.shape as usize].kind {
            ShapeKind::Instances => {
                let instance = &self.g.instances[r.index as usize];
                let p = instance.prototype as usize;
                let inner = Collector::new(&self.g.prototypes[p].geometry, &[], Mode::All, 0.0);
                let local = instance.transform.ray_to_object(ray);
                let mut stats = TraversalStats::default();
                self.prototypes[p].intersect(&inner, &local, t_max, &mut stats);
                let mut hits = sorted(inner.take());
                hits.dedup_by(|a, b| a.prim == b.prim && a.t == b.t);
                hits.into_iter()
                    .map(|h| PrimHit {
                        t: h.t,
                        u: h.u,
                        v: h.v,
                        sub: h.prim,
                    })
                    .collect()
            }
            ShapeKind::Mesh(_) => self.g.intersect(i, ray, t_max).into_iter().collect(),
            _ => self.analytic_hits(i, ray, t_max),
        }
    }

    /// The hits of a curved primitive: its closest hit, then the closest of the same primitive
    /// from just past that point (offset by the hit's error bound), and so on.
    fn analytic_hits(&self, i: usize, ray: &Ray, t_max: f32) -> Vec<PrimHit> {
        let mut out = Vec::new();
        let mut from = *ray;
        let mut t0 = 0.0f32;
        let dir2 = ray.dir.length_squared();
        while out.len() < MAX_HITS_PER_SHAPE {
            let Some(h) = self.g.intersect(i, &from, t_max - t0) else {
                break;
            };
            let t = t0 + h.t;
            if t >= t_max {
                break;
            }
            out.push(PrimHit { t, ..h });
            let si = self.g.interaction(&from, &self.g.scene_hit(Hit::new(i, h)));
            let origin = offset_ray_origin(si.p, si.p_error, si.n, ray.dir);
            let next = (origin - ray.origin).dot(ray.dir) / dir2;
            if next.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
                break;
            }
            t0 = next;
            from = Ray::new(origin, ray.dir);
        }
        out
    }
}

/// The vertices of a triangle hit, if the surface hit is a mesh.
fn triangle(g: &Geometry, h: &SceneHit) -> Option<[crate::math::Vec3; 3]> {
    let g = if h.instance == MISS {
        g
    } else {
        let i = &g.instances[h.instance as usize];
        &g.prototypes[i.prototype as usize].geometry
    };
    match g.shapes[h.shape as usize].kind {
        ShapeKind::Mesh(m) => Some(g.meshes[m as usize].vertices(h.prim as usize)),
        _ => None,
    }
}

/// Whether two hits of one surface are the same crossing: triangles sharing a vertex (by
/// position), hit at the same `t` up to the rounding of the two tests (a few ulps).
fn same_crossing(g: &Geometry, a: &SceneHit, b: &SceneHit) -> bool {
    if (b.t - a.t) > 8.0 * f32::EPSILON * a.t.abs().max(b.t.abs()) {
        return false;
    }
    match (triangle(g, a), triangle(g, b)) {
        (Some(x), Some(y)) => x.iter().any(|p| y.contains(p)),
        _ => false,
    }
}

fn sorted(mut hits: Vec<Hit>) -> Vec<Hit> {
    hits.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.prim.cmp(&b.prim)));
    hits
}

impl Primitives for Collector<'_> {
    fn count(&self) -> usize {
        self.g.count()
    }
    fn bounds(&self, i: usize) -> Aabb {
        Primitives::bounds(self.g, i)
    }
    fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit> {
        let hits = self.primitive_hits(i, ray, t_max);
        match self.mode {
            Mode::All => {
                let mut sink = self.hits.lock().unwrap_or_else(|e| e.into_inner());
                sink.extend(hits.into_iter().map(|h| Hit::new(i, h)));
                None
            }
            Mode::Closest => hits.into_iter().find(|h| h.t > self.tnear),
        }
    }
}

/// The hits along each ray of a batch, in CSR form: the hits of ray `r` are
/// `ray_splits[r]..ray_splits[r + 1]`, nearest first.
#[derive(Clone, Debug, Default)]
pub struct HitList {
    pub ray_splits: Vec<i64>,
    pub t: Vec<f32>,
    pub prim_ids: Vec<u32>,
    pub shape_ids: Vec<u32>,
    pub instance_ids: Vec<u32>,
}

/// Rays per parallel task.
const CHUNK: usize = 256;

impl SceneHandle {
    fn multi(&self, scene: &Scene) -> &MultiHit {
        self.multi.get_or_init(|| MultiHit::new(&scene.geometry))
    }

    /// Every hit of `ray` in `(tnear, tfar)`, nearest first.
    pub(super) fn all_hits(
        &self,
        scene: &Scene,
        ray: &Ray,
        tnear: f32,
        tfar: f32,
    ) -> Vec<SceneHit> {
        let g = &scene.geometry;
        let m = self.multi(scene);
        let c = Collector::new(g, &m.prototypes, Mode::All, tnear);
        let mut stats = TraversalStats::default();
        m.top.intersect(&c, ray, tfar, &mut stats);
        let mut hits: Vec<SceneHit> = sorted(c.take())
            .into_iter()
            .filter(|h| h.t > tnear)
            .map(|h| g.scene_hit(h))
            .collect();
        for &s in &g.unbounded {
            if let ShapeKind::Plane(p) = &g.shapes[s as usize].kind {
                if let Some(h) = p.intersect(ray, tfar).filter(|h| h.t > tnear) {
                    hits.push(SceneHit {
                        t: h.t,
                        shape: s,
                        prim: 0,
                        u: h.u,
                        v: h.v,
                        instance: MISS,
                    });
                }
            }
        }
        hits.sort_by(|a, b| a.t.total_cmp(&b.t));
        // A structure may test a primitive once per cell it spans; one hit each. And a ray
        // through an edge or a vertex hits every triangle around it (the watertight test has no
        // tie-breaking rule): one crossing of the surface, so one hit.
        hits.dedup_by(|later, kept| {
            later.shape == kept.shape
                && later.instance == kept.instance
                && (later.prim == kept.prim && later.t == kept.t || same_crossing(g, kept, later))
        });
        hits
    }

    /// The closest hit of `ray` in `(tnear, tfar)`, `tnear > 0`.
    pub(super) fn closest_beyond(
        &self,
        scene: &Scene,
        ray: &Ray,
        tnear: f32,
        tfar: f32,
    ) -> Option<SceneHit> {
        let g = &scene.geometry;
        let m = self.multi(scene);
        let c = Collector::new(g, &m.prototypes, Mode::Closest, tnear);
        let mut stats = TraversalStats::default();
        let bounded = m
            .top
            .intersect(&c, ray, tfar, &mut stats)
            .map(|h| g.scene_hit(h));
        let mut best = bounded;
        for &s in &g.unbounded {
            if let ShapeKind::Plane(p) = &g.shapes[s as usize].kind {
                let t_max = best.map_or(tfar, |b| b.t);
                if let Some(h) = p.intersect(ray, t_max).filter(|h| h.t > tnear) {
                    best = Some(SceneHit {
                        t: h.t,
                        shape: s,
                        prim: 0,
                        u: h.u,
                        v: h.v,
                        instance: MISS,
                    });
                }
            }
        }
        best
    }

    /// How many times each ray meets a surface in `(tnear, tfar)`; `out[i]` for ray `i`.
    pub fn count_intersections(
        &self,
        origins: Coords,
        directions: Coords,
        tnear: f32,
        tfar: f32,
        out: &mut [i32],
    ) {
        let scene = self.read();
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(k, out)| {
            for (j, o) in out.iter_mut().enumerate() {
                let i = k * CHUNK + j;
                let ray = Ray::new(origins.get(i), directions.get(i));
                *o = self.all_hits(&scene, &ray, tnear, tfar).len() as i32;
            }
        });
    }

    /// Every hit of each ray in `(tnear, tfar)`, nearest first, with the ids the `shapeid`,
    /// `primid` and `instanceid` AOVs report.
    pub fn list_intersections(
        &self,
        origins: Coords,
        directions: Coords,
        tnear: f32,
        tfar: f32,
    ) -> HitList {
        let n = origins.len();
        let scene = self.read();
        let chunks: Vec<(Vec<u32>, HitList)> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|k| {
                let mut counts = Vec::with_capacity(CHUNK);
                let mut list = HitList::default();
                for i in k * CHUNK..((k + 1) * CHUNK).min(n) {
                    let ray = Ray::new(origins.get(i), directions.get(i));
                    let hits = self.all_hits(&scene, &ray, tnear, tfar);
                    counts.push(hits.len() as u32);
                    for h in hits {
                        let (shape, prim) = scene.geometry.source_ids(&h);
                        list.t.push(h.t);
                        list.shape_ids.push(shape);
                        list.prim_ids.push(prim);
                        list.instance_ids.push(h.instance);
                    }
                }
                (counts, list)
            })
            .collect();
        let mut out = HitList {
            ray_splits: Vec::with_capacity(n + 1),
            ..Default::default()
        };
        out.ray_splits.push(0);
        for (counts, list) in chunks {
            for c in counts {
                let last = *out.ray_splits.last().unwrap_or(&0);
                out.ray_splits.push(last + c as i64);
            }
            out.t.extend(list.t);
            out.prim_ids.extend(list.prim_ids);
            out.shape_ids.extend(list.shape_ids);
            out.instance_ids.extend(list.instance_ids);
        }
        out
    }
}
