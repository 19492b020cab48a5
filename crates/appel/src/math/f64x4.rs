//! Four f64 lanes in one AVX register, for testing four rays at once against the f64 solves of
//! spheres and rectangles. Each operation is the IEEE operation on each lane (no fused
//! multiply-add), so a lane computes bit for bit what scalar code with the same operations does.
//!
//! A value can only be made with an [`Avx2`] token, which exists only on a CPU with AVX2: holding
//! an `F64x4` proves the instructions are there. The operations are `#[inline(always)]` and are
//! compiled into AVX code only inside functions built with `#[target_feature(enable = "avx2")]`
//! (callers enter such a function once per packet, see [`Avx2::detect`]); elsewhere each would be
//! a call.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use super::Ray;

/// Proof that the CPU has AVX2 (and so AVX): made only by [`Avx2::detect`].
#[derive(Clone, Copy, Debug)]
pub struct Avx2(());

impl Avx2 {
    /// The token, where the CPU has AVX2 (detected once).
    #[inline]
    pub fn detect() -> Option<Self> {
        #[cfg(target_arch = "x86_64")]
        {
            use std::sync::OnceLock;
            static AVX2: OnceLock<bool> = OnceLock::new();
            if *AVX2.get_or_init(|| std::is_x86_feature_detected!("avx2")) {
                return Some(Self(()));
            }
        }
        None
    }
}

#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct F64x4(__m256d);

/// Per-lane comparison results (all bits set where true).
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct Mask4(__m256d);

// SAFETY (every `unsafe` block below): an `F64x4` or `Mask4` exists only where an `Avx2` token
// was made, so the CPU runs the AVX instructions these intrinsics are.
#[cfg(target_arch = "x86_64")]
impl F64x4 {
    #[inline(always)]
    pub fn new(_: Avx2, v: [f64; 4]) -> Self {
        unsafe { Self(_mm256_loadu_pd(v.as_ptr())) }
    }
    #[inline(always)]
    pub fn splat(_: Avx2, x: f64) -> Self {
        unsafe { Self(_mm256_set1_pd(x)) }
    }
    /// `x` in every lane, with the token of `self` (a value already made).
    #[inline(always)]
    pub fn splat_as(self, x: f64) -> Self {
        unsafe { Self(_mm256_set1_pd(x)) }
    }
    #[inline(always)]
    pub fn to_array(self) -> [f64; 4] {
        let mut out = [0.0; 4];
        unsafe { _mm256_storeu_pd(out.as_mut_ptr(), self.0) };
        out
    }
    /// Each lane rounded to f32 (to nearest, as `as f32` does).
    #[inline(always)]
    pub fn to_f32(self) -> [f32; 4] {
        let mut out = [0.0; 4];
        unsafe { _mm_storeu_ps(out.as_mut_ptr(), _mm256_cvtpd_ps(self.0)) };
        out
    }
    /// Bit `k` set where lane `k`, rounded to f32, lies in `(0, t_max[k])`: the test callers make in
    /// f32, the precision they compare hits in.
    #[inline(always)]
    pub fn f32_inside(self, t_max: &[f32; 4]) -> u32 {
        unsafe {
            let t = _mm256_cvtpd_ps(self.0);
            let ok = _mm_and_ps(
                _mm_cmpgt_ps(t, _mm_setzero_ps()),
                _mm_cmplt_ps(t, _mm_loadu_ps(t_max.as_ptr())),
            );
            _mm_movemask_ps(ok) as u32
        }
    }
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        unsafe { Self(_mm256_sqrt_pd(self.0)) }
    }
    /// `|x|`: the sign bit cleared, as `f64::abs`.
    #[inline(always)]
    pub fn abs(self) -> Self {
        unsafe { Self(_mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0)) }
    }
    #[inline(always)]
    pub fn lt(self, o: Self) -> Mask4 {
        unsafe { Mask4(_mm256_cmp_pd::<_CMP_LT_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn gt(self, o: Self) -> Mask4 {
        unsafe { Mask4(_mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn ge(self, o: Self) -> Mask4 {
        unsafe { Mask4(_mm256_cmp_pd::<_CMP_GE_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn eq(self, o: Self) -> Mask4 {
        unsafe { Mask4(_mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, o.0)) }
    }
    /// `a` where `mask`, else `b`.
    #[inline(always)]
    pub fn select(mask: Mask4, a: Self, b: Self) -> Self {
        unsafe { Self(_mm256_blendv_pd(b.0, a.0, mask.0)) }
    }
}

#[cfg(target_arch = "x86_64")]
impl Mask4 {
    /// Bit `k` set where lane `k` is true.
    #[inline(always)]
    pub fn bits(self) -> u32 {
        unsafe { _mm256_movemask_pd(self.0) as u32 }
    }
    /// Where exactly one of the two is true.
    #[inline(always)]
    pub fn xor(self, o: Self) -> Self {
        unsafe { Self(_mm256_xor_pd(self.0, o.0)) }
    }
}

#[cfg(target_arch = "x86_64")]
impl Not for Mask4 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        unsafe {
            Self(_mm256_xor_pd(
                self.0,
                _mm256_castsi256_pd(_mm256_set1_epi64x(-1)),
            ))
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl BitAnd for Mask4 {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        unsafe { Self(_mm256_and_pd(self.0, o.0)) }
    }
}

#[cfg(target_arch = "x86_64")]
impl BitOr for Mask4 {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        unsafe { Self(_mm256_or_pd(self.0, o.0)) }
    }
}

#[cfg(target_arch = "x86_64")]
macro_rules! lanewise {
    ($trait:ident, $f:ident, $intrinsic:ident) => {
        impl $trait for F64x4 {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                unsafe { Self($intrinsic(self.0, o.0)) }
            }
        }
    };
}

#[cfg(target_arch = "x86_64")]
lanewise!(Add, add, _mm256_add_pd);
#[cfg(target_arch = "x86_64")]
lanewise!(Sub, sub, _mm256_sub_pd);
#[cfg(target_arch = "x86_64")]
lanewise!(Mul, mul, _mm256_mul_pd);
#[cfg(target_arch = "x86_64")]
lanewise!(Div, div, _mm256_div_pd);

#[cfg(target_arch = "x86_64")]
impl Neg for F64x4 {
    type Output = Self;
    /// The sign bit flipped, as scalar negation.
    #[inline(always)]
    fn neg(self) -> Self {
        unsafe { Self(_mm256_xor_pd(self.0, _mm256_set1_pd(-0.0))) }
    }
}

/// Four rays in f64, structure of arrays, with `|dir|^2`: [`super::RayF64`] of each lane (the
/// conversions are exact and `a` is summed in `DVec3::length_squared`'s order).
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct RayF64x4 {
    pub origin: [F64x4; 3],
    pub dir: [F64x4; 3],
    pub dir_length_squared: F64x4,
}

#[cfg(target_arch = "x86_64")]
impl RayF64x4 {
    #[inline(always)]
    pub fn new(avx: Avx2, rays: &[Ray; 4]) -> Self {
        let [a, b, c, d] = rays;
        let lanes = |x: [f32; 4]| F64x4::new(avx, x.map(|x| x as f64));
        let origin = [
            lanes([a.origin.x, b.origin.x, c.origin.x, d.origin.x]),
            lanes([a.origin.y, b.origin.y, c.origin.y, d.origin.y]),
            lanes([a.origin.z, b.origin.z, c.origin.z, d.origin.z]),
        ];
        let dir = [
            lanes([a.dir.x, b.dir.x, c.dir.x, d.dir.x]),
            lanes([a.dir.y, b.dir.y, c.dir.y, d.dir.y]),
            lanes([a.dir.z, b.dir.z, c.dir.z, d.dir.z]),
        ];
        let [x, y, z] = dir;
        Self {
            origin,
            dir,
            dir_length_squared: x * x + y * y + z * z,
        }
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::math::RayF64;
    use glam::Vec3;

    /// Every operation is the scalar one on each lane, bit for bit, NaN and infinities included.
    #[test]
    fn lanes_compute_what_scalars_compute() {
        let Some(avx) = Avx2::detect() else {
            return;
        };
        let xs = [
            1.5,
            -0.0,
            f64::INFINITY,
            f64::NAN,
            3e-310,
            -7.25,
            1e300,
            0.1,
        ];
        for i in 0..xs.len() {
            let a = [xs[i], xs[(i + 1) % 8], xs[(i + 2) % 8], xs[(i + 5) % 8]];
            let b = [xs[(i + 3) % 8], xs[(i + 4) % 8], xs[i], xs[(i + 7) % 8]];
            let (va, vb) = (F64x4::new(avx, a), F64x4::new(avx, b));
            let bits = |v: [f64; 4]| v.map(f64::to_bits);
            let each = |f: &dyn Fn(f64, f64) -> f64| bits([0, 1, 2, 3].map(|k| f(a[k], b[k])));
            assert_eq!(bits((va + vb).to_array()), each(&|x, y| x + y));
            assert_eq!(bits((va - vb).to_array()), each(&|x, y| x - y));
            assert_eq!(bits((va * vb).to_array()), each(&|x, y| x * y));
            assert_eq!(bits((va / vb).to_array()), each(&|x, y| x / y));
            assert_eq!(bits(va.sqrt().to_array()), each(&|x, _| x.sqrt()));
            assert_eq!(bits(va.abs().to_array()), each(&|x, _| x.abs()));
            assert_eq!(bits((-va).to_array()), each(&|x, _| -x));
            let mask = |f: &dyn Fn(f64, f64) -> bool| {
                (0..4).fold(0, |m, k| m | ((f(a[k], b[k]) as u32) << k))
            };
            assert_eq!(va.lt(vb).bits(), mask(&|x, y| x < y));
            assert_eq!(va.gt(vb).bits(), mask(&|x, y| x > y));
            assert_eq!(va.ge(vb).bits(), mask(&|x, y| x >= y));
            assert_eq!(va.eq(vb).bits(), mask(&|x, y| x == y));
            assert_eq!(
                (!va.lt(vb)).bits(),
                mask(&|x, y| x >= y || x.is_nan() || y.is_nan())
            );
            let sel = F64x4::select(va.lt(vb), va, vb).to_array();
            assert_eq!(bits(sel), each(&|x, y| if x < y { x } else { y }));
            assert_eq!(
                va.to_f32().map(f32::to_bits),
                a.map(|x| (x as f32).to_bits())
            );
            let t_max = [2.0, f32::INFINITY, 0.5, 1e30];
            let inside = (0..4).fold(0, |m, k| {
                let t = a[k] as f32;
                m | (((t > 0.0 && t < t_max[k]) as u32) << k)
            });
            assert_eq!(va.f32_inside(&t_max), inside);
        }
        let rays = [0.3f32, -2.0, 1e-20, 5.5]
            .map(|s| Ray::new(Vec3::new(s, 1.0 - s, 0.25 * s), Vec3::new(-s, 0.7, s * s)));
        let packet = RayF64x4::new(avx, &rays);
        for (k, ray) in rays.iter().enumerate() {
            let r = RayF64::new(ray);
            let lane = |v: F64x4| v.to_array()[k].to_bits();
            assert_eq!(
                lane(packet.dir_length_squared),
                r.dir_length_squared.to_bits()
            );
            assert_eq!(lane(packet.origin[1]), r.origin.y.to_bits());
            assert_eq!(lane(packet.dir[2]), r.dir.z.to_bits());
        }
    }
}
