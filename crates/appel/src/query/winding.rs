//! The generalized winding number (Jacobson, Kavan and Sorkine-Hornung 2013, "Robust Inside-Outside
//! Segmentation using Generalized Winding Numbers", eq. 4): the signed solid angles of all
//! triangles seen from a point, over 4 pi. For a closed, consistently oriented mesh it is exactly 1
//! inside and 0 outside, and it stays accurate as the point approaches the surface, where ray
//! parity can no longer be trusted (a ray starting within its own error bound of a triangle).

use crate::geometry::TriangleMesh;
use glam::DVec3;

/// The signed solid angle of triangle `(a, b, c)` seen from the origin, by Van Oosterom and
/// Strackee's formula (1983): `tan(omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| +
/// (c.a)|b|)`, evaluated with `atan2` so that every quadrant is right.
fn solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let det = a.dot(b.cross(c));
    let div = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    2.0 * det.atan2(div)
}

/// The winding number of `mesh` around `p`, in f64: near 1 inside, near 0 outside a closed mesh
/// whose triangles wind counter-clockwise seen from outside.
pub fn winding_number(mesh: &TriangleMesh, p: DVec3) -> f64 {
    let sum: f64 = mesh
        .indices
        .iter()
        .map(|t| {
            let v = |i: u32| mesh.positions[i as usize].as_dvec3() - p;
            solid_angle(v(t[0]), v(t[1]), v(t[2]))
        })
        .sum();
    sum / (4.0 * std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::procedural::{cube, icosphere};

    #[test]
    fn inside_is_one_and_outside_zero() {
        for mesh in [cube(), icosphere(2)] {
            assert!((winding_number(&mesh, DVec3::ZERO) - 1.0).abs() < 1e-9);
            assert!(winding_number(&mesh, DVec3::new(3.0, 0.2, 0.1)).abs() < 1e-9);
        }
    }

    #[test]
    fn a_point_a_millionth_inside_a_vertex_is_inside() {
        let mesh = icosphere(0);
        let v = mesh.positions[0].as_dvec3();
        assert!(winding_number(&mesh, v * (1.0 - 1e-6)) > 0.5);
        assert!(winding_number(&mesh, v * (1.0 + 1e-6)) < 0.5);
    }
}
