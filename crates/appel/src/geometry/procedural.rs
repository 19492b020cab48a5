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

/// A small deterministic random generator (SplitMix64, Steele et al. 2014), so generated scenes are
/// reproducible from their seed on every platform.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    pub fn in_box(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        lo + (hi - lo) * Vec3::new(self.next_f32(), self.next_f32(), self.next_f32())
    }
}

/// `count` small triangles scattered uniformly through the box `[lo, hi]`, each with vertices within
/// `size` of its first vertex: the uniform grid's best case.
pub fn scattered_triangles(count: usize, lo: Vec3, hi: Vec3, size: f32, seed: u64) -> TriangleMesh {
    let mut rng = SplitMix64(seed);
    let mut positions = Vec::with_capacity(3 * count);
    for _ in 0..count {
        let a = rng.in_box(lo, hi);
        let jitter = |rng: &mut SplitMix64| {
            a + size * (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5)
        };
        let b = jitter(&mut rng);
        let c = jitter(&mut rng);
        positions.extend([a, b, c]);
    }
    let indices = (0..count as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    TriangleMesh {
        positions,
        indices,
        normals: None,
        uvs: None,
    }
}

/// An open bowl of `segments x rings` quads, radius `radius`, around the origin: a stadium whose few
/// large triangles span a huge volume.
pub fn stadium(radius: f32, segments: u32, rings: u32) -> TriangleMesh {
    let mut positions = vec![];
    for r in 0..=rings {
        // From the field (angle 0, flat) up the stands to 60 degrees.
        let a = r as f32 / rings as f32 * std::f32::consts::FRAC_PI_3;
        let (ring_r, y) = (
            radius * (0.3 + 0.7 * a.sin() / 0.866),
            radius * 0.5 * (1.0 - a.cos()),
        );
        for s in 0..segments {
            let t = s as f32 / segments as f32 * std::f32::consts::TAU;
            positions.push(Vec3::new(ring_r * t.cos(), y, ring_r * t.sin()));
        }
    }
    let mut indices = vec![];
    for r in 0..rings {
        for s in 0..segments {
            let i = |r: u32, s: u32| r * segments + s % segments;
            let (a, b, c, d) = (i(r, s), i(r, s + 1), i(r + 1, s + 1), i(r + 1, s));
            indices.push([a, c, b]);
            indices.push([a, d, c]);
        }
    }
    // The field: a disc filling the inner ring.
    let centre = positions.len() as u32;
    positions.push(Vec3::ZERO);
    for s in 0..segments {
        indices.push([centre, (s + 1) % segments, s]);
    }
    TriangleMesh {
        positions,
        indices,
        normals: None,
        uvs: None,
    }
}

/// A dense small mesh in the middle of a huge sparse one, about `triangles` triangles in all: an
/// icosphere of radius 1 (the "teapot") standing on the field of a [`stadium`] of radius 1000. The
/// stadium's large triangles have bounds covering the teapot, the hard case for a uniform grid and
/// for structures that do not clip references.
pub fn teapot_in_stadium(triangles: usize) -> TriangleMesh {
    let subdivisions = ((triangles.max(20) as f64 / 20.0).log(4.0).round() as u32).clamp(1, 9);
    let mut teapot = icosphere(subdivisions);
    for p in &mut teapot.positions {
        *p += Vec3::Y;
    }
    let mut mesh = stadium(1000.0, 64, 8);
    append(&mut mesh, &teapot);
    mesh
}

/// Appends `other` to `mesh` (positions and triangles; attributes are dropped unless both have them).
pub fn append(mesh: &mut TriangleMesh, other: &TriangleMesh) {
    let base = mesh.positions.len() as u32;
    mesh.positions.extend_from_slice(&other.positions);
    mesh.indices
        .extend(other.indices.iter().map(|t| t.map(|i| i + base)));
    mesh.normals = None;
    mesh.uvs = None;
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
