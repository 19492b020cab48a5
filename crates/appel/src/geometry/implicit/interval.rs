//! Interval arithmetic over f64 (Moore 1966) with outward rounding: every result encloses the exact
//! image of its arguments, so `0 not in F([t0, t1])` proves the surface does not cross that stretch
//! of the ray (Mitchell 1990).
//!
//! The basic operations are correctly rounded in IEEE 754, so moving each computed bound one ulp
//! outwards (`next_down`/`next_up`) makes them enclosing. `exp`, `sin` and `cos` come from the
//! platform's libm, which is accurate to about 1 ulp but not guaranteed correctly rounded, so their
//! bounds move out by two ulps. Anything undefined (NaN, `inf - inf`, division by an interval that
//! contains 0) gives the whole line, which is always a correct enclosure.

use super::num::Num;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    pub lo: f64,
    pub hi: f64,
}

impl Interval {
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    pub fn new(lo: f64, hi: f64) -> Self {
        Self { lo, hi }
    }

    /// `[lo, hi]` computed with rounding to nearest, widened by one ulp each way.
    fn out(lo: f64, hi: f64) -> Self {
        if lo.is_nan() || hi.is_nan() {
            Self::ENTIRE
        } else {
            Self {
                lo: lo.next_down(),
                hi: hi.next_up(),
            }
        }
    }

    /// Like [`Interval::out`] for results of libm functions: two ulps.
    fn out2(lo: f64, hi: f64) -> Self {
        let i = Self::out(lo, hi);
        Self::out(i.lo, i.hi)
    }

    /// `self`, or the whole line if either product it was made of is NaN (f64::min/max drop NaN).
    fn nan_to_entire(self, a: f64, b: f64) -> Self {
        if a.is_nan() || b.is_nan() {
            Self::ENTIRE
        } else {
            self
        }
    }

    /// Whether 0 may be a value of the function over the box (NaN bounds count as yes).
    pub fn contains_zero(&self) -> bool {
        !(self.lo > 0.0 || self.hi < 0.0)
    }

    pub fn contains(&self, v: f64) -> bool {
        self.lo <= v && v <= self.hi
    }

    /// Bounds of `a^n` for `a >= 0`, `n >= 1`: binary powering with each product rounded
    /// down (or up).
    fn pow_bound(a: f64, n: i32, up: bool) -> f64 {
        let mut result = 1.0f64;
        let mut base = a;
        let mut n = n as u32;
        let step = |x: f64| {
            if up {
                x.next_up()
            } else {
                x.next_down().max(0.0)
            }
        };
        while n > 0 {
            if n & 1 == 1 {
                result = step(result * base);
            }
            n >>= 1;
            if n > 0 {
                base = step(base * base);
            }
        }
        result
    }
}

impl Num for Interval {
    fn constant(c: f64) -> Self {
        Self { lo: c, hi: c }
    }
    fn add(self, o: Self) -> Self {
        Self::out(self.lo + o.lo, self.hi + o.hi)
    }
    fn sub(self, o: Self) -> Self {
        Self::out(self.lo - o.hi, self.hi - o.lo)
    }
    fn mul(self, o: Self) -> Self {
        // Scaling by a point (constants, ray directions) needs two products, not four.
        if o.lo == o.hi {
            let (a, b) = (self.lo * o.lo, self.hi * o.lo);
            return Self::out(a.min(b), a.max(b)).nan_to_entire(a, b);
        }
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        if p.iter().any(|v| v.is_nan()) {
            // 0 * inf: no information kept.
            return Self::ENTIRE;
        }
        Self::out(
            p[0].min(p[1]).min(p[2].min(p[3])),
            p[0].max(p[1]).max(p[2].max(p[3])),
        )
    }
    fn div(self, o: Self) -> Self {
        if o.contains_zero() {
            return Self::ENTIRE;
        }
        let r = Self::out(1.0 / o.hi, 1.0 / o.lo);
        self.mul(r)
    }
    fn neg(self) -> Self {
        Self {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
    fn powi(self, n: i32) -> Self {
        if self.lo.is_nan() || self.hi.is_nan() {
            return Self::ENTIRE;
        }
        if n == 0 {
            return Self::constant(1.0);
        }
        if n < 0 {
            return Self::constant(1.0).div(self.powi(-n));
        }
        let (lo, hi) = (self.lo, self.hi);
        let down = |a: f64| Self::pow_bound(a, n, false);
        let up = |a: f64| Self::pow_bound(a, n, true);
        if n % 2 == 0 {
            // Even powers: decreasing on the negative half, increasing on the positive one, minimum 0.
            if lo >= 0.0 {
                Self::new(down(lo), up(hi))
            } else if hi <= 0.0 {
                Self::new(down(-hi), up(-lo))
            } else {
                Self::new(0.0, up((-lo).max(hi)))
            }
        } else {
            // Odd powers are increasing everywhere.
            let l = if lo >= 0.0 { down(lo) } else { -up(-lo) };
            let h = if hi >= 0.0 { up(hi) } else { -down(-hi) };
            Self::new(l, h)
        }
    }
    fn sqrt(self) -> Self {
        if self.lo.is_nan() || self.hi.is_nan() {
            return Self::ENTIRE;
        }
        // sqrt(max(x, 0)), matching the point evaluation; sqrt is correctly rounded.
        let lo = if self.lo <= 0.0 {
            0.0
        } else {
            self.lo.sqrt().next_down().max(0.0)
        };
        let hi = if self.hi <= 0.0 {
            0.0
        } else {
            self.hi.sqrt().next_up()
        };
        Self::new(lo, hi)
    }
    fn abs(self) -> Self {
        if self.lo >= 0.0 {
            self
        } else if self.hi <= 0.0 {
            self.neg()
        } else {
            Self::new(0.0, (-self.lo).max(self.hi))
        }
    }
    fn sin(self) -> Self {
        periodic(self, 0.0)
    }
    fn cos(self) -> Self {
        // cos(x) = sin(x + pi/2): same extremum test with the peaks shifted by -pi/2.
        periodic(self, -FRAC_PI_2)
    }
    fn exp(self) -> Self {
        let i = Self::out2(self.lo.exp(), self.hi.exp());
        Self::new(i.lo.max(0.0), i.hi)
    }
    fn min(self, o: Self) -> Self {
        if [self.lo, self.hi, o.lo, o.hi].iter().any(|v| v.is_nan()) {
            return Self::ENTIRE;
        }
        Self::new(self.lo.min(o.lo), self.hi.min(o.hi))
    }
    fn max(self, o: Self) -> Self {
        if [self.lo, self.hi, o.lo, o.hi].iter().any(|v| v.is_nan()) {
            return Self::ENTIRE;
        }
        Self::new(self.lo.max(o.lo), self.hi.max(o.hi))
    }
}

/// Enclosure of `sin(x)` (`shift = 0`) or `cos(x)` (`shift = -pi/2`, the maxima of cos sit at
/// `pi/2 + shift + 2k pi`). The range is `[-1, 1]` if the interval spans a period or is too far from
/// 0 for the range reduction below to be trusted; otherwise the end values, widened to +-1 where a
/// maximum or minimum lies inside. The test for an extremum inside is widened by a relative margin,
/// so rounding can only make it say "inside" too often, which costs tightness, never correctness.
fn periodic(x: Interval, shift: f64) -> Interval {
    const FULL: Interval = Interval { lo: -1.0, hi: 1.0 };
    if !(x.lo.is_finite() && x.hi.is_finite())
        || x.hi - x.lo >= TAU
        || x.lo.abs().max(x.hi.abs()) > 1e9
    {
        return FULL;
    }
    let f = |v: f64| if shift == 0.0 { v.sin() } else { v.cos() };
    let (a, b) = (f(x.lo), f(x.hi));
    let mut r = Interval::out2(a.min(b), a.max(b));
    let margin = 1e-12 * (1.0 + x.lo.abs().max(x.hi.abs()));
    // Is there an integer k with lo <= c + 2k pi <= hi?
    let has = |c: f64| {
        let k = ((x.lo - margin - c) / TAU).ceil();
        c + k * TAU <= x.hi + margin
    };
    if has(FRAC_PI_2 + shift) {
        r.hi = 1.0;
    }
    if has(FRAC_PI_2 + PI + shift) {
        r.lo = -1.0;
    }
    Interval::new(r.lo.max(-1.0), r.hi.min(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn even_and_odd_powers() {
        let i = Interval::new(-2.0, 1.0);
        let sq = i.powi(2);
        assert_eq!(sq.lo, 0.0);
        assert!(sq.contains(4.0) && sq.hi < 4.0 + 1e-12);
        let cube = i.powi(3);
        assert!(cube.contains(-8.0) && cube.contains(1.0) && cube.lo > -8.0 - 1e-12);
        let inv = Interval::new(2.0, 4.0).powi(-1);
        assert!(inv.contains(0.25) && inv.contains(0.5) && inv.hi < 0.5 + 1e-12);
        assert_eq!(i.powi(-2), Interval::ENTIRE);
    }

    #[test]
    fn division_by_an_interval_containing_zero_is_the_whole_line() {
        let r = Interval::new(1.0, 2.0).div(Interval::new(-1.0, 1.0));
        assert_eq!(r, Interval::ENTIRE);
    }

    #[test]
    fn sin_and_cos_find_interior_extrema() {
        let s = Interval::new(1.0, 2.0).sin();
        assert_eq!(s.hi, 1.0);
        assert!(s.lo <= 1.0f64.sin() && s.lo > 0.8);
        let c = Interval::new(3.0, 3.5).cos();
        assert_eq!(c.lo, -1.0);
        let c = Interval::new(0.1, 0.2).cos();
        assert!(c.contains(0.1f64.cos()) && c.contains(0.2f64.cos()) && c.hi < 1.0);
    }

    #[test]
    fn sqrt_clamps_negative_parts() {
        assert_eq!(Interval::new(-4.0, -1.0).sqrt(), Interval::new(0.0, 0.0));
        let s = Interval::new(-1.0, 4.0).sqrt();
        assert_eq!(s.lo, 0.0);
        assert!(s.contains(2.0));
    }
}
