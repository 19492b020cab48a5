//! Pictures of what a structure costs: for each pixel, the nodes visited and the primitive tests
//! of its camera ray (through the pixel's centre, traced alone rather than in a packet), both
//! levels of an instanced scene summed. The `cost` AOV and `--heatmap` are made of this.

use crate::accel::TraversalStats;
use crate::math::Ray;
use crate::scene::Scene;
use rayon::prelude::*;

/// Per pixel, row by row: nodes visited and primitive tests of its camera ray.
#[derive(Clone, Debug, PartialEq)]
pub struct CostImage {
    pub width: u32,
    pub height: u32,
    pub nodes: Vec<f32>,
    pub tests: Vec<f32>,
}

impl CostImage {
    /// Traces the camera ray through each pixel's centre of `scene` (its closest hit, as the
    /// camera rays of every integrator ask) and counts its work.
    pub fn of(scene: &Scene) -> CostImage {
        Self::trace(
            scene.camera.width,
            scene.camera.height,
            |x, y| scene.camera.ray(x, y),
            |ray, s| {
                scene.intersect(ray, f32::INFINITY, s);
            },
        )
    }

    /// The cost image of `width` by `height` pixels whose camera ray through film position
    /// `(x, y)` is `ray(x, y)`, traced by `trace` (which counts its work in the stats it is given).
    pub fn trace(
        width: u32,
        height: u32,
        ray: impl Fn(f32, f32) -> Ray + Sync,
        trace: impl Fn(&Ray, &mut TraversalStats) + Sync,
    ) -> CostImage {
        let rows: Vec<(Vec<f32>, Vec<f32>)> = (0..height)
            .into_par_iter()
            .map(|y| {
                (0..width)
                    .map(|x| {
                        let mut s = TraversalStats::default();
                        trace(&ray(x as f32 + 0.5, y as f32 + 0.5), &mut s);
                        (
                            (s.nodes_visited + s.instance_nodes_visited) as f32,
                            (s.prim_tests + s.instance_prim_tests) as f32,
                        )
                    })
                    .unzip()
            })
            .collect();
        let mut nodes = Vec::with_capacity(width as usize * height as usize);
        let mut tests = Vec::with_capacity(nodes.capacity());
        for (n, t) in rows {
            nodes.extend(n);
            tests.extend(t);
        }
        CostImage {
            width,
            height,
            nodes,
            tests,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::description_from_str;
    use crate::description::parse::Syntax;
    use crate::scene::builtin::builtin_scene;
    use std::path::Path;

    fn scene(accel: &str) -> Scene {
        let text = builtin_scene("glass-block").unwrap();
        let mut d = description_from_str(text, Syntax::Toml, Path::new("glass-block")).unwrap();
        d.render.accel = accel.into();
        d.camera.width = 40;
        d.camera.height = 30;
        Scene::new(&d, Path::new(".")).unwrap()
    }

    #[test]
    fn brute_force_tests_every_primitive_for_every_pixel_and_a_bvh_fewer() {
        let brute = CostImage::of(&scene("brute"));
        let n = scene("brute").geometry.prims.len() as f32;
        assert_eq!(brute.tests.len(), 40 * 30);
        assert!(brute.tests.iter().all(|&t| t == n), "{n}");
        assert!(brute.nodes.iter().all(|&x| x == 0.0));
        let bvh = CostImage::of(&scene("bvh"));
        let sum = |v: &[f32]| v.iter().sum::<f32>();
        assert!(sum(&bvh.tests) < 0.8 * sum(&brute.tests));
        assert!(bvh.nodes.iter().any(|&x| x > 0.0));
    }
}
