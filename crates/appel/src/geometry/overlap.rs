//! Triangle/box overlap by the separating axis theorem (Akenine-Moller 2001, "Fast 3D triangle-box
//! overlap testing"): a triangle and a box are disjoint iff one of 13 axes separates their
//! projections: the 3 box face normals, the triangle normal, and the 9 cross products of a triangle
//! edge with a box axis.

use crate::math::{Aabb, Vec3};

/// Whether the (closed) triangle `v` and the (closed) box `b` share a point. The test is exact up to
/// rounding; callers that need it conservative (a grid must never drop a triangle from a cell it
/// touches) pass a slightly enlarged box.
pub fn triangle_box_overlap(v: [Vec3; 3], b: &Aabb) -> bool {
    if b.is_empty() {
        return false;
    }
    let c = b.center();
    let h = 0.5 * (b.max - b.min);
    // Box at the origin: the box's projection onto an axis `a` is then `[-r, r]`, r = h . |a|.
    let v = v.map(|p| p - c);
    // The 3 box normals: the triangle's bounds against the box.
    for a in 0..3 {
        let lo = v[0][a].min(v[1][a]).min(v[2][a]);
        let hi = v[0][a].max(v[1][a]).max(v[2][a]);
        if lo > h[a] || hi < -h[a] {
            return false;
        }
    }
    let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    // The 9 edge x box-axis cross products.
    for edge in e {
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            let a = edge.cross(axis);
            if separates(a, &v, h) {
                return false;
            }
        }
    }
    // The triangle's normal: does the plane through the triangle cut the box?
    let n = e[0].cross(e[1]);
    !separates(n, &v, h)
}

/// Whether axis `a` separates the triangle `v` from the origin-centred box of half-size `h`. A zero
/// axis (parallel edge and box axis, or a degenerate triangle's normal) separates nothing.
#[inline]
fn separates(a: Vec3, v: &[Vec3; 3], h: Vec3) -> bool {
    let p = [a.dot(v[0]), a.dot(v[1]), a.dot(v[2])];
    let lo = p[0].min(p[1]).min(p[2]);
    let hi = p[0].max(p[1]).max(p[2]);
    let r = h.dot(a.abs());
    lo > r || hi < -r
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Aabb {
        Aabb::new(Vec3::ZERO, Vec3::ONE)
    }

    #[test]
    fn triangle_inside_the_box_overlaps() {
        let t = [
            Vec3::splat(0.2),
            Vec3::new(0.8, 0.2, 0.5),
            Vec3::new(0.5, 0.8, 0.5),
        ];
        assert!(triangle_box_overlap(t, &unit()));
    }

    #[test]
    fn triangle_cutting_a_corner_region_only_by_its_bounds_is_rejected() {
        // The bounds of this triangle contain the box's corner (1,1,1) region, but the triangle's
        // plane x + y + z = 3.5 passes beyond the corner (where x + y + z = 3): only the normal axis
        // separates them.
        let t = [
            Vec3::new(3.5, 0.0, 0.0),
            Vec3::new(0.0, 3.5, 0.0),
            Vec3::new(0.0, 0.0, 3.5),
        ];
        assert!(!triangle_box_overlap(t, &unit()));
        // Move the plane to x + y + z = 2.5: it now cuts the corner.
        let t = t.map(|p| p * (2.5 / 3.5));
        assert!(triangle_box_overlap(t, &unit()));
    }

    #[test]
    fn edge_axis_separates_a_sliver_passing_by_an_edge() {
        // A thin triangle in the plane z = 0.5 running diagonally past the corner (1, 1) of the box's
        // xy-square at distance: the face normals and the triangle normal do not separate (its
        // bounds overlap the box, its plane cuts the box), only an edge x z-axis cross product does.
        let t = [
            Vec3::new(2.0, 0.5, 0.5),
            Vec3::new(0.5, 2.0, 0.5),
            Vec3::new(2.0, 0.6, 0.5),
        ];
        assert!(!triangle_box_overlap(t, &unit()));
        // The mirrored sliver through the box's interior does overlap.
        let t = [
            Vec3::new(1.5, 0.0, 0.5),
            Vec3::new(0.0, 1.5, 0.5),
            Vec3::new(1.5, 0.1, 0.5),
        ];
        assert!(triangle_box_overlap(t, &unit()));
    }

    #[test]
    fn touching_counts_as_overlap_and_far_away_does_not() {
        let t = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        assert!(triangle_box_overlap(t, &unit()));
        let far = t.map(|p| p + Vec3::new(0.0, 0.0, 5.0));
        assert!(!triangle_box_overlap(far, &unit()));
    }

    #[test]
    fn degenerate_triangles_are_handled() {
        // A point inside, a segment through the box, a point outside.
        assert!(triangle_box_overlap([Vec3::splat(0.5); 3], &unit()));
        let seg = [
            Vec3::new(-1.0, 0.5, 0.5),
            Vec3::new(2.0, 0.5, 0.5),
            Vec3::new(2.0, 0.5, 0.5),
        ];
        assert!(triangle_box_overlap(seg, &unit()));
        assert!(!triangle_box_overlap([Vec3::splat(1.5); 3], &unit()));
        assert!(!triangle_box_overlap(seg, &Aabb::EMPTY));
    }

    #[test]
    fn agrees_with_point_sampling_on_random_triangles() {
        // Independent check: a dense sample of points of the triangle that fall in the box proves
        // overlap; the test must then say yes. (The converse is checked by the cases above.)
        let mut s = 12345u32;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            (s as f32 / u32::MAX as f32) * 3.0 - 1.0
        };
        for _ in 0..2000 {
            let t = [
                Vec3::new(rnd(), rnd(), rnd()),
                Vec3::new(rnd(), rnd(), rnd()),
                Vec3::new(rnd(), rnd(), rnd()),
            ];
            let mut inside = false;
            for i in 0..=20 {
                for j in 0..=(20 - i) {
                    let (b1, b2) = (i as f32 / 20.0, j as f32 / 20.0);
                    let p = (1.0 - b1 - b2) * t[0] + b1 * t[1] + b2 * t[2];
                    inside |= unit().contains(p);
                }
            }
            if inside {
                assert!(triangle_box_overlap(t, &unit()), "{t:?}");
            }
        }
    }
}
