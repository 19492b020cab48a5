//! Forward-mode automatic differentiation: a value and its gradient in (x, y, z), carried through
//! every operation by the chain rule (Griewank & Walther 2008, ch. 3). Exact up to rounding, unlike
//! finite differences, which is what normals and Newton steps need.

use super::num::Num;
use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual {
    pub v: f64,
    pub g: DVec3,
}

impl Dual {
    pub fn var(v: f64, axis: usize) -> Self {
        let mut g = DVec3::ZERO;
        g[axis] = 1.0;
        Self { v, g }
    }

    fn chain(self, v: f64, dv: f64) -> Self {
        Self { v, g: self.g * dv }
    }
}

impl Num for Dual {
    fn constant(c: f64) -> Self {
        Self {
            v: c,
            g: DVec3::ZERO,
        }
    }
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            g: self.g + o.g,
        }
    }
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            g: self.g - o.g,
        }
    }
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v * o.v,
            g: self.g * o.v + o.g * self.v,
        }
    }
    fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        Self {
            v,
            g: (self.g - o.g * v) / o.v,
        }
    }
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            g: -self.g,
        }
    }
    fn powi(self, n: i32) -> Self {
        if n == 0 {
            return Self::constant(1.0);
        }
        self.chain(self.v.powi(n), n as f64 * self.v.powi(n - 1))
    }
    fn sqrt(self) -> Self {
        let v = Num::sqrt(self.v);
        // Where the argument is clamped (or at 0, where the slope is infinite) the gradient is set to 0
        // rather than inf/NaN; the surface code falls back to a defined normal there.
        let dv = if v > 0.0 { 0.5 / v } else { 0.0 };
        self.chain(v, dv)
    }
    fn abs(self) -> Self {
        let s = if self.v > 0.0 {
            1.0
        } else if self.v < 0.0 {
            -1.0
        } else {
            0.0
        };
        self.chain(self.v.abs(), s)
    }
    fn sin(self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }
    fn cos(self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }
    fn exp(self) -> Self {
        let v = self.v.exp();
        self.chain(v, v)
    }
    fn min(self, o: Self) -> Self {
        if self.v.is_nan() || o.v.is_nan() {
            Self::constant(f64::NAN)
        } else if self.v <= o.v {
            self
        } else {
            o
        }
    }
    fn max(self, o: Self) -> Self {
        if self.v.is_nan() || o.v.is_nan() {
            Self::constant(f64::NAN)
        } else if self.v >= o.v {
            self
        } else {
            o
        }
    }
}
