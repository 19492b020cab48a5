//! Floating-point error bounds, after pbrt-v4 section 6.8 ("Managing rounding error").
//!
//! Secondary rays leave a surface from a point offset along the normal by the bound on the rounding
//! error of the hit point. The bound scales with the magnitude of the coordinates, so the same offset
//! logic works for a scene of size 1e-3 and one of size 1e5: there is no scene epsilon anywhere.

use glam::Vec3;

/// `gamma(n) = n * u / (1 - n * u)` with `u` the unit roundoff of f32: a bound on the relative error of
/// `n` chained floating-point operations (Higham 2002, pbrt-v4 eq. 6.8).
#[inline]
pub const fn gamma(n: i32) -> f32 {
    let u = f32::EPSILON * 0.5;
    let nu = n as f32 * u;
    nu / (1.0 - nu)
}

/// Moves `p`, whose coordinates are each within `p_error` of the true surface point, off the surface
/// along the geometric normal `n` to the side that `w` points into, far enough that a ray leaving from
/// the result cannot re-hit the surface it starts on (pbrt-v4 `OffsetRayOrigin`).
#[inline]
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    offset_ray_origin_to_side(p, p_error, n, w.dot(n) < 0.0)
}

/// [`offset_ray_origin`] for every `w` with `(w.dot(n) < 0.0) == below`: the result depends on `w`
/// only through that side, so a shading point computes each of its two possible origins once.
/// Inlined at each use, so that each kind of ray (shadow, reflected, refracted) has its own branches
/// in `round_away`, which the predictor then learns separately.
#[inline(always)]
pub fn offset_ray_origin_to_side(p: Vec3, p_error: Vec3, n: Vec3, below: bool) -> Vec3 {
    offset_ray_origin_by(p, surface_offset(p_error, n), below)
}

/// The offset of [`offset_ray_origin`] to the side `n` points to: along the normal, far enough to
/// leave the error box `p_error`.
#[inline(always)]
pub fn surface_offset(p_error: Vec3, n: Vec3) -> Vec3 {
    n.abs().dot(p_error) * n
}

/// [`offset_ray_origin_to_side`] with its [`surface_offset`] already known: the same value.
#[inline(always)]
pub fn offset_ray_origin_by(p: Vec3, mut offset: Vec3, below: bool) -> Vec3 {
    if below {
        offset = -offset;
    }
    let po = p + offset;
    // Round away from p, so the offset survives the rounding of the addition above.
    Vec3::new(
        round_away(po.x, offset.x),
        round_away(po.y, offset.y),
        round_away(po.z, offset.z),
    )
}

/// `po.next_up()` if `off > 0`, `po.next_down()` if `off < 0`, else `po`: the same values as the
/// standard functions for every input, with one integer step on the bits in the common case (a
/// finite, non-zero `po`), which is all this hot path (two calls per shading point) ever sees.
#[inline(always)]
fn round_away(po: f32, off: f32) -> f32 {
    let bits = po.to_bits();
    let magnitude = bits & 0x7fff_ffff;
    if off == 0.0 || off.is_nan() || magnitude == 0 || magnitude >= 0x7f80_0000 {
        // Zero offset, a zero `po` (whose neighbour is the smallest subnormal of the other sign),
        // infinities and NaN: the standard functions.
        return if off > 0.0 {
            po.next_up()
        } else if off < 0.0 {
            po.next_down()
        } else {
            po
        };
    }
    // A step away from zero when `po` and `off` have the same sign, towards zero otherwise.
    let away = (bits >> 31) == (off.to_bits() >> 31);
    f32::from_bits(if away { bits + 1 } else { bits - 1 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_grows_with_operation_count() {
        assert!(gamma(1) > 0.0);
        assert!(gamma(5) > gamma(3));
        assert!((gamma(1) - f32::EPSILON * 0.5).abs() < 1e-12);
    }

    #[test]
    fn offset_moves_to_the_side_of_w_by_at_least_the_error() {
        let p = Vec3::new(1.0e4, 0.0, 3.0);
        let err = Vec3::splat(1e-3);
        let n = Vec3::Y;
        let up = offset_ray_origin(p, err, n, Vec3::new(0.3, 1.0, 0.0));
        let down = offset_ray_origin(p, err, n, Vec3::new(0.3, -1.0, 0.0));
        assert!(up.y >= 1e-3 && down.y <= -1e-3);
        assert_eq!(up.x, p.x);
    }

    #[test]
    fn round_away_is_next_up_or_next_down() {
        let values = [
            1.0f32,
            -1.0,
            0.0,
            -0.0,
            1e-40,
            -1e-40,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::MAX,
            -f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            3.5e7,
            -2.25e-3,
            16777216.0,
        ];
        for &po in &values {
            for &off in &[1e-7f32, -1e-7, 0.0, -0.0, 1e30, -1e-45, f32::NAN] {
                let expected = if off > 0.0 {
                    po.next_up()
                } else if off < 0.0 {
                    po.next_down()
                } else {
                    po
                };
                let got = round_away(po, off);
                assert!(
                    got.to_bits() == expected.to_bits() || (got.is_nan() && expected.is_nan()),
                    "po {po:e} off {off:e}: {got:e} != {expected:e}"
                );
            }
        }
    }
}
