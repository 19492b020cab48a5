//! The lecture's 2D illustrations: "In lecture we will illustrate principles in 2D". Scenes of
//! circles, segments and triangles, and the acceleration structures of the 3D renderer in their
//! 2D form (uniform grid, quadtree, kd-tree, BSP tree, BVH), each recording its build step by
//! step and any ray's traversal (cells or nodes in order, slab intervals, objects tested,
//! mailbox hits, early exit), for `appel view --lecture` to draw. Each is tested against brute
//! force.

pub mod box_tree;
pub mod bsp;
pub mod bvh;
pub mod geometry;
pub mod grid;
pub mod kdtree;
pub mod quadtree;
pub mod scenes;
pub mod split_tree;
pub mod trace;

use geometry::{Box2, Ray2, Shape, P2};
use serde::Serialize;
use trace::{BuildStep, Counters, Trace};

/// The square every scene lies in.
pub const WORLD: Box2 = Box2 {
    min: P2::new(0.0, 0.0),
    max: P2::new(100.0, 100.0),
};

pub const STRUCTURES: &[&str] = &[
    "grid",
    "quadtree",
    "kdtree",
    "bsp",
    "bvh-midpoint",
    "bvh-median",
    "bvh-sah",
];

/// How to build: the grid's C (cells = C x objects) and whether it checks hits against the cell.
#[derive(Clone, Copy, Debug)]
pub struct Params {
    pub grid_c: f64,
    pub grid_check: bool,
}

pub enum Built {
    Grid(grid::Grid, bool),
    Quadtree(quadtree::Quadtree),
    KdTree(kdtree::KdTree),
    Bsp(bsp::Bsp),
    Bvh(bvh::Bvh),
}

impl Built {
    pub fn new(name: &str, objects: &[Shape], p: Params) -> Option<Built> {
        Some(match name {
            "grid" => Built::Grid(grid::Grid::build(objects, WORLD, p.grid_c), p.grid_check),
            "quadtree" => Built::Quadtree(quadtree::Quadtree::build(objects, WORLD)),
            "kdtree" => Built::KdTree(kdtree::KdTree::build(objects, WORLD)),
            "bsp" => Built::Bsp(bsp::Bsp::build(objects, WORLD)),
            _ => Built::Bvh(bvh::Bvh::build(
                objects,
                bvh::BvhSplit::from_name(name.strip_prefix("bvh-")?)?,
            )),
        })
    }

    pub fn steps(&self) -> &[BuildStep] {
        match self {
            Built::Grid(g, _) => &g.steps,
            Built::Quadtree(q) => &q.steps,
            Built::KdTree(k) => &k.tree.steps,
            Built::Bsp(b) => &b.tree.steps,
            Built::Bvh(b) => &b.steps,
        }
    }

    pub fn trace(&self, objects: &[Shape], ray: &Ray2) -> Trace {
        match self {
            Built::Grid(g, check) => g.trace(objects, ray, *check),
            Built::Quadtree(q) => q.trace(objects, ray),
            Built::KdTree(k) => k.trace(objects, ray),
            Built::Bsp(b) => b.trace(objects, ray),
            Built::Bvh(b) => b.trace(objects, ray),
        }
    }
}

/// One structure's work on the page's ray, beside the others'.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    pub structure: String,
    pub counters: Counters,
    pub hit: Option<(usize, f64)>,
    /// Whether the hit is the brute-force nearest one.
    pub correct: bool,
    /// Mean objects tested and cells or nodes visited per ray over a fixed set of random rays.
    pub mean_tests: f64,
    pub mean_visited: f64,
}

/// Every structure on the same scene and ray.
pub fn compare(objects: &[Shape], ray: Option<&Ray2>, p: Params) -> Vec<Comparison> {
    let rays = scenes::random_rays(200, 99);
    STRUCTURES
        .iter()
        .map(|&name| {
            let built = Built::new(name, objects, p).expect("a known structure");
            let (counters, hit, correct) = match ray {
                Some(r) => {
                    let t = built.trace(objects, r);
                    let correct = t.hit == geometry::brute_force(objects, r);
                    (t.counters, t.hit, correct)
                }
                None => (Counters::default(), None, true),
            };
            let (mut tests, mut visited) = (0, 0);
            for r in &rays {
                let c = built.trace(objects, r).counters;
                tests += c.tests;
                visited += c.visited;
            }
            Comparison {
                structure: name.to_string(),
                counters,
                hit,
                correct,
                mean_tests: tests as f64 / rays.len() as f64,
                mean_visited: visited as f64 / rays.len() as f64,
            }
        })
        .collect()
}
