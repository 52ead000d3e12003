//! e^x and ln x in plain arithmetic that the compiler inlines: the four exponentials at
//! the end of every lookup cost less than one library call, and the logarithms of the
//! physical map a fraction of one. Separate multiplies and adds, no FMA: the same bits
//! on every machine.
//!
//! - [`exp4`]: Cody–Waite reduction x = n·ln 2 + r, |r| ≤ ln 2 / 2, the Taylor
//!   polynomial of e^r to degree 12 (truncation below 2e-16 relative; summed by
//!   Estrin's scheme), and the scale 2^n
//!   built from its bits (split in two factors so that subnormal results come out right).
//!   With AVX2 (detected at run time) the four lanes run in one vector register, with
//!   the same operations in the same order, so that each lane has the bits of the
//!   scalar [`exp`] on every machine (a random lookup is about a tenth faster).
//! - [`ln`]: x = 2^e·m, a table of 128 logarithms ln c near m (computed at compile time
//!   by a slower series, [`ln_series`]) and the series of ln(1 + r), r = (m − c)/c,
//!   |r| < 2⁻⁷, to r⁸. The error is a few units in the last place of the result
//!   (tested below against the library logarithm: relative error below 4e-16, near
//!   x = 1 included).

/// ln 2 split in a high part with trailing zero bits (n·LN2_HI is exact) and the rest.
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
/// 1.5·2^52: adding it rounds to an integer held in the low mantissa bits.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// Σ_{j<4} c[k + j]·t^j by Estrin's scheme (t2 = t²).
#[inline(always)]
const fn quad(c: &[f64], k: usize, t: f64, t2: f64) -> f64 {
    (c[k] + t * c[k + 1]) + t2 * (c[k + 2] + t * c[k + 3])
}

/// 1/k! for k ≤ 12.
const INV_FACTORIAL: [f64; 13] = [
    1.0,
    1.0,
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5_040.0,
    1.0 / 40_320.0,
    1.0 / 362_880.0,
    1.0 / 3_628_800.0,
    1.0 / 39_916_800.0,
    1.0 / 479_001_600.0,
];

/// 1/(2k + 3) for k ≤ 10: the series of [`ln`].
const INV_ODD: [f64; 11] = [
    1.0 / 3.0,
    1.0 / 5.0,
    1.0 / 7.0,
    1.0 / 9.0,
    1.0 / 11.0,
    1.0 / 13.0,
    1.0 / 15.0,
    1.0 / 17.0,
    1.0 / 19.0,
    1.0 / 21.0,
    1.0 / 23.0,
];

/// 2^k for an integer-valued k in [−1022, 1023].
#[inline(always)]
fn pow2(k: f64) -> f64 {
    f64::from_bits((k + (ROUND + 1023.0)).to_bits() << 52)
}

#[cfg(target_arch = "x86_64")]
mod avx2;

/// Whether [`exp4`] may run its AVX2 code.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn has_avx2() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
}

/// e^x for each lane; exact 0 for −∞ (and below −745.2), +∞ above 709.79, NaN for NaN.
#[inline(always)]
pub fn exp4(x: [f64; 4]) -> [f64; 4] {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        // SAFETY: the CPU supports AVX2 (checked just above).
        return unsafe { avx2::exp4(x) };
    }
    x.map(exp)
}

/// e^x (see [`exp4`]).
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    let clamped = x.clamp(-746.0, 710.0);
    let n = (clamped * std::f64::consts::LOG2_E + ROUND) - ROUND;
    let r = (clamped - n * LN2_HI) - n * LN2_LO;
    // Σ r^k/k! for k ≤ 12 by Estrin's scheme (a short dependency chain; a lookup waits
    // on latency): pairs in r, pairs of pairs in r², then r⁴ and r⁸.
    let c = INV_FACTORIAL;
    let (r2, r4) = (r * r, (r * r) * (r * r));
    let p = (quad(&c, 0, r, r2) + r4 * quad(&c, 4, r, r2))
        + (r4 * r4) * (quad(&c, 8, r, r2) + r4 * c[12]);
    // n ∈ [−1076, 1024]: both halves lie in [−538, 512], where 2^k is normal.
    let half = (n * 0.5 + ROUND) - ROUND;
    let y = p * pow2(half) * pow2(n - half);
    if x.is_nan() {
        x
    } else if x < -745.2 {
        0.0
    } else if x > 709.79 {
        f64::INFINITY
    } else {
        y
    }
}

/// 2^54, to lift subnormal arguments of [`ln`] into the normal range.
const TWO54: f64 = 18_014_398_509_481_984.0;

/// Mantissa bits that index [`LN_TABLE`], and the first index whose m is halved (its
/// exponent raised): m ≥ 1 + 53/128 = 1.4140625 ≈ √2, so that the reduced argument is
/// near 1 and ln stays accurate relative to itself on both sides of x = 1.
const LN_BITS: u32 = 7;
const LN_FOLD: u64 = 53;

/// Per index i (the top [`LN_BITS`] bits of the mantissa m ∈ [1, 2)): [1/c, ln(c/2^f)]
/// with c = 1 + (i + f)/128 the end of i's interval nearer to 1 after the fold f (0 or
/// 1): the left end below the fold, the right one above, so that c/2^f = 1 exactly for
/// the intervals either side of 1. Computed at compile time by [`ln_series`].
const LN_TABLE: [[f64; 2]; 1 << LN_BITS] = ln_table();

const fn ln_table() -> [[f64; 2]; 1 << LN_BITS] {
    let mut t = [[0.0; 2]; 1 << LN_BITS];
    let mut i = 0;
    while i < t.len() {
        let fold = (i as u64 >= LN_FOLD) as u64;
        let c = ln_anchor(i as u64, fold);
        let reduced = if fold == 1 { c * 0.5 } else { c };
        t[i] = [1.0 / c, ln_series(reduced)];
        i += 1;
    }
    t
}

/// 1 + (i + fold)/128, exactly (2 for the last index above the fold).
#[inline(always)]
const fn ln_anchor(i: u64, fold: u64) -> f64 {
    f64::from_bits(0x3FF0_0000_0000_0000 + ((i + fold) << (52 - LN_BITS)))
}

/// −1/(k + 2) · (−1)^k for k ≤ 6: ln(1 + r) = r + r²·Σ_k c_k r^k.
const LOG1P_TAIL: [f64; 7] = [
    -1.0 / 2.0,
    1.0 / 3.0,
    -1.0 / 4.0,
    1.0 / 5.0,
    -1.0 / 6.0,
    1.0 / 7.0,
    -1.0 / 8.0,
];

/// ln x; −∞ for ±0, NaN for x < 0 or NaN, +∞ for +∞.
///
/// x = 2^e·m, m ∈ [1, 2); a table ([`LN_TABLE`]) indexed by m's top seven bits gives
/// c near m with ln c, and ln m = ln c + ln(1 + r) with r = (m − c)/c, |r| < 2⁻⁷, by
/// its Taylor series to r⁸ (truncation below 2e-18 relative). m − c is exact; the
/// rest is a few roundings: a few units in the last place, near x = 1 included (there
/// c = 1 and ln x = ln(1 + r) with r = x − 1 exactly).
#[inline(always)]
pub fn ln(x: f64) -> f64 {
    if !(x > 0.0 && x < f64::INFINITY) {
        return if x == 0.0 {
            f64::NEG_INFINITY
        } else if x == f64::INFINITY {
            x
        } else {
            f64::NAN
        };
    }
    let (x, e0) = if x < f64::MIN_POSITIVE {
        (x * TWO54, -54.0)
    } else {
        (x, 0.0)
    };
    let bits = x.to_bits();
    let i = (bits >> (52 - LN_BITS)) & ((1 << LN_BITS) - 1);
    let fold = (i >= LN_FOLD) as u64;
    let m = f64::from_bits((bits & 0x000F_FFFF_FFFF_FFFF) | 0x3FF0_0000_0000_0000);
    let e = ((bits >> 52) as i64 - 1023 + fold as i64) as f64 + e0;
    let [inv_c, ln_c] = LN_TABLE[i as usize];
    let r = (m - ln_anchor(i, fold)) * inv_c;
    let (r2, r4) = (r * r, (r * r) * (r * r));
    let c = LOG1P_TAIL;
    let q = (c[0] + r * c[1]) + r2 * (c[2] + r * c[3]) + r4 * ((c[4] + r * c[5]) + r2 * c[6]);
    e * LN2_HI + (ln_c + (r + (e * LN2_LO + r2 * q)))
}

/// ln x for the table of [`ln`], at compile time: x = 2^e·m with m ∈ [1/√2, √2),
/// ln m = 2 atanh(s) with s = (m − 1)/(m + 1), |s| ≤ 0.1716, summed to s²³ (truncation
/// below 1e-17 relative), plus e·ln 2 in two parts. For normal x > 0.
const fn ln_series(x: f64) -> f64 {
    let bits = x.to_bits();
    // m ∈ [1, 2) from the mantissa; above √2 halve it (exactly) and raise the exponent.
    let mut m = f64::from_bits((bits & 0x000F_FFFF_FFFF_FFFF) | 0x3FF0_0000_0000_0000);
    let mut e = ((bits >> 52) as i64 - 1023) as f64;
    if m > std::f64::consts::SQRT_2 {
        m *= 0.5;
        e += 1.0;
    }
    let f = m - 1.0;
    let s = f / (m + 1.0);
    let z = s * s;
    // p = Σ_{k=0}^{10} z^k/(2k + 3) by Estrin's scheme, as in `exp`.
    let c = &INV_ODD;
    let (z2, z4) = (z * z, (z * z) * (z * z));
    let p =
        (quad(c, 0, z, z2) + z4 * quad(c, 4, z, z2)) + (z4 * z4) * ((c[8] + z * c[9]) + z2 * c[10]);
    // ln m = 2s(1 + z/3 + z²/5 + …) = 2s + 2s·z·p; the small terms are summed first.
    let tail = 2.0 * s * (z * p);
    e * LN2_HI + (2.0 * s + (e * LN2_LO + tail))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_library_exp_to_a_few_ulp() {
        let mut worst: f64 = 0.0;
        let mut x = -744.0;
        while x < 709.0 {
            for dx in [0.0, 0.123_456_789, 0.5, std::f64::consts::LN_2] {
                let xs = [x + dx, -(x + dx) * 1e-3, (x + dx) * 1e-9, 0.25 * (x + dx)];
                let got = exp4(xs);
                for (g, &v) in got.iter().zip(&xs) {
                    let want = v.exp();
                    if want.is_normal() {
                        worst = worst.max(((g - want) / want).abs());
                    }
                }
            }
            x += 0.731;
        }
        assert!(worst < 1e-15, "{worst:e}");
    }

    #[test]
    fn ln_matches_the_library_logarithm() {
        let mut worst = 0.0f64;
        let mut check = |v: f64| {
            let (got, want) = (ln(v), v.ln());
            if want != 0.0 {
                worst = worst.max(((got - want) / want).abs());
            }
        };
        let mut x = 1e-310;
        while x < 1e300 {
            for f in [
                1.0,
                1.000_000_1,
                // Either side of the switch at √2.
                std::f64::consts::SQRT_2 * (1.0 - 1e-15),
                std::f64::consts::SQRT_2 * (1.0 + 1e-15),
                1.999_999_9,
                0.999_999_9,
            ] {
                check(x * f);
            }
            x *= 1.37;
        }
        // Near 1, where ln x → 0.
        for k in -20000..20000 {
            check(1.0 + k as f64 * 1e-5);
            check(1.0 + k as f64 * 1e-13);
        }
        assert!(worst < 4e-16, "{worst:e}");
        assert_eq!(ln(1.0), 0.0);
        assert_eq!(ln(0.0), f64::NEG_INFINITY);
        assert_eq!(ln(f64::INFINITY), f64::INFINITY);
        assert!(ln(-1.0).is_nan() && ln(f64::NAN).is_nan());
    }

    #[test]
    fn the_table_of_ln_holds_accurate_logarithms() {
        for (i, [inv_c, ln_c]) in LN_TABLE.iter().enumerate() {
            let fold = (i as u64 >= LN_FOLD) as u64;
            let c = ln_anchor(i as u64, fold);
            assert_eq!(*inv_c, 1.0 / c);
            let want = (c / (1 << fold) as f64).ln();
            assert!(
                (ln_c - want).abs() <= 4e-16 * want.abs(),
                "{i}: {ln_c} against {want}"
            );
        }
        assert_eq!(LN_TABLE[0][1], 0.0);
        assert_eq!(LN_TABLE[LN_TABLE.len() - 1][1], 0.0);
    }

    /// Arguments over the whole range, the special values and the limits of `exp`.
    fn probe_arguments() -> Vec<f64> {
        let mut xs = vec![
            0.0,
            -0.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            5e-324,
            f64::MAX,
            709.79,
            709.8,
            709.78,
            -745.2,
            -745.3,
            -745.1,
            710.5,
            -746.5,
        ];
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..20_000 {
            // xorshift64*: arbitrary bit patterns, then values of every exponent.
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            let r = state.wrapping_mul(0x2545_F491_4F6C_DD1D);
            xs.push(f64::from_bits(r));
            xs.push((r >> 11) as f64 / (1u64 << 53) as f64 * 1500.0 - 750.0);
        }
        xs
    }

    #[test]
    fn four_lanes_give_the_bits_of_the_scalar_exp() {
        let xs = probe_arguments();
        for w in xs.windows(4) {
            let x = [w[0], w[1], w[2], w[3]];
            let e = exp4(x);
            for i in 0..4 {
                assert_eq!(e[i].to_bits(), exp(x[i]).to_bits(), "exp({:e})", x[i]);
            }
        }
    }

    #[test]
    fn limits_are_exact() {
        let [a, b, c, d] = exp4([f64::NEG_INFINITY, 0.0, f64::INFINITY, f64::NAN]);
        assert_eq!((a, b, c), (0.0, 1.0, f64::INFINITY));
        assert!(d.is_nan());
        let [s, u, _, _] = exp4([-740.0, -800.0, 1.0, 2.0]);
        assert!((s - (-740f64).exp()).abs() <= 1e-3 * (-740f64).exp());
        assert_eq!(u, 0.0);
    }
}
