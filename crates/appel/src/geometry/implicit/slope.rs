//! Interval enclosures of a function along a ray together with its derivative along the ray: forward
//! automatic differentiation in interval arithmetic (Moore 1966; Mitchell 1990, section 4). Where the
//! derivative's enclosure excludes 0 the function is monotonic over the stretch, so it has at most
//! one root there, found from the signs at the two ends: root isolation can stop subdividing there.

use super::interval::Interval;
use super::num::Num;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slope {
    /// Enclosure of the value.
    pub v: Interval,
    /// Enclosure of the derivative with respect to the ray parameter.
    pub d: Interval,
}

impl Slope {
    fn point_sign(v: Interval) -> Interval {
        if v.lo > 0.0 {
            Interval::constant(1.0)
        } else if v.hi < 0.0 {
            Interval::constant(-1.0)
        } else {
            Interval::new(-1.0, 1.0)
        }
    }

    fn hull(a: Interval, b: Interval) -> Interval {
        if [a.lo, a.hi, b.lo, b.hi].iter().any(|x| x.is_nan()) {
            Interval::ENTIRE
        } else {
            Interval::new(a.lo.min(b.lo), a.hi.max(b.hi))
        }
    }
}

impl Num for Slope {
    fn constant(c: f64) -> Self {
        Self {
            v: Interval::constant(c),
            d: Interval::constant(0.0),
        }
    }
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v.add(o.v),
            d: self.d.add(o.d),
        }
    }
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v.sub(o.v),
            d: self.d.sub(o.d),
        }
    }
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v.mul(o.v),
            d: self.d.mul(o.v).add(o.d.mul(self.v)),
        }
    }
    fn div(self, o: Self) -> Self {
        let v = self.v.div(o.v);
        Self {
            v,
            d: self.d.sub(v.mul(o.d)).div(o.v),
        }
    }
    fn neg(self) -> Self {
        Self {
            v: self.v.neg(),
            d: self.d.neg(),
        }
    }
    fn powi(self, n: i32) -> Self {
        if n == 0 {
            return Self::constant(1.0);
        }
        Self {
            v: self.v.powi(n),
            d: Interval::constant(n as f64)
                .mul(self.v.powi(n - 1))
                .mul(self.d),
        }
    }
    fn sqrt(self) -> Self {
        let v = self.v.sqrt();
        // The slope 1 / (2 sqrt x) is unbounded as x reaches 0 (and 0 where clamped): no information.
        let d = if self.v.lo > 0.0 {
            self.d.div(Interval::constant(2.0).mul(v))
        } else {
            Interval::ENTIRE
        };
        Self { v, d }
    }
    fn abs(self) -> Self {
        Self {
            v: self.v.abs(),
            d: Self::point_sign(self.v).mul(self.d),
        }
    }
    fn sin(self) -> Self {
        Self {
            v: self.v.sin(),
            d: self.v.cos().mul(self.d),
        }
    }
    fn cos(self) -> Self {
        Self {
            v: self.v.cos(),
            d: self.v.sin().neg().mul(self.d),
        }
    }
    fn exp(self) -> Self {
        let v = self.v.exp();
        Self {
            v,
            d: v.mul(self.d),
        }
    }
    fn min(self, o: Self) -> Self {
        let d = if self.v.hi < o.v.lo {
            self.d
        } else if o.v.hi < self.v.lo {
            o.d
        } else {
            // Either branch may be taken, and at the switch the one-sided slopes are the branches'.
            Self::hull(self.d, o.d)
        };
        Self {
            v: self.v.min(o.v),
            d,
        }
    }
    fn max(self, o: Self) -> Self {
        let d = if self.v.lo > o.v.hi {
            self.d
        } else if o.v.lo > self.v.hi {
            o.d
        } else {
            Self::hull(self.d, o.d)
        };
        Self {
            v: self.v.max(o.v),
            d,
        }
    }
}
