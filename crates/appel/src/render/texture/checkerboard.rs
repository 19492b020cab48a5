//! Mitsuba's `checkerboard`: two colours alternating over unit-half squares of uv.

use super::transform_uv;
use glam::{Mat3, Vec2, Vec3};

#[derive(Clone, Debug, PartialEq)]
pub struct Checkerboard {
    pub color0: Vec3,
    pub color1: Vec3,
    /// 2D affine map applied to uv first.
    pub to_uv: Mat3,
}

impl Default for Checkerboard {
    /// Mitsuba's defaults: grey 0.4 and 0.2, identity map.
    fn default() -> Self {
        Self {
            color0: Vec3::splat(0.4),
            color1: Vec3::splat(0.2),
            to_uv: Mat3::IDENTITY,
        }
    }
}

impl Checkerboard {
    /// `color0` where the fractional parts of u and v are both above one half or both not (a
    /// fraction of exactly 0.5 counts as "not"), `color1` elsewhere.
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        let p = transform_uv(&self.to_uv, uv);
        let f = p - p.floor();
        if (f.x > 0.5) == (f.y > 0.5) {
            self.color0
        } else {
            self.color1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn squares_match_mitsuba() {
        let c = Checkerboard {
            color0: Vec3::X,
            color1: Vec3::Z,
            to_uv: Mat3::IDENTITY,
        };
        // What Mitsuba 3.9's `checkerboard` returned for these uvs (0 = color0, 1 = color1).
        let expect = [
            ((0.1, 0.1), 0),
            ((0.6, 0.1), 1),
            ((0.1, 0.6), 1),
            ((0.6, 0.6), 0),
            ((0.5, 0.5), 0),
            ((1.2, 0.3), 0),
            ((-0.2, 0.3), 1),
        ];
        for ((u, v), which) in expect {
            let want = if which == 0 { c.color0 } else { c.color1 };
            assert_eq!(c.eval(Vec2::new(u, v)), want, "uv ({u}, {v})");
        }
        // A scale of 2 in to_uv halves the squares.
        let scaled = Checkerboard {
            to_uv: Mat3::from_scale(Vec2::splat(2.0)),
            ..c.clone()
        };
        assert_eq!(scaled.eval(Vec2::new(0.3, 0.1)), c.color1);
    }
}
