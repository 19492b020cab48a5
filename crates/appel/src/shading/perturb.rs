//! Shading normals perturbed by a texture, as Mitsuba 3 (3.7 and later) does in its `normalmap`
//! and `bumpmap` BSDF adapters: the texture gives a new normal relative to the surface's shading
//! frame, the nested BSDF is evaluated in a frame around it, and directions on different sides of
//! the two frames are rejected. The same core serves every format's normal maps (glTF
//! `normalTexture`, OBJ `norm`) and bump maps (OBJ `bump`).
//!
//! Everything here is in the coordinates of the unperturbed shading frame (`z` = shading normal),
//! so it is independent of how that frame sits in the world.

use super::frame::ShadingFrame;
use crate::math::{Vec2, Vec3};

/// A normal map's normal, unnormalized: the texture's RGB in [0, 1] mapped to [-1, 1] per axis
/// (tangent-space normal maps: x along the shading frame's `s`, which follows dp/du).
#[inline]
pub fn normal_from_map(rgb: Vec3) -> Vec3 {
    2.0 * rgb - Vec3::ONE
}

/// A bump map's normal, unnormalized (Blinn 1978, as Mitsuba's `bumpmap` computes it): the
/// surface's derivatives `dpdu` and `dpdv` with their normal components replaced by the height
/// field's gradient `grad` (already scaled), crossed, and turned to the side of the geometric
/// normal `n`. The base normal's own variation over the surface is neglected, so a constant
/// offset of the height field changes nothing.
#[inline]
pub fn normal_from_bump(grad: Vec2, dpdu: Vec3, dpdv: Vec3, n: Vec3) -> Vec3 {
    let du = Vec3::new(dpdu.x, dpdu.y, grad.x);
    let dv = Vec3::new(dpdv.x, dpdv.y, grad.y);
    let c = du.cross(dv);
    if n.dot(c) < 0.0 {
        -c
    } else {
        c
    }
}

/// The frame a perturbed normal induces, relative to the unperturbed shading frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perturbation {
    pub frame: ShadingFrame,
    /// Attenuate by [`shadow_terminator`].
    pub shadowing: bool,
}

impl Perturbation {
    /// The frame around normal `n` (unnormalized) for a surface seen from `wo`.
    ///
    /// With `flip_invalid`, a normal that faces away from `wo` (on the other side of `wo` from the
    /// one the shading normal is) has its tangential part negated, which brings it to `wo`'s side
    /// (Schüssler et al. 2017, section 4, as Mitsuba applies it). The tangent `s` is the shading
    /// frame's `x` made orthogonal to the new normal, so that anisotropic BSDFs stay aligned with
    /// the texture's u direction.
    pub fn new(n: Vec3, wo: Vec3, flip_invalid: bool, shadowing: bool) -> Self {
        let mut n = n;
        if flip_invalid && wo.z * wo.dot(n) <= 0.0 {
            n = Vec3::new(-n.x, -n.y, n.z);
        }
        let len2 = n.length_squared();
        let n = if len2 > 0.0 && len2.is_finite() {
            n / len2.sqrt()
        } else {
            Vec3::Z
        };
        let s = Vec3::X - n * n.x;
        let s_len2 = s.length_squared();
        let s = if s_len2 > 0.0 && s_len2.is_finite() {
            s / s_len2.sqrt()
        } else {
            Vec3::Y
        };
        Perturbation {
            frame: ShadingFrame {
                s,
                t: n.cross(s),
                n,
            },
            shadowing,
        }
    }

    /// The factor on the BSDF value for light arriving from `wi` (unperturbed coordinates).
    #[inline]
    pub fn attenuation(&self, wi: Vec3) -> f32 {
        if self.shadowing {
            shadow_terminator(self.frame.n, wi)
        } else {
            1.0
        }
    }
}

/// `tan^2` of the angle between unit `w` and the z axis.
#[inline]
fn tan2_theta(w: Vec3) -> f32 {
    let c2 = w.z * w.z;
    ((1.0 - c2).max(0.0) / c2).min(f32::MAX)
}

/// Conty Estevez, Lecocq and Stein 2019, "A Microfacet-Based Shadowing Function to Solve the Bump
/// Terminator Problem" (Ray Tracing Gems, chapter 12): the perturbed normal `n` is taken as a
/// microfacet normal of a GGX surface whose roughness grows with its tilt (`alpha^2 = tan^2 / 8`,
/// at most 1), and light from `wi` is attenuated by that surface's Smith shadowing, which fades
/// the hard terminator a tilted normal leaves where the true surface turns away.
#[inline]
pub fn shadow_terminator(n: Vec3, wi: Vec3) -> f32 {
    let alpha2 = (0.125 * tan2_theta(n)).min(1.0);
    2.0 / (1.0 + (1.0 + alpha2 * tan2_theta(wi)).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_untilted_map_changes_nothing() {
        let p = Perturbation::new(
            normal_from_map(Vec3::new(0.5, 0.5, 1.0)),
            Vec3::Z,
            true,
            true,
        );
        assert_eq!(p.frame.n, Vec3::Z);
        assert_eq!(p.frame.s, Vec3::X);
        assert_eq!(p.frame.t, Vec3::Y);
        for wi in [
            Vec3::Z,
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(0.0, -0.99, 0.141),
        ] {
            assert_eq!(p.attenuation(wi.normalize()), 1.0);
        }
        // A flat height field: the base normal.
        let n = normal_from_bump(Vec2::ZERO, Vec3::X * 2.0, Vec3::Y * 3.0, Vec3::Z);
        assert_eq!(n.normalize(), Vec3::Z);
    }

    #[test]
    fn bump_normal_tilts_against_the_slope() {
        // Height rising along u: the normal leans towards -u, by atan(slope / |dpdu|).
        let n = normal_from_bump(Vec2::new(0.5, 0.0), Vec3::X, Vec3::Y, Vec3::Z).normalize();
        assert!(
            (n - Vec3::new(-0.5, 0.0, 1.0).normalize()).length() < 1e-6,
            "{n}"
        );
        // The geometric normal decides the side.
        let m = normal_from_bump(Vec2::new(0.5, 0.0), Vec3::Y, Vec3::X, Vec3::Z);
        assert!(m.z > 0.0);
    }

    #[test]
    fn frames_are_orthonormal_and_invalid_normals_flip_to_the_viewer() {
        let n = Vec3::new(0.7, -0.3, 0.4);
        let wo = Vec3::new(0.8, -0.2, 0.3).normalize();
        let p = Perturbation::new(n, wo, true, false);
        let f = p.frame;
        assert!((f.n - n.normalize()).length() < 1e-6);
        assert!(f.s.dot(f.n).abs() < 1e-6 && f.t.dot(f.n).abs() < 1e-6);
        assert!((f.s.cross(f.t) - f.n).length() < 1e-5);
        // s stays in the plane of x and n.
        assert!(f.s.dot(Vec3::new(1.0, 0.0, 0.0)) > 0.0 && f.s.dot(n.cross(Vec3::X)).abs() < 1e-6);
        // Seen from the other side of n, the tangential part turns around.
        let wo = Vec3::new(-0.9, 0.3, 0.2).normalize();
        assert!(wo.dot(n) < 0.0);
        let q = Perturbation::new(n, wo, true, false);
        assert!((q.frame.n - Vec3::new(-0.7, 0.3, 0.4).normalize()).length() < 1e-6);
        assert!(wo.dot(q.frame.n) > 0.0);
        let r = Perturbation::new(n, wo, false, false);
        assert!((r.frame.n - n.normalize()).length() < 1e-6);
        // Degenerate normals fall back to the shading normal.
        assert_eq!(
            Perturbation::new(Vec3::ZERO, wo, false, false).frame.n,
            Vec3::Z
        );
    }

    #[test]
    fn shadowing_by_hand() {
        // n tilted by 45 degrees: alpha^2 = 1/8; light at 60 degrees: tan^2 = 3.
        let n = Vec3::new(1.0, 0.0, 1.0).normalize();
        let wi = Vec3::new(3f32.sqrt() / 2.0, 0.0, 0.5);
        let want = 2.0 / (1.0 + (1.0f32 + 3.0 / 8.0).sqrt());
        assert!((shadow_terminator(n, wi) - want).abs() < 1e-6);
        // Grazing light is shadowed entirely, light along the normal not at all.
        assert!(shadow_terminator(n, Vec3::new(1.0, 0.0, 1e-6).normalize()) < 1e-3);
        assert_eq!(shadow_terminator(n, Vec3::Z), 1.0);
    }
}
