//! The default tolerances against much tighter ones, over corners and random points of
//! both rectangles, and physical properties of every solution (proptest).

use crate::common::*;
use emdstar_contact::{Model, RectCoords};
use emdstar_mor::{SolverOptions, solve, solve_with};
use proptest::prelude::*;

#[test]
fn default_tolerances_agree_with_tight_ones_on_both_rectangles() {
    for model in [Model::Linear, Model::Hertz] {
        let mut points = corners(model);
        points.extend(uniform_in_rect(model, 300, 5));
        points.extend(log_uniform_physical(model, 300, 6));
        for p in &points {
            let m = solve(model, p).unwrap();
            let (r, _) = solve_with(model, p, &tight()).unwrap();
            let e = mor_errors(&m, &r);
            assert!(e.iter().all(|&x| x <= 1e-9), "{model} {p:?}: {e:?}");
        }
    }
}

/// The potential energy of the scaled force law at overlap ξ.
fn potential(model: Model, xi: f64) -> f64 {
    match model {
        Model::Linear => 0.5 * xi * xi,
        Model::Hertz => 0.4 * xi.powf(2.5),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Anywhere in either rectangle: a finite MoR with ε_r ≤ 1, −1 ≤ ε_ṙ < 0, τ̃ > 0,
    /// ε_φ ≥ 0, F = 0 at the end, and no energy gained: ½ε_ṙ² + c_φ²/(2l̃²ε_r²) + V(ξ) ≤
    /// ½ + c_φ²/(2l̃²) (the dashpot only dissipates).
    #[test]
    fn every_solution_is_physical(hertz: bool, a in 0.0..1.0f64, b in 0.0..1.0f64, c in 0.0..1.0f64) {
        let model = if hertz { Model::Hertz } else { Model::Linear };
        let bounds = bounds(model);
        let [ra, rb, rc] = bounds.axes();
        let p = bounds.from_rect(&RectCoords {
            a: ra.min + a * ra.width(),
            b: rb.min + b * rb.width(),
            c: rc.min + c * rc.width(),
        });
        let m = solve(model, &p).unwrap();
        prop_assert!(m.eps_t > 0.0 && m.eps_phi >= 0.0);
        prop_assert!(m.one_minus_eps_r >= 0.0 && m.eps_r <= 1.0 && m.eps_r > 0.0);
        prop_assert!(m.eps_rdot < 0.0 && m.eps_rdot >= -1.0 - 1e-12);
        let xi = m.one_minus_eps_r * p.l_tilde;
        prop_assert!(rel(xi, -p.c_dis * m.eps_rdot) < 1e-12);
        let s = p.c_phi / p.l_tilde;
        let before = 0.5 + 0.5 * s * s;
        let after = 0.5 * m.eps_rdot.powi(2) + 0.5 * (s / m.eps_r).powi(2) + potential(model, xi);
        prop_assert!(after <= before * (1.0 + 1e-12), "{} > {}", after, before);
    }
}

/// A fixed workload for instruction counts (`valgrind --tool=callgrind <test binary>
/// --ignored --exact tolerance::workload_linear`), a noise-free proxy of speed on a shared
/// machine.
fn workload(model: Model) {
    let points = uniform_in_rect(model, 256, 42);
    for _ in 0..100 {
        for p in &points {
            std::hint::black_box(solve(model, p).unwrap());
        }
    }
}

#[test]
#[ignore]
fn workload_linear() {
    workload(Model::Linear);
}

#[test]
#[ignore]
fn workload_hertz() {
    workload(Model::Hertz);
}

#[test]
fn extreme_inputs_give_a_physical_result_or_a_clear_error() {
    let cases = [
        params(0.5, 1e-6, 0.0),
        params(0.5, 1e-12, 0.1),
        params(1e-3, 1e-4, 0.0),
        params(1e12, 1e11, 1.0),
        params(1e12, 0.0, 1e15),
        params(10.0, 1.0, 1e15),
        params(10.0, 100.0, 1e-300),
        params(10.0, 1e-300, 1e-3),
        params(f64::MAX, 1.0, 1.0),
    ];
    for model in [Model::Linear, Model::Hertz] {
        for p in cases {
            match solve_with(model, &p, &SolverOptions::default()) {
                Ok((m, s)) => {
                    eprintln!("{model} {p:?}: {m:?} {s:?}");
                    assert!(m.eps_t > 0.0 && m.eps_t.is_finite(), "{model} {p:?}: {m:?}");
                    assert!(
                        m.eps_rdot < 0.0 && m.eps_rdot >= -1.0 - 1e-9,
                        "{model} {p:?}: {m:?}"
                    );
                    assert!(
                        (0.0..=1.0).contains(&m.one_minus_eps_r),
                        "{model} {p:?}: {m:?}"
                    );
                    assert!(
                        m.eps_phi >= 0.0 && m.eps_phi.is_finite(),
                        "{model} {p:?}: {m:?}"
                    );
                }
                Err(e) => {
                    eprintln!("{model} {p:?}: error {e}");
                    assert!(!e.to_string().is_empty());
                }
            }
        }
    }
}
