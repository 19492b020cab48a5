//! The BSP tree with lines of any direction: the candidates are the lines through segments and
//! triangle edges (an autopartition, as in Fuchs, Kedem and Naylor 1980) and the axis-parallel
//! tangents of circles, scored by the same perimeter SAH as the kd-tree on the convex regions
//! they cut.

use super::geometry::Box2;
use super::geometry::{Ray2, Shape, P2};
use super::split_tree::{clip, Choice, SplitTree};
use super::trace::{box_region, Trace};

/// Objects whose lines are candidates at one node (spread over the node's objects).
const CANDIDATE_OBJECTS: usize = 48;

pub struct Bsp {
    pub tree: SplitTree,
    pub bounds: Box2,
}

impl Bsp {
    pub fn build(objects: &[Shape], bounds: Box2) -> Bsp {
        Bsp {
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

fn perimeter(poly: &[P2]) -> f64 {
    (0..poly.len())
        .map(|i| {
            let e = poly[(i + 1) % poly.len()].minus(poly[i]);
            e.dot(e).sqrt()
        })
        .sum()
}

/// The line through `a` and `b` as `(n, d)`, `n` of unit length.
fn line(a: P2, b: P2) -> Option<(P2, f64)> {
    let e = b.minus(a);
    let len = e.dot(e).sqrt();
    (len > 1e-9).then(|| {
        let n = P2::new(-e.y / len, e.x / len);
        (n, n.dot(a))
    })
}

fn candidates(objects: &[Shape], inside: &[usize]) -> Vec<(P2, f64)> {
    let step = inside.len().div_ceil(CANDIDATE_OBJECTS).max(1);
    let mut out = Vec::new();
    for &k in inside.iter().step_by(step) {
        match objects[k] {
            Shape::Segment { a, b } => out.extend(line(a, b)),
            Shape::Triangle { a, b, c } => {
                out.extend([line(a, b), line(b, c), line(c, a)].into_iter().flatten())
            }
            Shape::Circle { c, r } => {
                let (x, y) = (P2::new(1.0, 0.0), P2::new(0.0, 1.0));
                out.extend([(x, c.x - r), (x, c.x + r), (y, c.y - r), (y, c.y + r)]);
            }
        }
    }
    out
}

fn choose(objects: &[Shape], region: &[P2], inside: &[usize], _depth: u32) -> Choice {
    let area = perimeter(region).max(1e-12);
    let mut best: Option<(f64, P2, f64)> = None;
    for (n, d) in candidates(objects, inside) {
        let below = clip(region, n, d, false);
        let above = clip(region, n, d, true);
        if below.len() < 3 || above.len() < 3 {
            continue;
        }
        let (mut nb, mut na) = (0.0, 0.0);
        for &k in inside {
            let s = objects[k].sides(n, d);
            nb += s.below as u8 as f64;
            na += s.above as u8 as f64;
        }
        let cost = 1.0 + (perimeter(&below) * nb + perimeter(&above) * na) / area;
        if best.is_none_or(|b| cost < b.0) {
            best = Some((cost, n, d));
        }
    }
    let (cost, n, d) = best?;
    (cost < inside.len() as f64).then_some((n, d, None))
}

#[cfg(test)]
mod tests {
    use super::super::geometry::brute_force;
    use super::super::scenes::{random_rays, scene};
    use super::*;

    #[test]
    fn bsp_finds_the_brute_force_hit() {
        for (name, n) in [
            ("random", 40),
            ("clustered", 60),
            ("figures", 0),
            ("stadium", 80),
        ] {
            let objects = scene(name, n, 13);
            let b = Bsp::build(&objects, super::super::WORLD);
            assert!(b.tree.nodes.len() > 1, "{name}: should split");
            for ray in random_rays(300, 6) {
                assert_eq!(
                    b.trace(&objects, &ray).hit,
                    brute_force(&objects, &ray),
                    "{name} {ray:?}"
                );
            }
        }
    }

    #[test]
    fn parallel_oblique_segments_are_split_along_themselves() {
        let objects: Vec<Shape> = (0..6)
            .map(|i| {
                let o = 12.0 * i as f64;
                Shape::Segment {
                    a: P2::new(5.0 + o, 30.0 - o * 0.5),
                    b: P2::new(35.0 + o, 60.0 - o * 0.5),
                }
            })
            .collect();
        let b = Bsp::build(&objects, super::super::WORLD);
        assert!(b.tree.nodes.iter().any(
            |n| matches!(n.split, Some((dir, ..)) if dir.x.abs() > 1e-6 && dir.y.abs() > 1e-6)
        ));
    }
}
