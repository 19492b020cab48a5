//! Meshes made from a formula rather than a file: for tests, benchmarks and generated scenes.

use super::TriangleMesh;
use crate::math::Vec3;
use std::collections::HashMap;

/// The axis-aligned cube `[-1, 1]^3`, 12 triangles wound counter-clockwise seen from outside.
pub fn cube() -> TriangleMesh {
    let positions: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 4 != 0 { 1.0 } else { -1.0 },
                if i & 2 != 0 { 1.0 } else { -1.0 },
                if i & 1 != 0 { 1.0 } else { -1.0 },
            )
        })
        .collect();
    // Each face as a quad of corner indices, counter-clockwise from outside.
    let quads = [
        [0, 1, 3, 2], // -x
        [4, 6, 7, 5], // +x
        [0, 4, 5, 1], // -y
        [2, 3, 7, 6], // +y
        [0, 2, 6, 4], // -z
        [1, 5, 7, 3], // +z
    ];
    let indices = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    TriangleMesh {
        positions,
        indices,
        normals: None,
        uvs: None,
    }
}

/// A unit icosphere: the icosahedron with each triangle split in four `subdivisions` times and the new
/// vertices pushed onto the sphere. Closed, manifold, 20 * 4^subdivisions triangles, outward winding.
pub fn icosphere(subdivisions: u32) -> TriangleMesh {
    let phi = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, phi, 0.0),
        (1.0, phi, 0.0),
        (-1.0, -phi, 0.0),
        (1.0, -phi, 0.0),
        (0.0, -1.0, phi),
        (0.0, 1.0, phi),
        (0.0, -1.0, -phi),
        (0.0, 1.0, -phi),
        (phi, 0.0, -1.0),
        (phi, 0.0, 1.0),
        (-phi, 0.0, -1.0),
        (-phi, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut indices: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push((positions[a as usize] + positions[b as usize]).normalize());
                positions.len() as u32 - 1
            })
        };
        indices = indices
            .iter()
            .flat_map(|&[a, b, c]| {
                let ab = midpoint(a, b, &mut positions);
                let bc = midpoint(b, c, &mut positions);
                let ca = midpoint(c, a, &mut positions);
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    TriangleMesh {
        positions,
        indices,
        normals: None,
        uvs: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every edge of a closed manifold mesh is shared by exactly two triangles, in opposite directions.
    fn assert_closed_manifold(m: &TriangleMesh) {
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for &[a, b, c] in &m.indices {
            for (u, v) in [(a, b), (b, c), (c, a)] {
                *edges.entry((u, v)).or_default() += 1;
            }
        }
        for (&(u, v), &n) in &edges {
            assert_eq!(n, 1, "edge {u}-{v} repeated");
            assert_eq!(edges.get(&(v, u)), Some(&1), "edge {u}-{v} has no twin");
        }
    }

    fn assert_outward(m: &TriangleMesh) {
        for t in 0..m.triangle_count() {
            let [a, b, c] = m.vertices(t);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
        }
    }

    #[test]
    fn cube_and_icospheres_are_closed_and_outward() {
        for m in [cube(), icosphere(0), icosphere(2)] {
            assert_closed_manifold(&m);
            assert_outward(&m);
        }
        assert_eq!(icosphere(3).triangle_count(), 20 * 64);
        // Euler characteristic of a sphere: V - E + F = 2.
        let m = icosphere(2);
        let f = m.triangle_count();
        assert_eq!(m.positions.len() as i64 - (3 * f / 2) as i64 + f as i64, 2);
    }
}
