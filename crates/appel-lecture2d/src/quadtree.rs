//! The quadtree, the 2D octree: a square region split at its centre into four while it holds
//! more than a few objects, each object stored in every child its bounds overlap.

use super::box_tree::{self, BoxNode};
use super::geometry::{Box2, Ray2, Shape, P2};
use super::trace::{box_region, leaf_step, BuildStep, Trace};

pub const LEAF_SIZE: usize = 2;
pub const MAX_DEPTH: u32 = 7;

pub struct Quadtree {
    pub nodes: Vec<BoxNode>,
    pub steps: Vec<BuildStep>,
}

impl Quadtree {
    pub fn build(objects: &[Shape], bounds: Box2) -> Quadtree {
        let mut q = Quadtree {
            nodes: Vec::new(),
            steps: Vec::new(),
        };
        let all: Vec<usize> = (0..objects.len()).collect();
        q.node(objects, bounds, all, 0);
        q
    }

    fn node(&mut self, objects: &[Shape], b: Box2, inside: Vec<usize>, depth: u32) -> usize {
        let id = self.nodes.len();
        self.nodes.push(BoxNode {
            bounds: b,
            children: Vec::new(),
            objects: Vec::new(),
        });
        if inside.len() <= LEAF_SIZE || depth >= MAX_DEPTH {
            self.steps
                .push(leaf_step(depth, box_region(b), inside.len()));
            self.nodes[id].objects = inside;
            return id;
        }
        let c = b.centre();
        // The two lines through the centre, drawn as one step each.
        for line in [
            [P2::new(c.x, b.min.y), P2::new(c.x, b.max.y)],
            [P2::new(b.min.x, c.y), P2::new(b.max.x, c.y)],
        ] {
            self.steps.push(BuildStep {
                depth,
                region: box_region(b),
                split: Some(line),
                objects: inside.len(),
                leaf: false,
                sah: None,
            });
        }
        let quads = [
            Box2 { min: b.min, max: c },
            Box2 {
                min: P2::new(c.x, b.min.y),
                max: P2::new(b.max.x, c.y),
            },
            Box2 {
                min: P2::new(b.min.x, c.y),
                max: P2::new(c.x, b.max.y),
            },
            Box2 { min: c, max: b.max },
        ];
        for q in quads {
            let part: Vec<usize> = inside
                .iter()
                .copied()
                .filter(|&k| objects[k].bounds().overlaps(q))
                .collect();
            let child = self.node(objects, q, part, depth + 1);
            self.nodes[id].children.push(child);
        }
        id
    }

    pub fn trace(&self, objects: &[Shape], ray: &Ray2) -> Trace {
        box_tree::trace(&self.nodes, objects, ray)
    }
}

#[cfg(test)]
mod tests {
    use super::super::geometry::brute_force;
    use super::super::scenes::{random_rays, scene};
    use super::*;

    #[test]
    fn quadtree_finds_the_brute_force_hit() {
        for (name, n) in [
            ("random", 40),
            ("clustered", 60),
            ("figures", 0),
            ("stadium", 80),
        ] {
            let objects = scene(name, n, 5);
            let q = Quadtree::build(&objects, super::super::WORLD);
            assert!(q
                .nodes
                .iter()
                .all(|n| n.children.is_empty() || n.children.len() == 4));
            for ray in random_rays(300, 2) {
                assert_eq!(
                    q.trace(&objects, &ray).hit,
                    brute_force(&objects, &ray),
                    "{name} {ray:?}"
                );
            }
        }
    }
}
