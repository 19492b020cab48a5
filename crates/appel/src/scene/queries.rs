//! The scene's ray queries: the acceleration structure's closest and any hit, then the unbounded
//! planes it leaves out.

use super::{Scene, SceneHit};
use crate::accel::{Hit, Primitives, TraversalStats, LEAF_PACKET};
use crate::math::{Ray, Vec2, Vec3};
use crate::shading::bsdf::Phong;
use crate::shading::material::Material;

impl Scene {
    /// Closest hit in `(0, t_max)`.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_max: f32, stats: &mut TraversalStats) -> Option<SceneHit> {
        let hit = if self.one_leaf() {
            self.intersect_one_leaf::<false>(ray, t_max, stats)
        } else {
            self.accel.intersect(&self.geometry, ray, t_max, stats)
        };
        let bounded = hit.map(|h| self.geometry.scene_hit(h));
        let t_max = bounded.map_or(t_max, |h| h.t);
        self.geometry.intersect_unbounded(ray, t_max).or(bounded)
    }

    /// [`Self::intersect`] of each of `rays` (`out[i]` for `rays[i]`), for coherent rays such as the
    /// camera rays of neighbouring pixels: where the structure has a packet path (the 8-wide BVH
    /// over more than one leaf) they are traced in packets of [`crate::accel::bvh::PACKET`],
    /// otherwise one by one. The hits are the same either way; only the cost differs (a scene
    /// of one leaf, such as Whitted's, has nothing for a packet to share).
    pub fn intersect_coherent(
        &self,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<SceneHit>],
        stats: &mut TraversalStats,
    ) {
        if self.one_leaf() {
            return self.intersect_stream(rays, t_max, out, stats);
        }
        if !self.accel.has_packets() {
            for (ray, o) in rays.iter().zip(out.iter_mut()) {
                *o = self.intersect(ray, t_max, stats);
            }
            return;
        }
        const PACKET: usize = crate::accel::bvh::PACKET;
        for (rays, out) in rays.chunks(PACKET).zip(out.chunks_mut(PACKET)) {
            let mut hits = [None; PACKET];
            self.accel
                .intersect_packet(&self.geometry, rays, t_max, &mut hits, stats);
            for ((ray, hit), o) in rays.iter().zip(hits).zip(out.iter_mut()) {
                let bounded = hit.map(|h| self.geometry.scene_hit(h));
                let t_max = bounded.map_or(t_max, |h| h.t);
                *o = self.geometry.intersect_unbounded(ray, t_max).or(bounded);
            }
        }
    }

    /// [`Self::intersect`] of each of `rays` (`out[i]` for `rays[i]`), rays in any directions: the
    /// stream interface of Embree's `rtcIntersect1M` (a batch handed over at once, traced in
    /// whatever groups the scene can share work in). A scene of one leaf tests packets of
    /// [`LEAF_PACKET`] rays in SIMD lanes ([`Primitives::intersect_all_packet`]); other scenes go
    /// ray by ray. The hits and counts are [`Self::intersect`]'s on each ray.
    pub fn intersect_stream(
        &self,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<SceneHit>],
        stats: &mut TraversalStats,
    ) {
        if !self.one_leaf() {
            for (ray, o) in rays.iter().zip(out.iter_mut()) {
                *o = self.intersect(ray, t_max, stats);
            }
            return;
        }
        let tests = self.geometry.count() as u64;
        for (rays, out) in rays.chunks(LEAF_PACKET).zip(out.chunks_mut(LEAF_PACKET)) {
            let n = rays.len();
            // Lanes past the end are copies of the last ray, never active.
            let lanes: [Ray; LEAF_PACKET] = match rays.try_into() {
                Ok(full) => full,
                Err(_) => std::array::from_fn(|k| rays[k.min(n - 1)]),
            };
            let mut limits = [t_max; LEAF_PACKET];
            let mut hits = [None; LEAF_PACKET];
            stats.rays += n as u64;
            stats.prim_tests += tests * n as u64;
            self.geometry.intersect_all_packet::<false>(
                &lanes,
                (1 << n) - 1,
                &mut limits,
                &mut hits,
                stats,
            );
            let unbounded = self.geometry.has_unbounded();
            for ((ray, hit), o) in rays.iter().zip(hits).zip(out.iter_mut()) {
                let bounded = hit.map(|h| self.geometry.scene_hit(h));
                *o = if unbounded {
                    let t_max = bounded.map_or(t_max, |h| h.t);
                    self.geometry.intersect_unbounded(ray, t_max).or(bounded)
                } else {
                    bounded
                };
            }
        }
    }

    /// [`Self::occluded`] of each of `rays` within its own `t_max[i]` (`out[i]` for `rays[i]`): the
    /// any-hit stream, in packets as [`Self::intersect_stream`]. Answers and counts are
    /// [`Self::occluded`]'s on each ray.
    pub fn occluded_stream(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        out: &mut [bool],
        stats: &mut TraversalStats,
    ) {
        if !self.one_leaf() {
            for ((ray, &t), o) in rays.iter().zip(t_max).zip(out.iter_mut()) {
                *o = self.occluded(ray, t, stats);
            }
            return;
        }
        let tests = self.geometry.count() as u64;
        let chunks = rays.chunks(LEAF_PACKET).zip(t_max.chunks(LEAF_PACKET));
        for ((rays, t_max), out) in chunks.zip(out.chunks_mut(LEAF_PACKET)) {
            let n = rays.len();
            let lanes: [Ray; LEAF_PACKET] = std::array::from_fn(|k| rays[k.min(n - 1)]);
            let mut limits: [f32; LEAF_PACKET] = std::array::from_fn(|k| t_max[k.min(n - 1)]);
            let mut active = 0;
            for k in 0..n {
                // As `occluded`: the unbounded planes first, the leaf only for rays they let pass.
                out[k] = self.geometry.has_unbounded()
                    && self.geometry.occluded_unbounded(&rays[k], t_max[k]);
                active |= (!out[k] as u32) << k;
            }
            if active == 0 {
                continue;
            }
            let live = active.count_ones() as u64;
            stats.rays += live;
            stats.prim_tests += tests * live;
            let mut hits = [None; LEAF_PACKET];
            self.geometry.intersect_all_packet::<true>(
                &lanes,
                active,
                &mut limits,
                &mut hits,
                stats,
            );
            for k in 0..n {
                out[k] |= hits[k].is_some();
            }
        }
    }

    /// Whether anything lies on the ray in `(0, t_max)`.
    #[inline(always)]
    pub fn occluded(&self, ray: &Ray, t_max: f32, stats: &mut TraversalStats) -> bool {
        self.geometry.occluded_unbounded(ray, t_max)
            || if self.one_leaf() {
                self.intersect_one_leaf::<true>(ray, t_max, stats).is_some()
            } else {
                self.accel.occluded(&self.geometry, ray, t_max, stats)
            }
    }

    /// The material of the surface hit.
    #[inline]
    pub fn material(&self, hit: &SceneHit) -> &Material {
        &self.shading_materials[self.geometry.material(hit) as usize]
    }

    /// What `whitted` and `raycast` read of the material hit, at texture coordinates `uv`: its
    /// Phong lobes and its albedo (see [`Material::whitted`], and there `other`).
    #[inline(always)]
    pub fn whitted_material<'a>(
        &'a self,
        hit: &SceneHit,
        uv: Vec2,
        other: &'a mut Option<Phong>,
    ) -> (&'a Phong, Vec3) {
        Material::whitted(
            &self.shading_materials,
            self.geometry.material(hit),
            uv,
            || self.geometry.attributes_at(hit),
            other,
        )
    }

    /// Whether the structure is a single leaf holding every primitive (a scene of a few spheres and
    /// rectangles, such as Whitted's): its queries are then asked of `Geometry::intersect_all`
    /// directly, past the calls through `Accel`, `Bvh` and the wide tree (a real share of such a
    /// cheap query), with the same hits and counts.
    #[inline(always)]
    fn one_leaf(&self) -> bool {
        self.accel.single_leaf() == Some(self.geometry.count())
    }

    /// What the single leaf's traversal does (see [`Self::one_leaf`]), in one function: kept out of
    /// line, as the traversal keeps its root leaf, so that its registers are not paid for by
    /// every caller.
    #[inline(never)]
    fn intersect_one_leaf<const ANY: bool>(
        &self,
        ray: &Ray,
        mut t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        stats.rays += 1;
        stats.prim_tests += self.geometry.count() as u64;
        self.geometry.intersect_all::<ANY>(ray, &mut t_max, stats)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::description_from_str;
    use crate::description::parse::Syntax;
    use crate::math::Vec3;
    use crate::scene::builtin::builtin_scene;
    use std::path::Path;

    /// The queries of a scene of one leaf (Whitted's spheres and rectangle), asked of
    /// `Geometry::intersect_all` directly, answer what the structure's traversal answers: the same
    /// closest hits, the same any-hit answers and the same counts, on camera rays and on rays from
    /// all around, with and without a `t_max`.
    #[test]
    fn one_leaf_queries_answer_as_the_structure() {
        let text = builtin_scene("whitted").unwrap();
        let d = description_from_str(text, Syntax::Toml, Path::new("whitted")).unwrap();
        let scene = Scene::new(&d, Path::new(".")).unwrap();
        assert!(scene.one_leaf(), "the scene is expected to be one leaf");
        let mut rays: Vec<Ray> = (0..40)
            .flat_map(|j| (0..60).map(move |i| (i as f32 * 10.7, j as f32 * 11.9)))
            .map(|(x, y)| scene.camera.ray(x, y))
            .collect();
        let mut seed = 0x9e37_79b9_u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        for _ in 0..4000 {
            let origin = Vec3::new(next() * 4.0, next() * 2.0 + 1.0, next() * 4.0);
            rays.push(Ray::new(origin, Vec3::new(next(), next(), next())));
        }
        let (mut hits, mut occluded) = (0, 0);
        for (k, ray) in rays.iter().enumerate() {
            let t_max = if k % 3 == 0 { 2.5 } else { f32::INFINITY };
            let (mut fast, mut slow) = (TraversalStats::default(), TraversalStats::default());
            let hit = scene.intersect(ray, t_max, &mut fast);
            let bounded = scene
                .accel
                .intersect(&scene.geometry, ray, t_max, &mut slow)
                .map(|h| scene.geometry.scene_hit(h));
            let limit = bounded.map_or(t_max, |h| h.t);
            let expected = scene.geometry.intersect_unbounded(ray, limit).or(bounded);
            assert_eq!(hit, expected, "ray {k}");
            let any = scene.occluded(ray, t_max, &mut fast);
            assert_eq!(
                any,
                scene.accel.occluded(&scene.geometry, ray, t_max, &mut slow)
            );
            assert_eq!(fast, slow, "ray {k}");
            hits += hit.is_some() as usize;
            occluded += any as usize;
        }
        // Both answers occur often enough for the comparison to mean something.
        assert!(hits > rays.len() / 4 && hits < rays.len() * 3 / 4, "{hits}");
        assert!(occluded == hits);
    }
}
