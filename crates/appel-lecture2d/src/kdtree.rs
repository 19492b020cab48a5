//! The kd-tree: axis-parallel lines placed by the surface area heuristic (MacDonald and Booth
//! 1990), in 2D with perimeters (see `Box2::perimeter`): a split at `p` costs
//! `1 + (P(left) n_left + P(right) n_right) / P(node)`, a leaf `n`; the node splits where the
//! cost is least if that beats the leaf.

use super::geometry::{Box2, Ray2, Shape, P2};
use super::split_tree::{Choice, SplitTree};
use super::trace::{box_region, SahCurve, Trace};

pub struct KdTree {
    pub tree: SplitTree,
    pub bounds: Box2,
}

impl KdTree {
    pub fn build(objects: &[Shape], bounds: Box2) -> KdTree {
        KdTree {
            tree: SplitTree::build(objects, box_region(bounds), &choose),
            bounds,
        }
    }

    pub fn trace(&self, objects: &[Shape], ray: &Ray2) -> Trace {
        match self.bounds.slab(ray, 0.0, f64::INFINITY) {
            Some((a, b)) => self.tree.trace(objects, ray, a, b),
            None => self.tree.trace(objects, ray, 1.0, 0.0),
        }
    }
}

fn region_box(region: &[P2]) -> Box2 {
    region.iter().fold(Box2::EMPTY, |b, p| b.add_point(*p))
}

/// The SAH curve of a box along one axis, over the objects' bound edges inside it.
pub fn sah_curve(objects: &[Shape], b: Box2, inside: &[usize], axis: usize) -> SahCurve {
    let bounds: Vec<Box2> = inside.iter().map(|&k| objects[k].bounds()).collect();
    let (lo, hi) = (b.min.get(axis), b.max.get(axis));
    let mut positions: Vec<f64> = bounds
        .iter()
        .flat_map(|o| [o.min.get(axis), o.max.get(axis)])
        .filter(|&p| p > lo && p < hi)
        .collect();
    positions.sort_by(f64::total_cmp);
    positions.dedup();
    let area = b.perimeter().max(1e-12);
    let costs = positions
        .iter()
        .map(|&p| {
            let n_left = bounds.iter().filter(|o| o.min.get(axis) < p).count() as f64;
            let n_right = bounds.iter().filter(|o| o.max.get(axis) >= p).count() as f64;
            let (mut left, mut right) = (b, b);
            if axis == 0 {
                left.max.x = p;
                right.min.x = p;
            } else {
                left.max.y = p;
                right.min.y = p;
            }
            1.0 + (left.perimeter() * n_left + right.perimeter() * n_right) / area
        })
        .collect::<Vec<f64>>();
    let chosen = costs
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(i, _)| i);
    SahCurve {
        axis,
        positions,
        costs,
        chosen,
        leaf_cost: inside.len() as f64,
    }
}

fn choose(objects: &[Shape], region: &[P2], inside: &[usize], _depth: u32) -> Choice {
    let b = region_box(region);
    let best = (0..2)
        .map(|axis| sah_curve(objects, b, inside, axis))
        .filter(|c| !c.costs.is_empty())
        .min_by(|x, y| x.costs[x.chosen].total_cmp(&y.costs[y.chosen]))?;
    if best.costs[best.chosen] >= best.leaf_cost {
        return None;
    }
    let p = best.positions[best.chosen];
    let n = if best.axis == 0 {
        P2::new(1.0, 0.0)
    } else {
        P2::new(0.0, 1.0)
    };
    Some((n, p, Some(best)))
}

#[cfg(test)]
mod tests {
    use super::super::geometry::brute_force;
    use super::super::scenes::{random_rays, scene};
    use super::*;

    #[test]
    fn kdtree_finds_the_brute_force_hit() {
        for (name, n) in [
            ("random", 40),
            ("clustered", 60),
            ("figures", 0),
            ("stadium", 80),
        ] {
            let objects = scene(name, n, 9);
            let k = KdTree::build(&objects, super::super::WORLD);
            assert!(k.tree.nodes.len() > 1, "{name}: the SAH should split");
            for ray in random_rays(300, 4) {
                assert_eq!(
                    k.trace(&objects, &ray).hit,
                    brute_force(&objects, &ray),
                    "{name} {ray:?}"
                );
            }
        }
    }

    #[test]
    fn sah_prefers_the_gap_between_two_clusters() {
        let mut objects = Vec::new();
        for i in 0..5 {
            objects.push(Shape::Circle {
                c: P2::new(10.0 + i as f64, 50.0),
                r: 0.4,
            });
            objects.push(Shape::Circle {
                c: P2::new(80.0 + i as f64, 50.0),
                r: 0.4,
            });
        }
        let all: Vec<usize> = (0..objects.len()).collect();
        let c = sah_curve(&objects, super::super::WORLD, &all, 0);
        let p = c.positions[c.chosen];
        assert!(p > 14.0 && p < 80.0, "split at {p}");
        assert!(c.costs[c.chosen] < c.leaf_cost);
    }
}
