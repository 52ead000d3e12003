//! e^x of four numbers at once, in plain arithmetic that the compiler vectorises: the
//! four exponentials at the end of every lookup cost about one library call.
//!
//! Cody–Waite reduction x = n·ln 2 + r, |r| ≤ ln 2 / 2, the Taylor polynomial of e^r to
//! degree 12 (truncation below 2e-16 relative), and the scale 2^n built from its bits
//! (split in two factors so that subnormal results come out right). Separate multiplies
//! and adds, no FMA: the same bits on every machine.

/// ln 2 split in a high part with trailing zero bits (n·LN2_HI is exact) and the rest.
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
/// 1.5·2^52: adding it rounds to an integer held in the low mantissa bits.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// 2^k for an integer-valued k in [−1022, 1023].
#[inline(always)]
fn pow2(k: f64) -> f64 {
    f64::from_bits((k + (ROUND + 1023.0)).to_bits() << 52)
}

/// e^x for each lane; exact 0 for −∞ (and below −745.2), +∞ above 709.79, NaN for NaN.
#[inline(always)]
pub fn exp4(x: [f64; 4]) -> [f64; 4] {
    let mut out = [0.0; 4];
    for (o, &x) in out.iter_mut().zip(&x) {
        let clamped = x.clamp(-746.0, 710.0);
        let n = (clamped * std::f64::consts::LOG2_E + ROUND) - ROUND;
        let r = (clamped - n * LN2_HI) - n * LN2_LO;
        let mut p = 1.0 / 479_001_600.0;
        for d in [
            39_916_800.0,
            3_628_800.0,
            362_880.0,
            40_320.0,
            5_040.0,
            720.0,
            120.0,
            24.0,
            6.0,
            2.0,
            1.0,
            1.0,
        ] {
            p = p * r + 1.0 / d;
        }
        // n ∈ [−1076, 1024]: both halves lie in [−538, 512], where 2^k is normal.
        let half = (n * 0.5 + ROUND) - ROUND;
        let y = p * pow2(half) * pow2(n - half);
        *o = if x.is_nan() {
            x
        } else if x < -745.2 {
            0.0
        } else if x > 709.79 {
            f64::INFINITY
        } else {
            y
        };
    }
    out
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
    fn limits_are_exact() {
        let [a, b, c, d] = exp4([f64::NEG_INFINITY, 0.0, f64::INFINITY, f64::NAN]);
        assert_eq!((a, b, c), (0.0, 1.0, f64::INFINITY));
        assert!(d.is_nan());
        let [s, u, _, _] = exp4([-740.0, -800.0, 1.0, 2.0]);
        assert!((s - (-740f64).exp()).abs() <= 1e-3 * (-740f64).exp());
        assert_eq!(u, 0.0);
    }
}
