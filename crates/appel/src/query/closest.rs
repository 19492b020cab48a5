//! The closest point of a triangle mesh to a query point, through a bounding volume hierarchy of
//! its own (the ray structures answer rays, not distances): nodes are visited nearer box first and
//! skipped when their box is farther than the best triangle so far. Distances are computed in
//! f64, so that the sign of a signed distance and the winding number's hand-over near the surface
//! rest on accurate figures.

use crate::geometry::TriangleMesh;
use crate::math::Aabb;
use glam::DVec3;

/// Triangles per leaf: a closest-point test costs about as much as two box distances.
const LEAF: usize = 4;

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: the first of `count` triangles in `order`; inner node: the second child's index (the
    /// first child follows the node).
    start: u32,
    count: u32,
}

/// The nearest point of a mesh to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    pub point: DVec3,
    pub distance: f64,
    /// The triangle's index in the mesh.
    pub triangle: u32,
}

/// A hierarchy over a mesh's triangles for closest-point queries.
#[derive(Clone, Debug)]
pub struct ClosestPoint {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl ClosestPoint {
    pub fn new(mesh: &TriangleMesh) -> Self {
        let bounds: Vec<Aabb> = (0..mesh.triangle_count())
            .map(|t| mesh.triangle_bounds(t))
            .collect();
        let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * bounds.len() / LEAF + 1);
        if !bounds.is_empty() {
            build(&bounds, &mut order, 0, &mut nodes);
        }
        Self { nodes, order }
    }

    /// The nearest point of `mesh` (the one this was built over) to `p`; `None` for a mesh
    /// without triangles.
    pub fn closest(&self, mesh: &TriangleMesh, p: DVec3) -> Option<Closest> {
        let mut best: Option<Closest> = None;
        let mut best_d2 = f64::INFINITY;
        let mut stack: Vec<(u32, f64)> = Vec::with_capacity(64);
        if self.nodes.is_empty() {
            return None;
        }
        stack.push((0, box_distance2(&self.nodes[0], p)));
        while let Some((i, d2)) = stack.pop() {
            if d2 >= best_d2 {
                continue;
            }
            let node = &self.nodes[i as usize];
            if node.count > 0 {
                for &t in &self.order[node.start as usize..(node.start + node.count) as usize] {
                    let [a, b, c] = mesh.vertices(t as usize).map(|v| v.as_dvec3());
                    let q = closest_on_triangle(p, a, b, c);
                    let d2 = (q - p).length_squared();
                    if d2 < best_d2 {
                        best_d2 = d2;
                        best = Some(Closest {
                            point: q,
                            distance: 0.0,
                            triangle: t,
                        });
                    }
                }
                continue;
            }
            let (l, r) = (i + 1, node.start);
            let (dl, dr) = (
                box_distance2(&self.nodes[l as usize], p),
                box_distance2(&self.nodes[r as usize], p),
            );
            // The nearer child is popped first.
            if dl < dr {
                stack.push((r, dr));
                stack.push((l, dl));
            } else {
                stack.push((l, dl));
                stack.push((r, dr));
            }
        }
        best.map(|b| Closest {
            distance: best_d2.sqrt(),
            ..b
        })
    }
}

fn box_distance2(n: &Node, p: DVec3) -> f64 {
    let d = (n.lo - p).max(p - n.hi).max(DVec3::ZERO);
    d.length_squared()
}

/// Builds the subtree over `order[..]` (whose first element is triangle `first` of the whole
/// order) by median splits along the longest axis of the centroids.
fn build(bounds: &[Aabb], order: &mut [u32], first: usize, nodes: &mut Vec<Node>) {
    let b = order
        .iter()
        .fold(Aabb::EMPTY, |b, &t| b.union(bounds[t as usize]));
    let index = nodes.len();
    nodes.push(Node {
        lo: b.min.as_dvec3(),
        hi: b.max.as_dvec3(),
        start: first as u32,
        count: order.len() as u32,
    });
    if order.len() <= LEAF {
        return;
    }
    let centre = |t: u32| {
        let b = bounds[t as usize];
        (b.min + b.max) * 0.5
    };
    let c = order.iter().fold(Aabb::EMPTY, |c, &t| {
        let p = centre(t);
        c.union(Aabb::new(p, p))
    });
    let axis = c.largest_axis();
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |&x, &y| centre(x)[axis].total_cmp(&centre(y)[axis]));
    let (left, right) = order.split_at_mut(mid);
    build(bounds, left, first, nodes);
    let second = nodes.len() as u32;
    build(bounds, right, first + mid, nodes);
    nodes[index].start = second;
    nodes[index].count = 0;
}

/// The point of triangle `(a, b, c)` nearest to `p`, by the Voronoi regions of its vertices,
/// edges and face (Ericson, "Real-Time Collision Detection", section 5.1.5).
pub fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::procedural::{icosphere, scattered_triangles};
    use crate::math::Vec3;

    /// The hierarchy's answer is the brute-force minimum over every triangle.
    #[test]
    fn agrees_with_brute_force() {
        let mesh = scattered_triangles(500, Vec3::splat(-1.0), Vec3::splat(1.0), 0.2, 3);
        let cp = ClosestPoint::new(&mesh);
        for k in 0..200 {
            let p = DVec3::new(
                (k as f64 * 0.37).sin() * 1.5,
                (k as f64 * 0.71).cos() * 1.5,
                (k as f64 * 0.13).sin(),
            );
            let brute = (0..mesh.triangle_count())
                .map(|t| {
                    let [a, b, c] = mesh.vertices(t).map(|v| v.as_dvec3());
                    (closest_on_triangle(p, a, b, c) - p).length()
                })
                .fold(f64::INFINITY, f64::min);
            let got = cp.closest(&mesh, p).unwrap();
            assert_eq!(got.distance, brute, "{p}");
        }
    }

    #[test]
    fn distance_to_an_icosphere_is_near_one_minus_radius() {
        let mesh = icosphere(4);
        let cp = ClosestPoint::new(&mesh);
        let c = cp.closest(&mesh, DVec3::new(0.0, 0.0, 3.0)).unwrap();
        assert!((c.distance - 2.0).abs() < 2e-3, "{}", c.distance);
        let empty = TriangleMesh::default();
        assert!(ClosestPoint::new(&empty)
            .closest(&empty, DVec3::ZERO)
            .is_none());
    }
}
