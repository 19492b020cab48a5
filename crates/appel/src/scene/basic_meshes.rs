//! Mitsuba's parametric shapes as triangle meshes in their local frames: `rectangle` ([-1, 1]^2 at
//! z = 0, facing +z), `cube` ([-1, 1]^3, faces outward) and `disk` (the unit disk at z = 0, facing
//! +z). The rectangle and the cube are exact as meshes (Mitsuba's cube is one); the disk is a fan
//! of `DISK_SEGMENTS` triangles whose area is within 0.01% of the circle's.

use crate::geometry::TriangleMesh;
use crate::math::{Vec2, Vec3};
use glam::Mat4;

pub const DISK_SEGMENTS: u32 = 256;

/// uv as Mitsuba's rectangle: `((x + 1) / 2, (y + 1) / 2)`.
pub fn rectangle() -> TriangleMesh {
    let positions = vec![
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ];
    let uvs = positions
        .iter()
        .map(|p| Vec2::new(p.x * 0.5 + 0.5, p.y * 0.5 + 0.5))
        .collect();
    TriangleMesh {
        positions,
        indices: vec![[0, 1, 2], [0, 2, 3]],
        normals: None,
        uvs: Some(uvs),
    }
}

/// Six faces of four vertices each (so that each face has its own uv square), wound outward,
/// with Mitsuba's corners and uvs: each face's corners in the order Mitsuba's `cube` lists them,
/// taking uv (0, 1), (1, 1), (1, 0), (0, 0), and its two triangles (0, 1, 2) and (3, 0, 2). The
/// orientation of each face's uv square matters to any texture that is not symmetric.
pub fn cube() -> TriangleMesh {
    const FACES: [[[f32; 3]; 4]; 6] = [
        [
            [1., -1., -1.],
            [1., -1., 1.],
            [-1., -1., 1.],
            [-1., -1., -1.],
        ],
        [[1., 1., -1.], [-1., 1., -1.], [-1., 1., 1.], [1., 1., 1.]],
        [[1., -1., -1.], [1., 1., -1.], [1., 1., 1.], [1., -1., 1.]],
        [[1., -1., 1.], [1., 1., 1.], [-1., 1., 1.], [-1., -1., 1.]],
        [
            [-1., -1., 1.],
            [-1., 1., 1.],
            [-1., 1., -1.],
            [-1., -1., -1.],
        ],
        [
            [1., 1., -1.],
            [1., -1., -1.],
            [-1., -1., -1.],
            [-1., 1., -1.],
        ],
    ];
    const UVS: [[f32; 2]; 4] = [[0., 1.], [1., 1.], [1., 0.], [0., 0.]];
    let mut positions = Vec::with_capacity(24);
    let mut uvs = Vec::with_capacity(24);
    let mut indices = Vec::with_capacity(12);
    for face in FACES {
        let base = positions.len() as u32;
        for (corner, uv) in face.iter().zip(UVS) {
            positions.push(Vec3::from(*corner));
            uvs.push(Vec2::from(uv));
        }
        indices.push([base, base + 1, base + 2]);
        indices.push([base + 3, base, base + 2]);
    }
    TriangleMesh {
        positions,
        indices,
        normals: None,
        uvs: Some(uvs),
    }
}

/// A fan around the centre; uv as Mitsuba's disk: (radius, angle / 2 pi). Each triangle has its
/// own centre vertex, at the angle of its middle, and the rim closes on a vertex at angle 1 (not
/// 0): interpolated across a triangle, v then stays within 1 / (2 `DISK_SEGMENTS`) of the angle
/// instead of winding into a spiral.
pub fn disk() -> TriangleMesh {
    let n = DISK_SEGMENTS;
    // The fan's vertices lie at a radius that gives the polygon the circle's area:
    // n/2 r^2 sin(2 pi / n) = pi.
    let step = std::f32::consts::TAU / n as f32;
    let r = (std::f32::consts::PI / (0.5 * n as f32 * step.sin())).sqrt();
    let mut positions = Vec::with_capacity(2 * n as usize + 1);
    let mut uvs = Vec::with_capacity(2 * n as usize + 1);
    for i in 0..=n {
        let phi = i as f32 * step;
        positions.push(Vec3::new(r * phi.cos(), r * phi.sin(), 0.0));
        uvs.push(Vec2::new(1.0, i as f32 / n as f32));
    }
    let mut indices = Vec::with_capacity(n as usize);
    for i in 0..n {
        let centre = positions.len() as u32;
        positions.push(Vec3::ZERO);
        uvs.push(Vec2::new(0.0, (i as f32 + 0.5) / n as f32));
        indices.push([centre, i, i + 1]);
    }
    TriangleMesh {
        positions,
        indices,
        normals: None,
        uvs: Some(uvs),
    }
}

/// A `trianglemesh` shape's mesh, placed by its transform.
pub fn inline_mesh(t: &crate::description::TriangleMeshDesc) -> TriangleMesh {
    let mesh = TriangleMesh {
        positions: t.positions.iter().map(|&p| p.into()).collect(),
        indices: t.indices.clone(),
        normals: t
            .normals
            .as_ref()
            .map(|n| n.iter().map(|&n| Vec3::from(n)).collect()),
        uvs: t
            .uvs
            .as_ref()
            .map(|u| u.iter().map(|&u| u.into()).collect()),
    };
    let m = t.transform.as_ref().map_or(Mat4::IDENTITY, |t| t.matrix());
    let mut mesh = transformed(mesh, m);
    if t.flip_normals {
        flip_normals(&mut mesh);
    }
    mesh
}

/// The mesh moved by `m` (normals by its inverse transpose).
pub fn transformed(mut mesh: TriangleMesh, m: Mat4) -> TriangleMesh {
    for p in &mut mesh.positions {
        *p = m.transform_point3(*p);
    }
    if let Some(normals) = &mut mesh.normals {
        let nm = m.inverse().transpose();
        for n in normals {
            *n = nm.transform_vector3(*n).normalize_or_zero();
        }
    }
    // A mirroring transform turns the winding, and so the geometric normal, inside out: wind
    // the triangles back so that the front stays where the transformed +z (or outside) is.
    if m.determinant() < 0.0 {
        flip_winding(&mut mesh);
    }
    mesh
}

/// Turns the surface's front side around: reversed winding and negated vertex normals.
pub fn flip_winding(mesh: &mut TriangleMesh) {
    for t in &mut mesh.indices {
        t.swap(1, 2);
    }
}

/// [`flip_winding`] and the vertex normals negated.
pub fn flip_normals(mesh: &mut TriangleMesh) {
    flip_winding(mesh);
    if let Some(normals) = &mut mesh.normals {
        for n in normals {
            *n = -*n;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area_and_normal_sum(m: &TriangleMesh) -> (f32, Vec3) {
        let mut area = 0.0;
        let mut sum = Vec3::ZERO;
        for t in 0..m.triangle_count() {
            let [a, b, c] = m.vertices(t);
            let n = (b - a).cross(c - a);
            area += 0.5 * n.length();
            sum += 0.5 * n;
        }
        (area, sum)
    }

    #[test]
    fn shapes_have_mitsubas_areas_and_orientation() {
        let (a, n) = area_and_normal_sum(&rectangle());
        assert!((a - 4.0).abs() < 1e-6 && (n - Vec3::new(0.0, 0.0, 4.0)).length() < 1e-6);
        let (a, n) = area_and_normal_sum(&disk());
        assert!((a - std::f32::consts::PI).abs() < 1e-4 && n.z > 0.0);
        let c = cube();
        let (a, n) = area_and_normal_sum(&c);
        assert!((a - 24.0).abs() < 1e-5 && n.length() < 1e-5);
        // Outward: every face's normal points away from the centre.
        for t in 0..c.triangle_count() {
            let [p0, p1, p2] = c.vertices(t);
            assert!((p1 - p0).cross(p2 - p0).dot(p0 + p1 + p2) > 0.0);
        }
    }

    /// Texture coordinates follow Mitsuba's: the disk's (radius, angle / 2 pi) at the middle of
    /// each triangle, and the cube's +z face maps (1, -1) to uv (0, 1) and (-1, 1) to (1, 0).
    #[test]
    fn uvs_follow_mitsubas_parameterisations() {
        let d = disk();
        let uvs = d.uvs.as_ref().unwrap();
        for t in [0, 7, DISK_SEGMENTS as usize - 1] {
            let [a, b, c] = d.indices[t];
            let (b0, b1, b2) = (0.4, 0.35, 0.25);
            let p = b0 * d.positions[a as usize]
                + b1 * d.positions[b as usize]
                + b2 * d.positions[c as usize];
            let uv = b0 * uvs[a as usize] + b1 * uvs[b as usize] + b2 * uvs[c as usize];
            let mut phi = p.y.atan2(p.x);
            if phi < 0.0 {
                phi += std::f32::consts::TAU;
            }
            assert!((uv.y - phi / std::f32::consts::TAU).abs() < 1.0 / DISK_SEGMENTS as f32);
            assert!((uv.x - p.length()).abs() < 1e-3, "{uv} {p}");
        }
        let c = cube();
        // The +z face is the fourth: corners (1, -1, 1), (1, 1, 1), (-1, 1, 1), (-1, -1, 1).
        assert_eq!(c.positions[12], Vec3::new(1.0, -1.0, 1.0));
        assert_eq!(c.uvs.as_ref().unwrap()[12], Vec2::new(0.0, 1.0));
        assert_eq!(c.positions[14], Vec3::new(-1.0, 1.0, 1.0));
        assert_eq!(c.uvs.as_ref().unwrap()[14], Vec2::new(1.0, 0.0));
    }

    #[test]
    fn a_mirroring_transform_keeps_the_front() {
        let m = transformed(rectangle(), Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
        let (_, n) = area_and_normal_sum(&m);
        assert!(n.z > 0.0);
    }
}
