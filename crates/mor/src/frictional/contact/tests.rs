//! The AVX2 and FMA build of the fast solver against its portable build.

use super::super::{Frame, contact, start};
use super::*;
use emdstar_contact::PairLaw;

/// The AVX2 and FMA build of the integrator takes the same steps to the same bits as the
/// portable one (the same operations in the same order; the Runge–Kutta sums are fused
/// multiply-adds in both, by the CPU or in software).
#[test]
fn the_avx2_path_is_the_portable_one_to_the_bit() {
    if !(std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma"))
    {
        eprintln!("no AVX2 and FMA here: nothing to compare");
        return;
    }
    let opts = super::super::CONTACT_OPTIONS;
    for (k, law) in [
        PairLaw::Hertz {
            rho_el: 5.6e7,
            dissipation: 9.5e-6,
        },
        PairLaw::Linear {
            stiffness: 2000.0,
            damping: 0.5,
        },
    ]
    .iter()
    .enumerate()
    {
        let spring = HistorySpring {
            friction: 0.3,
            stiffness: if k == 0 { 1e5 } else { 500.0 },
            damping: 0.1 * k as f64,
        };
        let r: [f64; 3] = [0.012, -0.015, 0.004];
        let l = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let v = [-0.9, 1.1, 0.2];
        let approach = -(v[0] * r[0] + v[1] * r[1] + v[2] * r[2]) / l;
        let c = contact(
            law,
            &spring,
            Geometry::Pair { l },
            2.4e-3,
            (5.0e4, 2.5e2),
            v,
            approach,
            l,
            &opts,
        );
        let y0 = start(&Frame::new(r, v), v, [0.3, -0.2, 0.5], [1.0, 0.0, 0.0, 0.0]);
        let portable = c.integrate_portable(y0).unwrap();
        // SAFETY: the CPU has AVX2 and FMA (checked above).
        let avx2 = unsafe { c.integrate_avx2(y0) }.unwrap();
        assert_eq!(portable.0.map(f64::to_bits), avx2.0.map(f64::to_bits));
        assert_eq!(portable.1, avx2.1);
        assert_eq!(portable.2, avx2.2);
    }
}
