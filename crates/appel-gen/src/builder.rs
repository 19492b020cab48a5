//! Appending shapes to a growing triangle mesh: tubes along a path, leaf blades, quads. The
//! procedural plants, terrain and city are made of these.

use appel::geometry::TriangleMesh;
use appel::math::{orthonormal_basis, Vec3};

#[derive(Clone, Debug, Default)]
pub struct MeshBuilder {
    pub positions: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
}

impl MeshBuilder {
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    pub fn into_mesh(self) -> TriangleMesh {
        TriangleMesh {
            positions: self.positions,
            indices: self.indices,
            normals: None,
            uvs: None,
        }
    }

    pub fn vertex(&mut self, p: Vec3) -> u32 {
        self.positions.push(p);
        self.positions.len() as u32 - 1
    }

    /// A quad `a b c d` (counter-clockwise seen from its front) as two triangles.
    pub fn quad(&mut self, a: Vec3, b: Vec3, c: Vec3, d: Vec3) {
        let i = self.vertex(a);
        self.vertex(b);
        self.vertex(c);
        self.vertex(d);
        self.indices.push([i, i + 1, i + 2]);
        self.indices.push([i, i + 2, i + 3]);
    }

    /// A quad of existing vertices `a b c d` (counter-clockwise seen from its front).
    pub fn quad_indices(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.indices.push([a, b, c]);
        self.indices.push([a, c, d]);
    }

    /// Triangles of a tube through `path` with `sides` faces around: `2 * sides` per segment.
    pub fn tube_triangles(path_points: usize, sides: u32) -> usize {
        2 * sides as usize * path_points.saturating_sub(1)
    }

    /// A closed-around, open-ended tube of radius `radii[k]` at `path[k]`. Each ring is oriented by
    /// the tangent's orthonormal basis, so the tube twists a little where the path bends, which a
    /// bark texture would hide and Whitted shading does not show.
    pub fn tube(&mut self, path: &[Vec3], radii: &[f32], sides: u32) {
        if path.len() < 2 {
            return;
        }
        let first = self.positions.len() as u32;
        for (k, (&p, &r)) in path.iter().zip(radii).enumerate() {
            let tangent = if k + 1 < path.len() {
                path[k + 1] - p
            } else {
                p - path[k - 1]
            }
            .normalize_or(Vec3::Y);
            let (s, t) = orthonormal_basis(tangent);
            for j in 0..sides {
                let a = j as f32 / sides as f32 * std::f32::consts::TAU;
                self.vertex(p + r * (a.cos() * s + a.sin() * t));
            }
        }
        for k in 0..path.len() as u32 - 1 {
            for j in 0..sides {
                let a = first + k * sides + j;
                let b = first + k * sides + (j + 1) % sides;
                let (c, d) = (a + sides, b + sides);
                self.indices.push([a, b, d]);
                self.indices.push([a, d, c]);
            }
        }
    }

    /// Triangles of a leaf of `segments` segments along its midrib.
    pub fn leaf_triangles(segments: u32) -> usize {
        4 * segments as usize - 2
    }

    /// A leaf blade from `base` along `dir` (unit), `length` long and at most `width` wide, lying
    /// in the plane spanned by `dir` and `side` (unit, perpendicular), folded a little along its
    /// midrib and curled by `droop` (towards -Y at the tip, in units of its length).
    #[allow(clippy::too_many_arguments)]
    pub fn leaf(
        &mut self,
        base: Vec3,
        dir: Vec3,
        side: Vec3,
        length: f32,
        width: f32,
        droop: f32,
        segments: u32,
    ) {
        let normal = dir.cross(side).normalize_or(Vec3::Y);
        let segments = segments.max(1);
        let at = |t: f32| base + dir * (length * t) - Vec3::Y * (droop * length * t * t);
        let mut mid = self.vertex(at(0.0));
        let mut left = self.vertex(at(0.0) + side * (0.08 * width));
        let mut right = self.vertex(at(0.0) - side * (0.08 * width));
        for k in 1..=segments {
            let t = k as f32 / segments as f32;
            let m = self.vertex(at(t));
            if k == segments {
                self.indices.push([mid, left, m]);
                self.indices.push([mid, m, right]);
                break;
            }
            // Widest a third of the way up, like most leaves; the edges sit slightly above the
            // midrib (the fold).
            let w = 0.5 * width * (std::f32::consts::PI * t.powf(0.7)).sin();
            let lift = normal * (0.15 * w);
            let l = self.vertex(at(t) + side * w + lift);
            let r = self.vertex(at(t) - side * w + lift);
            self.indices.push([mid, left, m]);
            self.indices.push([left, l, m]);
            self.indices.push([mid, m, right]);
            self.indices.push([right, m, r]);
            (mid, left, right) = (m, l, r);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_match_what_is_built_and_no_triangle_is_degenerate() {
        let mut b = MeshBuilder::default();
        let path = [Vec3::ZERO, Vec3::Y, Vec3::new(0.3, 2.0, 0.0)];
        b.tube(&path, &[0.2, 0.15, 0.1], 7);
        assert_eq!(b.triangle_count(), MeshBuilder::tube_triangles(3, 7));
        let before = b.triangle_count();
        b.leaf(Vec3::ZERO, Vec3::X, Vec3::Z, 1.0, 0.4, 0.2, 5);
        assert_eq!(b.triangle_count() - before, MeshBuilder::leaf_triangles(5));
        b.quad(Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y);
        let m = b.into_mesh();
        for t in 0..m.triangle_count() {
            let [p0, p1, p2] = m.vertices(t);
            assert!((p1 - p0).cross(p2 - p0).length() > 1e-6, "triangle {t}");
        }
    }
}
