//! The bounding volume hierarchy: objects partitioned (never split) into two groups per node
//! along the longest axis of their centroids' box, by one of three rules: the midpoint of that
//! box, the median object, or the least SAH cost over every partition of the sorted centroids
//! (in 2D with perimeters; `1 + (P(L) n_L + P(R) n_R) / P(node)` against a leaf's `n`).

use super::box_tree::{self, BoxNode};
use super::geometry::{Box2, Ray2, Shape, P2};
use super::trace::{box_region, leaf_step, BuildStep, SahCurve, Trace};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhSplit {
    Midpoint,
    Median,
    Sah,
}

impl BvhSplit {
    pub fn from_name(s: &str) -> Option<BvhSplit> {
        match s {
            "midpoint" => Some(BvhSplit::Midpoint),
            "median" => Some(BvhSplit::Median),
            "sah" => Some(BvhSplit::Sah),
            _ => None,
        }
    }
}

pub const LEAF_SIZE: usize = 2;

pub struct Bvh {
    pub nodes: Vec<BoxNode>,
    pub steps: Vec<BuildStep>,
}

fn bounds_of(objects: &[Shape], ids: &[usize]) -> Box2 {
    ids.iter()
        .fold(Box2::EMPTY, |b, &k| b.union(objects[k].bounds()))
}

impl Bvh {
    pub fn build(objects: &[Shape], split: BvhSplit) -> Bvh {
        let mut b = Bvh {
            nodes: Vec::new(),
            steps: Vec::new(),
        };
        if !objects.is_empty() {
            b.node(objects, (0..objects.len()).collect(), split, 0);
        }
        b
    }

    fn node(
        &mut self,
        objects: &[Shape],
        mut ids: Vec<usize>,
        split: BvhSplit,
        depth: u32,
    ) -> usize {
        let id = self.nodes.len();
        let bounds = bounds_of(objects, &ids);
        self.nodes.push(BoxNode {
            bounds,
            children: Vec::new(),
            objects: Vec::new(),
        });
        let cb = ids
            .iter()
            .fold(Box2::EMPTY, |b, &k| b.add_point(objects[k].centroid()));
        let e = cb.extent();
        let axis = if e.x >= e.y { 0 } else { 1 };
        let key = |k: usize| objects[k].centroid().get(axis);
        ids.sort_by(|&a, &b| key(a).total_cmp(&key(b)));
        let cut = if ids.len() <= LEAF_SIZE || e.get(axis) <= 0.0 {
            None
        } else {
            match split {
                BvhSplit::Median => Some((ids.len() / 2, None)),
                BvhSplit::Midpoint => {
                    let mid = cb.centre().get(axis);
                    let n = ids.iter().take_while(|&&k| key(k) < mid).count();
                    Some((n.clamp(1, ids.len() - 1), None))
                }
                BvhSplit::Sah => {
                    let curve = sah_curve(objects, &ids, axis, bounds);
                    let c = curve.chosen;
                    (curve.costs[c] < curve.leaf_cost).then(|| (c + 1, Some(curve)))
                }
            }
        };
        let Some((n, sah)) = cut else {
            self.steps
                .push(leaf_step(depth, box_region(bounds), ids.len()));
            self.nodes[id].objects = ids;
            return id;
        };
        let right = ids.split_off(n);
        // Drawn as the two child boxes' facing edges: the line between the groups' centroids.
        let pos = 0.5 * (key(ids[ids.len() - 1]) + key(right[0]));
        let line = if axis == 0 {
            [P2::new(pos, bounds.min.y), P2::new(pos, bounds.max.y)]
        } else {
            [P2::new(bounds.min.x, pos), P2::new(bounds.max.x, pos)]
        };
        self.steps.push(BuildStep {
            depth,
            region: box_region(bounds),
            split: Some(line),
            objects: ids.len() + right.len(),
            leaf: false,
            sah,
        });
        let a = self.node(objects, ids, split, depth + 1);
        let b = self.node(objects, right, split, depth + 1);
        self.nodes[id].children = vec![a, b];
        id
    }

    pub fn trace(&self, objects: &[Shape], ray: &Ray2) -> Trace {
        box_tree::trace(&self.nodes, objects, ray)
    }
}

/// Cost of each partition of the sorted objects into the first `i + 1` and the rest (prefix
/// and suffix boxes, so linear after the sort). Positions are the centroid between the groups.
pub fn sah_curve(objects: &[Shape], sorted: &[usize], axis: usize, bounds: Box2) -> SahCurve {
    let n = sorted.len();
    let mut prefix = Vec::with_capacity(n);
    let mut b = Box2::EMPTY;
    for &k in sorted {
        b = b.union(objects[k].bounds());
        prefix.push(b);
    }
    let mut suffix = vec![Box2::EMPTY; n];
    let mut b = Box2::EMPTY;
    for i in (0..n).rev() {
        b = b.union(objects[sorted[i]].bounds());
        suffix[i] = b;
    }
    let area = bounds.perimeter().max(1e-12);
    let mut positions = Vec::with_capacity(n - 1);
    let mut costs = Vec::with_capacity(n - 1);
    for i in 0..n - 1 {
        let left = prefix[i].perimeter() * (i + 1) as f64;
        let right = suffix[i + 1].perimeter() * (n - i - 1) as f64;
        costs.push(1.0 + (left + right) / area);
        positions.push(objects[sorted[i]].centroid().get(axis));
    }
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
        leaf_cost: n as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::super::geometry::brute_force;
    use super::super::scenes::{random_rays, scene};
    use super::*;

    #[test]
    fn every_bvh_finds_the_brute_force_hit() {
        for split in [BvhSplit::Midpoint, BvhSplit::Median, BvhSplit::Sah] {
            for (name, n) in [
                ("random", 40),
                ("clustered", 60),
                ("figures", 0),
                ("stadium", 80),
            ] {
                let objects = scene(name, n, 3);
                let b = Bvh::build(&objects, split);
                // Every object sits in exactly one leaf.
                let mut seen: Vec<usize> = b.nodes.iter().flat_map(|n| n.objects.clone()).collect();
                seen.sort();
                assert_eq!(seen, (0..objects.len()).collect::<Vec<_>>());
                for ray in random_rays(300, 8) {
                    assert_eq!(
                        b.trace(&objects, &ray).hit,
                        brute_force(&objects, &ray),
                        "{split:?} {name}"
                    );
                }
            }
        }
    }

    #[test]
    fn sah_bvh_tests_fewer_objects_than_median_on_the_stadium() {
        let objects = scene("stadium", 200, 1);
        let (sah, median) = (
            Bvh::build(&objects, BvhSplit::Sah),
            Bvh::build(&objects, BvhSplit::Median),
        );
        let tests = |b: &Bvh| -> usize {
            random_rays(400, 3)
                .iter()
                .map(|r| b.trace(&objects, r).counters.tests)
                .sum()
        };
        assert!(
            tests(&sah) <= tests(&median),
            "{} vs {}",
            tests(&sah),
            tests(&median)
        );
    }
}
