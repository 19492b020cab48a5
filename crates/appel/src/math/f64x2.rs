//! Two f64 lanes: SSE2 on x86_64 (part of the base instruction set there), plain arrays elsewhere.
//! Each operation is the IEEE operation on each lane (no fused multiply-add), so a lane computes
//! bit for bit what scalar code with the same operations computes.

use std::ops::{Add, BitAnd, BitOr, Mul, Not, Sub};

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct F64x2(__m128d);

#[cfg(not(target_arch = "x86_64"))]
#[derive(Clone, Copy, Debug)]
pub struct F64x2([f64; 2]);

/// Per-lane comparison results (all bits set where true).
#[derive(Clone, Copy, Debug)]
pub struct Mask2(F64x2);

#[cfg(target_arch = "x86_64")]
impl F64x2 {
    #[inline(always)]
    pub fn new(v: [f64; 2]) -> Self {
        // SAFETY: SSE2 is part of x86_64.
        unsafe { Self(_mm_setr_pd(v[0], v[1])) }
    }
    #[inline(always)]
    pub fn splat(x: f64) -> Self {
        unsafe { Self(_mm_set1_pd(x)) }
    }
    #[inline(always)]
    pub fn lt(self, o: Self) -> Mask2 {
        unsafe { Mask2(Self(_mm_cmplt_pd(self.0, o.0))) }
    }
    #[inline(always)]
    pub fn gt(self, o: Self) -> Mask2 {
        unsafe { Mask2(Self(_mm_cmpgt_pd(self.0, o.0))) }
    }
    #[inline(always)]
    pub fn ge(self, o: Self) -> Mask2 {
        unsafe { Mask2(Self(_mm_cmpge_pd(self.0, o.0))) }
    }
}

#[cfg(target_arch = "x86_64")]
impl Mask2 {
    /// Bit `k` set where lane `k` is true.
    #[inline(always)]
    pub fn bits(self) -> u32 {
        unsafe { _mm_movemask_pd(self.0 .0) as u32 }
    }
}

#[cfg(target_arch = "x86_64")]
impl Not for Mask2 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        // All bits set is a NaN, so the constant comes from the integer side.
        unsafe {
            let ones = _mm_castsi128_pd(_mm_set1_epi32(-1));
            Self(F64x2(_mm_xor_pd(self.0 .0, ones)))
        }
    }
}

#[cfg(target_arch = "x86_64")]
macro_rules! binary {
    ($trait:ident, $f:ident, $intrinsic:ident) => {
        impl $trait for F64x2 {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                // SAFETY: SSE2 is part of x86_64.
                unsafe { Self($intrinsic(self.0, o.0)) }
            }
        }
    };
}

#[cfg(target_arch = "x86_64")]
binary!(Add, add, _mm_add_pd);
#[cfg(target_arch = "x86_64")]
binary!(Sub, sub, _mm_sub_pd);
#[cfg(target_arch = "x86_64")]
binary!(Mul, mul, _mm_mul_pd);

#[cfg(target_arch = "x86_64")]
impl BitAnd for Mask2 {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        unsafe { Self(F64x2(_mm_and_pd(self.0 .0, o.0 .0))) }
    }
}

#[cfg(target_arch = "x86_64")]
impl BitOr for Mask2 {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        unsafe { Self(F64x2(_mm_or_pd(self.0 .0, o.0 .0))) }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod portable {
    use super::*;

    fn lanes(f: impl Fn(usize) -> f64) -> F64x2 {
        F64x2([f(0), f(1)])
    }

    fn mask(f: impl Fn(usize) -> bool) -> Mask2 {
        Mask2(lanes(|k| f64::from_bits(if f(k) { u64::MAX } else { 0 })))
    }

    impl F64x2 {
        pub fn new(v: [f64; 2]) -> Self {
            Self(v)
        }
        pub fn splat(x: f64) -> Self {
            Self([x, x])
        }
        pub fn lt(self, o: Self) -> Mask2 {
            mask(|k| self.0[k] < o.0[k])
        }
        pub fn gt(self, o: Self) -> Mask2 {
            mask(|k| self.0[k] > o.0[k])
        }
        pub fn ge(self, o: Self) -> Mask2 {
            mask(|k| self.0[k] >= o.0[k])
        }
    }

    impl Mask2 {
        fn lane(self, k: usize) -> bool {
            self.0 .0[k].to_bits() != 0
        }
        pub fn bits(self) -> u32 {
            self.lane(0) as u32 | (self.lane(1) as u32) << 1
        }
    }

    impl Not for Mask2 {
        type Output = Self;
        fn not(self) -> Self {
            mask(|k| !self.lane(k))
        }
    }

    impl Add for F64x2 {
        type Output = Self;
        fn add(self, o: Self) -> Self {
            lanes(|k| self.0[k] + o.0[k])
        }
    }
    impl Sub for F64x2 {
        type Output = Self;
        fn sub(self, o: Self) -> Self {
            lanes(|k| self.0[k] - o.0[k])
        }
    }
    impl Mul for F64x2 {
        type Output = Self;
        fn mul(self, o: Self) -> Self {
            lanes(|k| self.0[k] * o.0[k])
        }
    }
    impl BitAnd for Mask2 {
        type Output = Self;
        fn bitand(self, o: Self) -> Self {
            mask(|k| self.lane(k) & o.lane(k))
        }
    }
    impl BitOr for Mask2 {
        type Output = Self;
        fn bitor(self, o: Self) -> Self {
            mask(|k| self.lane(k) | o.lane(k))
        }
    }
}

/// What code written once for a scalar `f64` and for [`F64x2`] needs: arithmetic, splats and
/// comparisons into a mask (`bool` for the scalar).
pub trait Lanes: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> {
    type Mask: Copy + BitAnd<Output = Self::Mask> + BitOr<Output = Self::Mask>;
    fn splat(x: f64) -> Self;
    fn lt(self, o: Self) -> Self::Mask;
    fn gt(self, o: Self) -> Self::Mask;
    fn ge(self, o: Self) -> Self::Mask;
}

impl Lanes for f64 {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self < o
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self > o
    }
    #[inline(always)]
    fn ge(self, o: Self) -> bool {
        self >= o
    }
}

impl Lanes for F64x2 {
    type Mask = Mask2;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        F64x2::splat(x)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Mask2 {
        F64x2::lt(self, o)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Mask2 {
        F64x2::gt(self, o)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> Mask2 {
        F64x2::ge(self, o)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_compute_what_scalars_do() {
        let (a, b) = ([1.5, -0.0], [0.1, f64::NAN]);
        let (x, y) = (F64x2::new(a), F64x2::new(b));
        let lanes = |v: F64x2| -> [f64; 2] { unsafe { std::mem::transmute(v) } };
        for k in 0..2 {
            assert_eq!(lanes(x + y)[k].to_bits(), (a[k] + b[k]).to_bits());
            assert_eq!(lanes(x - y)[k].to_bits(), (a[k] - b[k]).to_bits());
            assert_eq!(lanes(x * y)[k].to_bits(), (a[k] * b[k]).to_bits());
        }
        // NaN compares false, as in scalar code; `not` turns it true.
        assert_eq!(x.lt(y).bits(), 0b00);
        assert_eq!(x.gt(y).bits(), 0b01);
        assert_eq!(x.ge(F64x2::splat(-0.0)).bits(), 0b11);
        assert_eq!((!x.gt(y)).bits(), 0b10);
        assert_eq!((x.gt(y) | x.lt(y)).bits(), 0b01);
        assert_eq!((x.gt(y) & x.lt(y)).bits(), 0b00);
    }
}
