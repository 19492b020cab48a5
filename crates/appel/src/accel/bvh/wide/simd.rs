//! The few vector operations the wide BVH needs, in SSE (4 lanes, part of every x86_64) and AVX2
//! (8 lanes; every function is compiled for AVX2, so callers must have checked for it), under the
//! same names, so that one body (a macro) serves both widths. Comparisons are the ordered ones (false
//! when either operand is NaN), like Rust's scalar comparisons.
pub mod sse {
    use std::arch::x86_64::*;
    type V = __m128;
    #[inline(always)]
    pub unsafe fn load(p: *const f32) -> V {
        _mm_load_ps(p)
    }
    #[inline(always)]
    pub unsafe fn store(p: *mut f32, v: V) {
        _mm_storeu_ps(p, v)
    }
    #[inline(always)]
    pub unsafe fn loadu(p: *const f32) -> V {
        _mm_loadu_ps(p)
    }
    #[inline(always)]
    pub unsafe fn splat(x: f32) -> V {
        _mm_set1_ps(x)
    }
    /// `b` when either operand is NaN.
    #[inline(always)]
    pub unsafe fn max(a: V, b: V) -> V {
        _mm_max_ps(a, b)
    }
    /// `b` when either operand is NaN.
    #[inline(always)]
    pub unsafe fn min(a: V, b: V) -> V {
        _mm_min_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn add(a: V, b: V) -> V {
        _mm_add_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn sub(a: V, b: V) -> V {
        _mm_sub_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn mul(a: V, b: V) -> V {
        _mm_mul_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn eq(a: V, b: V) -> V {
        _mm_cmpeq_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn lt(a: V, b: V) -> V {
        _mm_cmplt_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn le(a: V, b: V) -> V {
        _mm_cmple_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn gt(a: V, b: V) -> V {
        _mm_cmpgt_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn ge(a: V, b: V) -> V {
        _mm_cmpge_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn or(a: V, b: V) -> V {
        _mm_or_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn and(a: V, b: V) -> V {
        _mm_and_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn xor(a: V, b: V) -> V {
        _mm_xor_ps(a, b)
    }
    #[inline(always)]
    pub unsafe fn not(a: V) -> V {
        _mm_xor_ps(a, _mm_castsi128_ps(_mm_set1_epi32(-1)))
    }
    #[inline(always)]
    pub unsafe fn mask(a: V) -> u32 {
        _mm_movemask_ps(a) as u32
    }
}

/// Callers must have AVX2 (every function here is compiled for it).
pub mod avx {
    use std::arch::x86_64::*;
    type V = __m256;
    /// Lanes 0-3 from `lo`, 4-7 from `hi`.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn load2(hi: *const f32, lo: *const f32) -> V {
        _mm256_loadu2_m128(hi, lo)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn store(p: *mut f32, v: V) {
        _mm256_storeu_ps(p, v)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn loadu(p: *const f32) -> V {
        _mm256_loadu_ps(p)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn splat(x: f32) -> V {
        _mm256_set1_ps(x)
    }
    /// `b` when either operand is NaN.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn max(a: V, b: V) -> V {
        _mm256_max_ps(a, b)
    }
    /// `b` when either operand is NaN.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn min(a: V, b: V) -> V {
        _mm256_min_ps(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn add(a: V, b: V) -> V {
        _mm256_add_ps(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn sub(a: V, b: V) -> V {
        _mm256_sub_ps(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn mul(a: V, b: V) -> V {
        _mm256_mul_ps(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn eq(a: V, b: V) -> V {
        _mm256_cmp_ps::<_CMP_EQ_OQ>(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn lt(a: V, b: V) -> V {
        _mm256_cmp_ps::<_CMP_LT_OQ>(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn le(a: V, b: V) -> V {
        _mm256_cmp_ps::<_CMP_LE_OQ>(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn gt(a: V, b: V) -> V {
        _mm256_cmp_ps::<_CMP_GT_OQ>(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn ge(a: V, b: V) -> V {
        _mm256_cmp_ps::<_CMP_GE_OQ>(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn or(a: V, b: V) -> V {
        _mm256_or_ps(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn and(a: V, b: V) -> V {
        _mm256_and_ps(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn xor(a: V, b: V) -> V {
        _mm256_xor_ps(a, b)
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn not(a: V) -> V {
        _mm256_xor_ps(a, _mm256_castsi256_ps(_mm256_set1_epi32(-1)))
    }
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn mask(a: V) -> u32 {
        _mm256_movemask_ps(a) as u32
    }
}
