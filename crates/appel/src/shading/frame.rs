//! The local shading frame in which BSDFs are evaluated: `z` is the shading normal.

use crate::math::{orthonormal_basis, Vec3};

/// An orthonormal basis: tangent `s`, bitangent `t`, normal `n` (right-handed, `s × t = n`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingFrame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl ShadingFrame {
    /// A frame around unit normal `n`, with the branch-free basis of Duff et al. 2017 ("Building
    /// an orthonormal basis, revisited"), the one Mitsuba 3's `Frame3f(n)` builds, so isotropic
    /// BSDFs see the same local directions.
    pub fn from_normal(n: Vec3) -> Self {
        let (s, t) = orthonormal_basis(n);
        ShadingFrame { s, t, n }
    }

    /// A frame around unit normal `n` whose `s` follows the surface tangent `dpdu` (Gram-Schmidt:
    /// `dpdu` minus its component along `n`, normalized; `t = n × s`), as Mitsuba orients its
    /// shading frame, so that anisotropic roughness `alpha_u` runs along `u`. Falls back to
    /// [`ShadingFrame::from_normal`] when `dpdu` is zero, not finite or parallel to `n`.
    pub fn from_normal_tangent(n: Vec3, dpdu: Vec3) -> Self {
        let s = dpdu - n * n.dot(dpdu);
        let len2 = s.length_squared();
        if !len2.is_finite() || len2 <= 1e-20 * dpdu.length_squared() {
            return Self::from_normal(n);
        }
        let s = s / len2.sqrt();
        ShadingFrame {
            s,
            t: n.cross(s),
            n,
        }
    }

    /// World direction `v` in this frame's coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local direction `v` back in world coordinates.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_orthonormal(f: &ShadingFrame) {
        for (a, b) in [(f.s, f.t), (f.t, f.n), (f.n, f.s)] {
            assert!(a.dot(b).abs() < 1e-6, "{f:?}");
        }
        for v in [f.s, f.t, f.n] {
            assert!((v.length() - 1.0).abs() < 1e-6, "{f:?}");
        }
        assert!((f.s.cross(f.t) - f.n).length() < 1e-5, "{f:?}");
    }

    #[test]
    fn frames_are_orthonormal_and_round_trip() {
        let normals = [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.5, 0.8).normalize(),
            Vec3::new(1e-4, 2e-4, -1.0).normalize(),
            Vec3::new(-0.7, 0.7, -0.1).normalize(),
        ];
        let v = Vec3::new(0.2, -0.9, 0.4);
        for n in normals {
            let f = ShadingFrame::from_normal(n);
            assert_orthonormal(&f);
            assert!((f.to_local(n) - Vec3::Z).length() < 1e-6);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-5);
            let g = ShadingFrame::from_normal_tangent(n, Vec3::new(1.0, 2.0, 3.0));
            assert_orthonormal(&g);
            // s lies in the plane of n and dpdu, on dpdu's side.
            assert!(g.s.dot(Vec3::new(1.0, 2.0, 3.0)) > 0.0);
            assert!(n.cross(Vec3::new(1.0, 2.0, 3.0)).dot(g.s).abs() < 1e-5);
            assert!((g.to_world(g.to_local(v)) - v).length() < 1e-5);
        }
    }

    #[test]
    fn tangent_fallbacks() {
        let n = Vec3::new(0.0, 0.6, 0.8);
        for dpdu in [Vec3::ZERO, n * 3.0, Vec3::splat(f32::NAN)] {
            assert_eq!(
                ShadingFrame::from_normal_tangent(n, dpdu),
                ShadingFrame::from_normal(n)
            );
        }
        let f = ShadingFrame::from_normal_tangent(Vec3::Z, Vec3::new(2.0, 0.0, 5.0));
        assert!((f.s - Vec3::X).length() < 1e-6 && (f.t - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn matches_mitsuba_frame() {
        // Mitsuba 3 (scalar_rgb): mi.Frame3f(mi.Vector3f(0.3, -0.5, 0.8) normalized) has
        // s = [0.949209, 0.0846521, -0.303046], t = [0.0846521, 0.858913, 0.505076].
        let f = ShadingFrame::from_normal(Vec3::new(0.3, -0.5, 0.8).normalize());
        assert!(
            (f.s - Vec3::new(0.949209, 0.0846521, -0.303046)).length() < 1e-5,
            "{f:?}"
        );
        assert!(
            (f.t - Vec3::new(0.0846521, 0.858913, 0.505076)).length() < 1e-5,
            "{f:?}"
        );
    }
}
