//! Tangents that mesh files state per vertex (glTF's `TANGENT`), interpolated at a hit.
//!
//! glTF 2.0 (section "Meshes", attribute `TANGENT`): xyz is the unit tangent, w (+1 or -1) the
//! handedness, and the bitangent is `cross(normal, tangent.xyz) * tangent.w`; a tangent-space normal
//! map's x runs along the tangent and its y along that bitangent.

use crate::math::Vec3;
use glam::Vec4;

/// A file's tangent frame at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FileTangent {
    /// Where tangent-space x points: the shading frame's `s` is it made orthogonal to `ns`.
    pub dir: Vec3,
    /// +1 or -1: tangent-space y runs along `sign * (ns × s)`.
    pub sign: f32,
}

impl FileTangent {
    /// The tangent at barycentrics `(b1, b2)` of the triangle whose vertices are `tri`: the
    /// vertices' xyz interpolated (made orthogonal to the normal later, as the shading frame is
    /// built), and the sign of the interpolated w (exporters give a triangle's three vertices the
    /// same w: MikkTSpace splits vertices where the handedness changes). `None` where the
    /// interpolated tangent vanishes or is not finite: the shading frame then follows dp/du.
    #[inline]
    pub fn at(tangents: &[Vec4], tri: [u32; 3], b1: f32, b2: f32) -> Option<FileTangent> {
        let b0 = 1.0 - b1 - b2;
        let [t0, t1, t2] = tri.map(|i| tangents[i as usize]);
        let t = b0 * t0 + b1 * t1 + b2 * t2;
        let dir = t.truncate();
        let len2 = dir.length_squared();
        (len2 > 0.0 && len2.is_finite()).then_some(FileTangent {
            dir,
            sign: if t.w < 0.0 { -1.0 } else { 1.0 },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_the_direction_and_keeps_the_handedness() {
        let t = [
            Vec4::new(1.0, 0.0, 0.0, -1.0),
            Vec4::new(0.0, 1.0, 0.0, -1.0),
            Vec4::new(0.0, 0.0, 1.0, -1.0),
        ];
        let f = FileTangent::at(&t, [0, 1, 2], 0.25, 0.5).unwrap();
        assert_eq!(f.dir, Vec3::new(0.25, 0.25, 0.5));
        assert_eq!(f.sign, -1.0);
        // w = 0 (a file that leaves it unset) reads as +1.
        let t = [Vec4::new(1.0, 0.0, 0.0, 0.0); 3];
        assert_eq!(FileTangent::at(&t, [0, 1, 2], 0.3, 0.3).unwrap().sign, 1.0);
    }

    #[test]
    fn vanishing_tangents_give_none() {
        let t = [
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::new(-1.0, 0.0, 0.0, 1.0),
            Vec4::ZERO,
        ];
        assert_eq!(FileTangent::at(&t, [0, 1, 2], 0.5, 0.0), None);
        assert_eq!(FileTangent::at(&t, [2, 2, 2], 0.2, 0.2), None);
        let nan = [Vec4::splat(f32::NAN); 3];
        assert_eq!(FileTangent::at(&nan, [0, 1, 2], 0.2, 0.2), None);
    }
}
