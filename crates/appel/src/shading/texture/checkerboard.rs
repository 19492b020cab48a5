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

    /// The float query (a roughness, a weight): Mitsuba 3's `eval_1` picks the squares the other
    /// way round from its `eval` (`color0` where exactly one fraction is above one half;
    /// measured in Mitsuba 3.9.1 and in its `checkerboard.cpp`). Its reference images are
    /// rendered so, and so is this.
    pub fn eval_1(&self, uv: Vec2) -> f32 {
        let p = transform_uv(&self.to_uv, uv);
        let f = p - p.floor();
        let c = if (f.x > 0.5) != (f.y > 0.5) {
            self.color0
        } else {
            self.color1
        };
        (c.x + c.y + c.z) / 3.0
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
            // eval_1 takes the other colour (Mitsuba 3.9.1's eval_1 for color0 = 0, color1 = 1:
            // 1 at (0.01, 0.01) x 25, 0 at (0.03, 0.01) x 25).
            let one = Checkerboard {
                color0: Vec3::ZERO,
                color1: Vec3::ONE,
                to_uv: Mat3::IDENTITY,
            };
            assert_eq!(one.eval_1(Vec2::new(u, v)), (1 - which) as f32, "{u} {v}");
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
