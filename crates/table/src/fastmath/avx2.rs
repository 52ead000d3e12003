//! [`exp4`] four lanes at a time with AVX2: the operations of the scalar
//! [`exp`](super::exp) in the same order (separate multiplies and adds, IEEE lane by
//! lane), so every lane has the bits of the scalar result; the special values are
//! selected at the end instead of branched to.

use super::{INV_FACTORIAL, LN2_HI, LN2_LO, ROUND};
use std::arch::x86_64::*;

#[inline(always)]
unsafe fn splat(x: f64) -> __m256d {
    unsafe { _mm256_set1_pd(x) }
}

#[inline(always)]
unsafe fn add(a: __m256d, b: __m256d) -> __m256d {
    unsafe { _mm256_add_pd(a, b) }
}

#[inline(always)]
unsafe fn mul(a: __m256d, b: __m256d) -> __m256d {
    unsafe { _mm256_mul_pd(a, b) }
}

/// `a + t·c` with c a constant.
#[inline(always)]
unsafe fn ma(a: f64, t: __m256d, c: f64) -> __m256d {
    unsafe { add(splat(a), mul(t, splat(c))) }
}

/// Σ_{j<4} c[k + j]·t^j by Estrin's scheme, as the scalar `quad`.
#[inline(always)]
unsafe fn quad(c: &[f64], k: usize, t: __m256d, t2: __m256d) -> __m256d {
    unsafe { add(ma(c[k], t, c[k + 1]), mul(t2, ma(c[k + 2], t, c[k + 3]))) }
}

/// `if mask { a } else { b }` per lane.
#[inline(always)]
unsafe fn select(mask: __m256d, a: __m256d, b: __m256d) -> __m256d {
    unsafe { _mm256_blendv_pd(b, a, mask) }
}

/// 2^k for integer-valued lanes k in [−1022, 1023], as the scalar `pow2`.
#[inline(always)]
unsafe fn pow2(k: __m256d) -> __m256d {
    unsafe {
        let biased = add(k, splat(ROUND + 1023.0));
        _mm256_castsi256_pd(_mm256_slli_epi64::<52>(_mm256_castpd_si256(biased)))
    }
}

/// e^x per lane (see [`super::exp`]).
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub unsafe fn exp4(x: [f64; 4]) -> [f64; 4] {
    unsafe {
        let xv = _mm256_loadu_pd(x.as_ptr());
        // clamp(−746, 710); a NaN lane is replaced at the end.
        let clamped = _mm256_max_pd(_mm256_min_pd(xv, splat(710.0)), splat(-746.0));
        let n = _mm256_sub_pd(
            add(mul(clamped, splat(std::f64::consts::LOG2_E)), splat(ROUND)),
            splat(ROUND),
        );
        let r = _mm256_sub_pd(
            _mm256_sub_pd(clamped, mul(n, splat(LN2_HI))),
            mul(n, splat(LN2_LO)),
        );
        let c = &INV_FACTORIAL;
        let r2 = mul(r, r);
        let r4 = mul(r2, r2);
        let p = add(
            add(quad(c, 0, r, r2), mul(r4, quad(c, 4, r, r2))),
            mul(mul(r4, r4), add(quad(c, 8, r, r2), mul(r4, splat(c[12])))),
        );
        let half = _mm256_sub_pd(add(mul(n, splat(0.5)), splat(ROUND)), splat(ROUND));
        let y = mul(mul(p, pow2(half)), pow2(_mm256_sub_pd(n, half)));
        let y = select(
            _mm256_cmp_pd::<_CMP_GT_OQ>(xv, splat(709.79)),
            splat(f64::INFINITY),
            y,
        );
        let y = select(
            _mm256_cmp_pd::<_CMP_LT_OQ>(xv, splat(-745.2)),
            splat(0.0),
            y,
        );
        let y = select(_mm256_cmp_pd::<_CMP_UNORD_Q>(xv, xv), xv, y);
        let mut out = [0.0; 4];
        _mm256_storeu_pd(out.as_mut_ptr(), y);
        out
    }
}
