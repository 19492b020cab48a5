//! Fresnel equations and the mirror and refraction directions, in the local shading frame, with
//! the conventions of Mitsuba 3's `fresnel.h` (unpolarized light).

use crate::math::Vec3;

/// Unpolarized Fresnel reflectance at a dielectric interface of relative IOR `eta` (inside over
/// outside), for a direction on the side given by the sign of `cos_theta_i` (positive: outside).
///
/// Returns `(r, cos_theta_t, eta_it, eta_ti)`: the reflectance, the signed cosine of the refracted
/// direction (opposite side to `cos_theta_i`; 0 under total internal reflection), and the relative
/// IORs across the crossing in both orders. `r` is 1 at exactly grazing incidence and 0 when the
/// indices match, as in Mitsuba.
#[inline]
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> (f32, f32, f32, f32) {
    let outside = cos_theta_i >= 0.0;
    let rcp_eta = 1.0 / eta;
    let (eta_it, eta_ti) = if outside {
        (eta, rcp_eta)
    } else {
        (rcp_eta, eta)
    };
    // Snell's law: cos²θt = 1 - sin²θi / η².
    let cos_theta_t_sqr = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * (eta_ti * eta_ti);
    let cos_i = cos_theta_i.abs();
    let cos_t = cos_theta_t_sqr.max(0.0).sqrt();
    let index_matched = eta == 1.0;
    let r = if index_matched {
        0.0
    } else if cos_i == 0.0 {
        1.0
    } else {
        // Amplitudes of the s- and p-polarized reflected waves (Hecht, "Optics", 4.4).
        let a_s = (cos_i - eta_it * cos_t) / (cos_i + eta_it * cos_t);
        let a_p = (cos_t - eta_it * cos_i) / (cos_t + eta_it * cos_i);
        0.5 * (a_s * a_s + a_p * a_p)
    };
    let cos_theta_t = if cos_theta_i >= 0.0 { -cos_t } else { cos_t };
    (r, cos_theta_t, eta_it, eta_ti)
}

/// Unpolarized Fresnel reflectance of a conductor of complex relative IOR `eta + i k`, per RGB
/// channel, for `cos_theta_i` in [0, 1] (Moeller, "Optics", 1988, as Mitsuba's
/// `fresnel_conductor`). `eta = 0, k = 1` reflects everything at every angle.
#[inline]
pub fn fresnel_conductor(cos_theta_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let cos2 = cos_theta_i * cos_theta_i;
    let sin2 = 1.0 - cos2;
    let sin4 = sin2 * sin2;
    let temp_1 = eta * eta - k * k - Vec3::splat(sin2);
    let a2pb2 = (temp_1 * temp_1 + 4.0 * k * k * eta * eta)
        .max(Vec3::ZERO)
        .powf(0.5);
    let a = (0.5 * (a2pb2 + temp_1)).max(Vec3::ZERO).powf(0.5);
    let term_1 = a2pb2 + Vec3::splat(cos2);
    let term_2 = 2.0 * cos_theta_i * a;
    let r_s = (term_1 - term_2) / (term_1 + term_2);
    let term_3 = a2pb2 * cos2 + Vec3::splat(sin4);
    let term_4 = term_2 * sin2;
    let r_p = r_s * (term_3 - term_4) / (term_3 + term_4);
    0.5 * (r_s + r_p)
}

/// Hemispherical average of the Fresnel reflectance seen from a medium of relative IOR `eta`
/// (`2 ∫ F(cos θ) cos θ dcos θ`), by the fits Mitsuba's `fresnel_diffuse_reflectance` uses:
/// Egan and Hilgeman (1973) for `eta < 1`, d'Eon and Irving (2011) otherwise.
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    let inv_eta = 1.0 / eta;
    if eta < 1.0 {
        0.0636 * inv_eta + eta * (eta * -1.4399 + 0.7099) + 0.6681
    } else {
        // Horner form of 0.919317 - 3.4793 x + 6.75335 x² - 7.80989 x³ + 4.98554 x⁴ - 1.36881 x⁵,
        // x = 1 / eta.
        let x = inv_eta;
        0.919317 + x * (-3.4793 + x * (6.75335 + x * (-7.80989 + x * (4.98554 + x * -1.36881))))
    }
}

/// Mirror direction about the normal `z`.
#[inline]
pub fn reflect(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

/// Mirror direction of `w` about the unit microfacet normal `m`.
#[inline]
pub fn reflect_about(w: Vec3, m: Vec3) -> Vec3 {
    2.0 * w.dot(m) * m - w
}

/// Refracted direction through the interface `z`, given `cos_theta_t` and `eta_ti` from
/// [`fresnel_dielectric`].
#[inline]
pub fn refract(w: Vec3, cos_theta_t: f32, eta_ti: f32) -> Vec3 {
    Vec3::new(-eta_ti * w.x, -eta_ti * w.y, cos_theta_t)
}

/// Refracted direction through a microfacet of unit normal `m`, given `cos_theta_t` and `eta_ti`
/// from [`fresnel_dielectric`] of `w · m`.
#[inline]
pub fn refract_about(w: Vec3, m: Vec3, cos_theta_t: f32, eta_ti: f32) -> Vec3 {
    m * (w.dot(m) * eta_ti + cos_theta_t) - w * eta_ti
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_against_closed_forms() {
        // Normal incidence: ((η - 1) / (η + 1))², from either side.
        let (r, ct, eta_it, eta_ti) = fresnel_dielectric(1.0, 1.5);
        assert!((r - 0.04).abs() < 1e-7 && ct == -1.0 && eta_it == 1.5 && eta_ti == 1.0 / 1.5);
        let (r, ct, eta_it, _) = fresnel_dielectric(-1.0, 1.5);
        assert!((r - 0.04).abs() < 1e-7 && ct == 1.0 && eta_it == 1.0 / 1.5);
        // Total internal reflection beyond the critical angle asin(1 / 1.5) = 41.8°.
        let cos_45 = std::f32::consts::FRAC_1_SQRT_2;
        assert_eq!(fresnel_dielectric(-cos_45, 1.5).0, 1.0);
        assert_eq!(fresnel_dielectric(-cos_45, 1.5).1, 0.0);
        // Brewster's angle tan θ = η: p-polarized reflectance vanishes, r = r_s / 2.
        let theta_b = 1.5f32.atan();
        let (r, ct, _, _) = fresnel_dielectric(theta_b.cos(), 1.5);
        let (ci, ctt) = (theta_b.cos(), -ct);
        let rs = ((ci - 1.5 * ctt) / (ci + 1.5 * ctt)).powi(2);
        assert!((r - 0.5 * rs).abs() < 1e-6, "{r} {rs}");
        // Index matched and grazing special cases.
        assert_eq!(fresnel_dielectric(0.3, 1.0).0, 0.0);
        assert_eq!(fresnel_dielectric(0.0, 1.5).0, 1.0);
        // Snell's law holds for the refracted direction, and it is unit length.
        let w = Vec3::new(0.6, 0.0, 0.8);
        let (_, ct, _, eta_ti) = fresnel_dielectric(w.z, 1.33);
        let t = refract(w, ct, eta_ti);
        assert!((t.length() - 1.0).abs() < 1e-6 && t.z < 0.0);
        assert!((0.6 - 1.33 * t.x.abs()).abs() < 1e-6);
        // Mitsuba 3: mi.fresnel(0.5, 1.5) = (0.0891867, -0.816497, 1.5, 0.666667),
        // mi.fresnel(-0.8, 1.33) = (0.0383115, 0.602657, 0.75188, 1.33).
        let (r, ct, _, _) = fresnel_dielectric(0.5, 1.5);
        assert!((r - 0.0891867).abs() < 1e-6 && (ct + 0.816497).abs() < 1e-6);
        let (r, ct, _, _) = fresnel_dielectric(-0.8, 1.33);
        assert!((r - 0.0383115).abs() < 1e-6 && (ct - 0.602657).abs() < 1e-6);
    }

    #[test]
    fn conductor_limits_and_mitsuba() {
        // k = 0 reduces to the dielectric formula.
        for c in [1.0f32, 0.7, 0.3] {
            let f = fresnel_conductor(c, Vec3::splat(1.5), Vec3::ZERO);
            assert!((f.x - fresnel_dielectric(c, 1.5).0).abs() < 1e-6, "{c}");
        }
        // eta = 0, k = 1 is a perfect mirror.
        for c in [1.0f32, 0.5, 0.01] {
            assert!((fresnel_conductor(c, Vec3::ZERO, Vec3::ONE) - Vec3::ONE).length() < 1e-6);
        }
        // Normal incidence: ((η - 1)² + k²) / ((η + 1)² + k²).
        let f = fresnel_conductor(1.0, Vec3::splat(0.2), Vec3::splat(3.0));
        assert!((f.x - (0.64 + 9.0) / (1.44 + 9.0)).abs() < 1e-6);
        // Mitsuba 3: mi.fresnel_conductor(0.6, mi.Complex2f(0.2, 3.9)) = 0.948190.
        let f = fresnel_conductor(0.6, Vec3::splat(0.2), Vec3::splat(3.9));
        assert!((f.x - 0.948190).abs() < 1e-5, "{f}");
    }

    #[test]
    fn diffuse_reflectance_against_mitsuba() {
        // Mitsuba 3: mi.fresnel_diffuse_reflectance(1.5) = 0.0917743, (1 / 1.5) = 0.596811.
        assert!((fresnel_diffuse_reflectance(1.5) - 0.0917743).abs() < 1e-6);
        assert!((fresnel_diffuse_reflectance(1.0 / 1.5) - 0.596811).abs() < 1e-6);
    }

    #[test]
    fn directions() {
        let w = Vec3::new(0.3, -0.4, 0.866_025_4);
        assert_eq!(reflect(w), reflect_about(w, Vec3::Z));
        let m = Vec3::new(0.1, 0.2, 0.9).normalize();
        let r = reflect_about(w, m);
        assert!((r.length() - 1.0).abs() < 1e-6 && ((r + w).normalize() - m).length() < 1e-6);
        let (_, ct, _, eta_ti) = fresnel_dielectric(w.dot(m), 1.5);
        let t = refract_about(w, m, ct, eta_ti);
        assert!((t.length() - 1.0).abs() < 1e-5);
        // The generalized half vector of a refraction, w + η t, is along -m (Walter et al. 2007).
        assert!(((w + 1.5 * t).normalize() + m).length() < 1e-5);
    }
}
