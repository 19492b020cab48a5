//! Reflection, refraction and Fresnel's equations.

use crate::math::Vec3;

/// Mirror direction of incident direction `d` about the unit normal `n`.
#[inline]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Refracted direction by Snell's law for unit incident direction `d` and unit normal `n` on the
/// incident side (`dot(d, n) < 0`), with `eta = n_incident / n_transmitted`. `None` on total internal
/// reflection.
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * d + (eta * cos_i - cos_t) * n).normalize())
}

/// Fresnel reflectance of unpolarized light at a dielectric boundary (the average of the s and p
/// terms), for `cos_i` on the incident side and `eta = n_incident / n_transmitted`. 1 past the
/// critical angle.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_s = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_p = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_s * r_s + r_p * r_p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_flips_the_normal_component() {
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        let r = reflect(d, Vec3::Y);
        assert!((r - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn snell_law_holds() {
        let theta_i = 30f32.to_radians();
        let d = Vec3::new(theta_i.sin(), -theta_i.cos(), 0.0);
        let t = refract(d, Vec3::Y, 1.0 / 1.5).unwrap();
        let sin_t = t.x;
        assert!((theta_i.sin() - 1.5 * sin_t).abs() < 1e-6);
        assert!(t.y < 0.0);
    }

    #[test]
    fn total_internal_reflection_past_the_critical_angle() {
        let critical = (1.0f32 / 1.5).asin();
        let just_below = critical - 0.01;
        let just_above = critical + 0.01;
        let dir = |a: f32| Vec3::new(a.sin(), -a.cos(), 0.0);
        assert!(refract(dir(just_below), Vec3::Y, 1.5).is_some());
        assert!(refract(dir(just_above), Vec3::Y, 1.5).is_none());
        assert_eq!(fresnel_dielectric(just_above.cos(), 1.5), 1.0);
    }

    #[test]
    fn fresnel_at_normal_incidence_is_the_known_four_percent() {
        // ((n1 - n2) / (n1 + n2))^2 = 0.04 for glass.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_dielectric(0.0, 1.0 / 1.5) - 1.0).abs() < 1e-6);
    }
}
