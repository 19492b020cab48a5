//! The ecosystem's ground: a height field on a square grid, two triangles per cell.

use super::builder::MeshBuilder;
use super::noise::fbm;
use appel::math::Vec3;

#[derive(Clone, Debug)]
pub struct Terrain {
    /// Vertices per side.
    pub n: usize,
    /// Side of the square, centred on the origin.
    pub size: f32,
    pub heights: Vec<f32>,
}

impl Terrain {
    /// Rolling hills: a few octaves of noise, the larger features about a third of the side across.
    pub fn new(n: usize, size: f32, seed: u64) -> Self {
        let n = n.max(2);
        let mut heights = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let (x, z) = Self::coord(n, size, i, j);
                let h = fbm(x / (0.3 * size), z / (0.3 * size), 6, seed);
                // Squaring flattens the valleys, where the water lies.
                heights.push(0.14 * size * h * h);
            }
        }
        Self { n, size, heights }
    }

    fn coord(n: usize, size: f32, i: usize, j: usize) -> (f32, f32) {
        let step = size / (n - 1) as f32;
        (-0.5 * size + i as f32 * step, -0.5 * size + j as f32 * step)
    }

    pub fn triangle_count(&self) -> usize {
        2 * (self.n - 1) * (self.n - 1)
    }

    fn vertex(&self, i: usize, j: usize) -> Vec3 {
        let (x, z) = Self::coord(self.n, self.size, i, j);
        Vec3::new(x, self.heights[j * self.n + i], z)
    }

    /// The height of the triangulated surface at `(x, z)` (exactly the mesh's, not the noise's),
    /// clamped to the square.
    pub fn height(&self, x: f32, z: f32) -> f32 {
        let step = self.size / (self.n - 1) as f32;
        let fx = ((x + 0.5 * self.size) / step).clamp(0.0, (self.n - 1) as f32 - 1e-3);
        let fz = ((z + 0.5 * self.size) / step).clamp(0.0, (self.n - 1) as f32 - 1e-3);
        let (i, j) = (fx as usize, fz as usize);
        let (u, v) = (fx - i as f32, fz - j as f32);
        let h = |a, b| self.heights[b * self.n + a];
        // Cells are split along the diagonal from (i, j) to (i + 1, j + 1), as in `mesh`.
        if u >= v {
            h(i, j) + u * (h(i + 1, j) - h(i, j)) + v * (h(i + 1, j + 1) - h(i + 1, j))
        } else {
            h(i, j) + v * (h(i, j + 1) - h(i, j)) + u * (h(i + 1, j + 1) - h(i, j + 1))
        }
    }

    /// The grid as triangles facing up.
    pub fn mesh(&self) -> MeshBuilder {
        let n = self.n;
        let mut b = MeshBuilder::default();
        b.positions.reserve(n * n);
        b.indices.reserve(self.triangle_count());
        for j in 0..n {
            for i in 0..n {
                b.positions.push(self.vertex(i, j));
            }
        }
        for j in 0..n as u32 - 1 {
            for i in 0..n as u32 - 1 {
                let a = j * n as u32 + i;
                let (r, d, rd) = (a + 1, a + n as u32, a + n as u32 + 1);
                b.indices.push([a, rd, r]);
                b.indices.push([a, d, rd]);
            }
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn height_is_the_meshes_and_triangles_face_up() {
        let t = Terrain::new(17, 100.0, 3);
        let m = t.mesh().into_mesh();
        assert_eq!(m.triangle_count(), t.triangle_count());
        for k in 0..m.triangle_count() {
            let [a, b, c] = m.vertices(k);
            assert!((b - a).cross(c - a).y > 0.0);
            // The centroid lies on the surface `height` describes.
            let g = (a + b + c) / 3.0;
            assert!((t.height(g.x, g.z) - g.y).abs() < 1e-3, "triangle {k}");
        }
    }
}
