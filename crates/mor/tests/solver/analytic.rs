//! Analytic limits: elastic durations, Schwager & Pöschel's dashpot, the Hertz restitution
//! table and series of docs/physics.md ("Reference values"), energy conservation, and the large-l̃ limit of ε_φ.

use crate::common::*;
use emdstar_contact::Model;
use emdstar_mor::{SolverOptions, solve, solve_with};
use std::f64::consts::PI;

#[test]
fn linear_elastic_central_impact_lasts_pi_and_keeps_its_energy() {
    for l in [1.5, 10.0, 1e3, 2.4e7] {
        let m = solve(Model::Linear, &params(l, 0.0, 0.0)).unwrap();
        assert!(rel(m.eps_t, PI) < 1e-10, "l = {l}: τ = {}", m.eps_t);
        assert!(
            rel(m.eps_rdot, -1.0) < 1e-10,
            "l = {l}: ε_ṙ = {}",
            m.eps_rdot
        );
        assert_eq!((m.one_minus_eps_r, m.eps_r, m.eps_phi), (0.0, 1.0, 0.0));
    }
}

#[test]
fn hertz_elastic_central_duration_matches_the_gamma_formula() {
    // τ̃ = (4/5)(5/4)^{2/5}·√π·Γ(2/5)/Γ(9/10) = 3.218065 (docs/physics.md), evaluated by
    // emdstar-contact (Lanczos Γ, tested there against known Γ values), not the solver.
    let exact = emdstar_contact::hertz_elastic_scaled_duration();
    assert!((exact - 3.218065).abs() < 5e-7);
    for l in [2.0, 1e3, 2.4e7] {
        let m = solve(Model::Hertz, &params(l, 0.0, 0.0)).unwrap();
        assert!(rel(m.eps_t, exact) < 1e-10, "l = {l}: τ = {}", m.eps_t);
        assert!(
            rel(m.eps_rdot, -1.0) < 1e-10,
            "l = {l}: ε_ṙ = {}",
            m.eps_rdot
        );
    }
}

/// Schwager & Pöschel, Granular Matter 9, 465 (2007), as tabulated in docs/physics.md, in scaled
/// units ω0 = 1, β = c_dis/2: (t_c, ε).
fn schwager_poeschel(c_dis: f64) -> (f64, f64) {
    let omega0 = 1.0f64;
    let beta = c_dis / 2.0;
    let t_c = if beta > omega0 {
        let big = (beta * beta - omega0 * omega0).sqrt();
        ((beta + big) / (beta - big)).ln() / big
    } else {
        let omega = (omega0 * omega0 - beta * beta).sqrt();
        let arctan = (2.0 * beta * omega / (omega * omega - beta * beta)).atan();
        if beta < omega0 / 2f64.sqrt() {
            (PI - arctan) / omega
        } else if beta == omega0 / 2f64.sqrt() {
            PI / (2.0 * omega)
        } else {
            -arctan / omega
        }
    };
    (t_c, (-beta * t_c).exp())
}

#[test]
fn linear_dashpot_matches_schwager_poeschel_in_every_damping_regime() {
    // β < ω0/√2, = ω0/√2, between, = ω0 (limit 2/β of the overdamped form), > ω0.
    let cases = [1e-6, 0.1, 0.9, 2f64.sqrt(), 1.6, 1.99, 2.0, 2.01, 5.0, 54.6];
    for c_dis in cases {
        let (t_c, eps) = if c_dis == 2.0 {
            (2.0, (-2.0f64).exp())
        } else {
            schwager_poeschel(c_dis)
        };
        check_central_linear(c_dis, t_c, eps);
    }
}

/// Solves a central linear-dashpot impact and compares with (t_c, ε); F = 0 at the end
/// also means ξ = c_dis·ε.
fn check_central_linear(c_dis: f64, t_c: f64, eps: f64) {
    let m = solve(Model::Linear, &params(1e4, 0.0, c_dis)).unwrap();
    let e = [m.eps_t, -m.eps_rdot, m.one_minus_eps_r * 1e4];
    let want = [t_c, eps, c_dis * eps];
    for (x, y) in e.iter().zip(want) {
        assert!(rel(*x, y) < 1e-9, "c_dis = {c_dis}: {e:?} vs {want:?}");
    }
}

#[test]
fn strongly_overdamped_central_impacts_stay_accurate() {
    // β ≫ ω0: t_c = ln((β+Ω)/(β−Ω))/Ω with β − Ω = ω0²/(β + Ω) to avoid cancellation.
    for c_dis in [1e2, 1e4, 1e6, 1e8f64] {
        let beta = c_dis / 2.0;
        let big = (beta * beta - 1.0).sqrt();
        let t_c = ((beta + big) * (beta + big)).ln() / big;
        check_central_linear(c_dis, t_c, (-beta * t_c).exp());
    }
}

#[test]
fn hertz_central_restitution_matches_the_table_and_the_small_delta_series() {
    for (delta, eps) in HERTZ_RESTITUTION {
        let m = solve(Model::Hertz, &params(1e4, 0.0, delta)).unwrap();
        assert!(
            (-m.eps_rdot - eps).abs() < 6e-7,
            "δ = {delta}: {}",
            -m.eps_rdot
        );
    }
    for delta in [1e-6, 1e-5, 1e-4] {
        let m = solve(Model::Hertz, &params(1e4, 0.0, delta)).unwrap();
        let d = (-m.eps_rdot - hertz_restitution_series(delta)).abs();
        assert!(
            d < hertz_series_tolerance(delta),
            "δ = {delta}: off by {d:e}"
        );
    }
}

#[test]
fn elastic_oblique_impacts_conserve_energy() {
    // c_dis = 0: the end is at r = l̃, where the centrifugal and elastic potentials take
    // their start values, so ½u² is conserved: ε_ṙ = −1 and ε_r = 1 — also for small l̃,
    // where the spheres nearly pass through each other.
    for model in [Model::Linear, Model::Hertz] {
        for p in uniform_in_rect(model, 100, 7) {
            let p = params(p.l_tilde, p.c_phi, 0.0);
            let m = solve(model, &p).unwrap();
            assert!(
                rel(m.eps_rdot, -1.0) < 1e-10,
                "{model} {p:?}: {}",
                m.eps_rdot
            );
            assert_eq!(m.eps_r, 1.0);
        }
    }
}

#[test]
fn rotation_at_huge_l_tilde_follows_the_perturbation_series() {
    // l̃ → ∞, linear, elastic: ξ = sin t, φ' = (c_φ/l̃²)(1 + 2ξ/l̃ + …), so
    // ε_φ = (c_φ/l̃²)(π + 4/l̃) up to O(s²/l̃, 1/l̃²) with s = c_φ/l̃.
    let l = 17f64.exp();
    let c_phi = 0.01 * l;
    let m = solve(Model::Linear, &params(l, c_phi, 0.0)).unwrap();
    let expected = c_phi / (l * l) * (PI + 4.0 / l);
    assert!(
        rel(m.eps_phi, expected) < 1e-10,
        "{} vs {expected}",
        m.eps_phi
    );
}

#[test]
fn invalid_parameters_and_options_are_clear_errors() {
    let bad = [
        params(f64::NAN, 1.0, 1.0),
        params(0.0, 1.0, 1.0),
        params(-1.0, 1.0, 1.0),
        params(f64::INFINITY, 1.0, 1.0),
        params(1.0, -1.0, 1.0),
        params(1.0, f64::NAN, 1.0),
        params(1.0, 1.0, -1e-3),
        params(1.0, 1.0, f64::NAN),
    ];
    for model in [Model::Linear, Model::Hertz] {
        for p in bad {
            let e = solve(model, &p).unwrap_err().to_string();
            assert!(e.contains("must be finite"), "{p:?}: {e}");
        }
        // Central impact whose overlap would reach l̃: the centres meet.
        let e = solve(model, &params(0.5, 0.0, 0.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("centres meet"), "{e}");
        let o = SolverOptions {
            rtol: 0.0,
            ..SolverOptions::default()
        };
        assert!(solve_with(model, &params(10.0, 1.0, 1.0), &o).is_err());
        let o = SolverOptions {
            max_steps: 3,
            ..SolverOptions::default()
        };
        let e = solve_with(model, &params(10.0, 1.0, 1.0), &o)
            .unwrap_err()
            .to_string();
        assert!(e.contains("did not end"), "{e}");
    }
}

#[test]
fn central_impacts_just_clear_of_the_centre_still_solve() {
    // Overlap reaches 1 (linear, elastic): l̃ = 1.01 keeps r > 0; the small-l̃ regime with
    // c_φ > 0 is kept away from r = 0 by the centrifugal barrier.
    let m = solve(Model::Linear, &params(1.01, 0.0, 0.0)).unwrap();
    assert!(rel(m.eps_t, PI) < 1e-10);
    let m = solve(Model::Linear, &params(0.1, 1e-3, 0.0)).unwrap();
    assert!(m.eps_t.is_finite() && m.eps_phi > 0.0 && rel(m.eps_rdot, -1.0) < 1e-10);
}
