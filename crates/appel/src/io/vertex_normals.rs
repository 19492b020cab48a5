//! Smooth vertex normals for meshes that come without them, as Mitsuba 3 computes them
//! (`Mesh::recompute_vertex_normals`): each vertex gets the sum of its triangles' unit normals
//! weighted by the triangle's angle at the vertex (Thürmer and Wüthrich 1998, "Computing Vertex
//! Normals from Polygonal Facets", JGT 3(1)), normalized. The weighting makes the normal
//! independent of how the faces around a vertex are cut into triangles. Vertices are smoothed
//! over the triangles that index them, without merging vertices at the same position.

use crate::math::Vec3;

/// One normal per position; zero for a vertex whose triangles are all degenerate (Appel then
/// shades with the triangle's own normal; Mitsuba writes an arbitrary one).
pub fn angle_weighted(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for tri in indices {
        let p = tri.map(|i| positions[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let len2 = n.length_squared();
        if !(len2 > 0.0 && len2.is_finite()) {
            continue;
        }
        let n = n / len2.sqrt();
        for k in 0..3 {
            let d0 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
            let d1 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
            normals[tri[k] as usize] += n * unit_angle(d0, d1);
        }
    }
    for n in &mut normals {
        *n = n.normalize_or_zero();
    }
    normals
}

/// The angle between unit vectors, accurate near 0 and pi (Mitsuba's `unit_angle`: twice the
/// arcsine of half the chord).
fn unit_angle(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) < 0.0 {
        std::f32::consts::PI - 2.0 * (0.5 * (a + b).length()).min(1.0).asin()
    } else {
        2.0 * (0.5 * (b - a).length()).min(1.0).asin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-6
    }

    #[test]
    fn a_flat_fan_has_its_plane_s_normal() {
        let p = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::Y,
            Vec3::new(-1.0, 0.5, 0.0),
        ];
        let n = angle_weighted(&p, &[[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
        for (v, n) in n.iter().enumerate() {
            assert!(close(*n, Vec3::Z), "{v}: {n:?}");
        }
    }

    /// At the corner of a cube's three faces, split into triangles any way, the angle weights
    /// make the normal the diagonal: each face meets the corner at a right angle in total.
    #[test]
    fn a_cube_corner_gets_the_diagonal_however_its_faces_are_split() {
        let c = Vec3::ZERO;
        // Face z = 0 as one triangle fan of two (corner angle split 30 + 60 degrees), faces
        // x = 0 and y = 0 as one triangle each with a right angle at the corner.
        let s = 3f32.sqrt();
        let p = [
            c,
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(s, 1.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        // Wound so that the three faces' normals are +z, +x and +y.
        let tris = [[0, 2, 1], [0, 3, 2], [0, 1, 4], [0, 4, 3]];
        let n = angle_weighted(&p, &tris);
        assert!(close(n[0], Vec3::ONE / 3f32.sqrt()), "{:?}", n[0]);
        // Weighted by area instead, the split face would count for more.
        let by_area: Vec3 = tris
            .iter()
            .map(|t| {
                let q = t.map(|i| p[i as usize]);
                (q[1] - q[0]).cross(q[2] - q[0])
            })
            .sum();
        assert!(!close(by_area.normalize(), n[0]));
    }

    #[test]
    fn degenerate_triangles_count_for_nothing() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(2.0, 0.0, 0.0)];
        // The second triangle is a line: vertex 3 has no normal, the others only the first's.
        let n = angle_weighted(&p, &[[0, 1, 2], [0, 1, 3]]);
        assert!(close(n[0], Vec3::Z) && close(n[1], Vec3::Z) && close(n[2], Vec3::Z));
        assert_eq!(n[3], Vec3::ZERO);
    }

    #[test]
    fn unit_angle_is_accurate_at_both_ends() {
        let a = Vec3::X;
        for angle in [1e-4f32, 0.5, 1.5, 3.0, std::f32::consts::PI - 1e-3] {
            let b = Vec3::new(angle.cos(), angle.sin(), 0.0);
            assert!((unit_angle(a, b) - angle).abs() < 2e-6, "{angle}");
        }
    }
}
