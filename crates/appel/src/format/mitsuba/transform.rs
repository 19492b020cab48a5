//! `<transform>` operations as Mitsuba composes them: each new operation multiplies the
//! transform so far from the left, so operations apply to a point in the order written.

use glam::{DMat4, DVec3, DVec4};

/// A translation by `v`.
pub fn translate(v: [f64; 3]) -> DMat4 {
    DMat4::from_translation(DVec3::from(v))
}

/// A scale by `v` along the axes.
pub fn scale(v: [f64; 3]) -> DMat4 {
    DMat4::from_scale(DVec3::from(v))
}

/// A right-handed rotation by `degrees` about `axis`. Like Mitsuba, the axis is used as given
/// (Rodrigues' formula without normalizing it), so a non-unit axis also scales and shears.
pub fn rotate(axis: [f64; 3], degrees: f64) -> DMat4 {
    let (s, c) = degrees.to_radians().sin_cos();
    let [x, y, z] = axis;
    let k = 1.0 - c;
    rows([
        [x * x * k + c, x * y * k - z * s, x * z * k + y * s, 0.0],
        [x * y * k + z * s, y * y * k + c, y * z * k - x * s, 0.0],
        [x * z * k - y * s, y * z * k + x * s, z * z * k + c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// The camera-to-world transform of a camera at `origin` looking at `target`: its local +z is
/// the viewing direction, +y the up direction made orthogonal to it, and +x = y cross z (to the
/// left in the image). A zero `up` picks any orthogonal one, as Mitsuba does. None if the
/// directions are degenerate.
pub fn look_at(origin: [f64; 3], target: [f64; 3], up: [f64; 3]) -> Option<DMat4> {
    let (origin, target) = (DVec3::from(origin), DVec3::from(target));
    let dir = (target - origin).normalize();
    let mut up = DVec3::from(up);
    if up == DVec3::ZERO {
        up = coordinate_system(dir);
    }
    let left = up.cross(dir).normalize();
    let new_up = dir.cross(left);
    let m = DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        DVec4::new(origin.x, origin.y, origin.z, 1.0),
    );
    m.is_finite().then_some(m)
}

/// The first vector of the orthonormal basis Mitsuba's `coordinate_system` builds around the unit
/// vector `n` (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
fn coordinate_system(n: DVec3) -> DVec3 {
    let sign = 1.0f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x)
}

/// A matrix from its rows.
pub fn rows(r: [[f64; 4]; 4]) -> DMat4 {
    DMat4::from_cols_array_2d(&r).transpose()
}

/// A `<matrix>` of 16 values (4x4) or 9 (3x3, completed with the identity), row by row.
pub fn matrix(values: &[f64]) -> Option<DMat4> {
    match values.len() {
        16 => {
            let mut r = [[0.0; 4]; 4];
            for (i, v) in values.iter().enumerate() {
                r[i / 4][i % 4] = *v;
            }
            Some(rows(r))
        }
        9 => {
            let mut r = DMat4::IDENTITY.transpose().to_cols_array_2d();
            for (i, v) in values.iter().enumerate() {
                r[i / 3][i % 3] = *v;
            }
            Some(rows(r))
        }
        _ => None,
    }
}

/// The rows of a matrix.
pub fn to_rows(m: &DMat4) -> [[f64; 4]; 4] {
    m.transpose().to_cols_array_2d()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_rows(m: DMat4, expected: [[f64; 4]; 4], tol: f64) {
        let got = to_rows(&m);
        for (g, e) in got.iter().flatten().zip(expected.iter().flatten()) {
            assert!((g - e).abs() <= tol, "{got:?} != {expected:?}");
        }
    }

    // Expected values below: Mitsuba 3.9.1's `ScalarTransform4f` (Python, scalar_rgb).
    #[test]
    fn look_at_matches_mitsuba() {
        let m = look_at([0.0, -5.0, 1.0], [0.0, 0.0, 0.5], [0.0, 0.0, 1.0]).unwrap();
        assert_rows(
            m,
            [
                [-1.0, 0.0, 0.0, 0.0],
                [0.0, 0.0995037, 0.995037, -5.0],
                [0.0, 0.995037, -0.0995037, 1.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
            1e-6,
        );
        assert!(look_at([0.0; 3], [0.0; 3], [0.0, 0.0, 1.0]).is_none());
        assert!(look_at([0.0; 3], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]).is_none());
        // A zero up (or none) is chosen as Mitsuba does: its sensor's to_world for
        // `<lookat origin="1,2,3" target="1,2,5"/>`.
        assert_rows(
            look_at([1.0, 2.0, 3.0], [1.0, 2.0, 5.0], [0.0; 3]).unwrap(),
            [
                [0.0, 1.0, 0.0, 1.0],
                [-1.0, 0.0, 0.0, 2.0],
                [0.0, 0.0, 1.0, 3.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
            1e-12,
        );
    }

    #[test]
    fn rotate_uses_the_axis_as_given_like_mitsuba() {
        assert_rows(
            rotate([1.0, 1.0, 0.0], 30.0),
            [
                [1.0, 0.133975, 0.5, 0.0],
                [0.133975, 1.0, -0.5, 0.0],
                [-0.5, 0.5, 0.866025, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
            1e-6,
        );
        // Right-handed: +x turns towards +y about +z.
        let m = rotate([0.0, 0.0, 1.0], 90.0);
        assert!((m.transform_vector3(DVec3::X) - DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn matrices_are_row_major() {
        let v: Vec<f64> = (0..16).map(f64::from).collect();
        let m = matrix(&v).unwrap();
        assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(3.0, 7.0, 11.0));
        let m = matrix(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]).unwrap();
        assert_rows(
            m,
            [
                [1.0, 2.0, 3.0, 0.0],
                [4.0, 5.0, 6.0, 0.0],
                [7.0, 8.0, 9.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
            0.0,
        );
        assert!(matrix(&[1.0; 12]).is_none());
        assert_eq!(
            translate([1.0, 2.0, 3.0]).transform_point3(DVec3::ONE),
            DVec3::new(2.0, 3.0, 4.0)
        );
        assert_eq!(
            scale([1.0, 2.0, 3.0]).transform_point3(DVec3::ONE),
            DVec3::new(1.0, 2.0, 3.0)
        );
    }
}
