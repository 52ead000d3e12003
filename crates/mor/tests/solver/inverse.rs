//! Restitution as input (`emdstar_mor::inverse`) against the forward problem: the exact
//! solver on the physical impact, Schwager & Pöschel's closed form for the linear dashpot,
//! and the published Hertz restitution ε(c_dis) with its small-c_dis series
//! (docs/physics.md, "Reference values").

use crate::common::{HERTZ_RESTITUTION, hertz_restitution_series, hertz_series_tolerance};
use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, Sphere, ViscoelasticHertz,
    scale,
};
use emdstar_mor::inverse::{InverseError, MAX_C_DIS};
use emdstar_mor::{central_c_dis, solve, with_restitution};

const RESTITUTIONS: [f64; 7] = [0.999, 0.95, 0.8, 0.5, 0.2, 0.03, 1e-4];

/// ε_n of a central impact of `pair` at normal speed `v`, by the forward solver on the
/// physical parameters.
fn forward(law: &ForceLaw, pair: &PairProperties, v: f64) -> f64 {
    let pair_law = PairLaw::same_material(law, pair.r_eff).unwrap();
    let impact = Impact::from_speed_eccentricity(v, 0.0).unwrap();
    let scaled = scale(&pair_law, pair, &impact).unwrap();
    -solve(law.model(), &scaled.params).unwrap().eps_rdot
}

fn pair(radius: f64, radius2: f64, density: f64) -> PairProperties {
    PairProperties::spheres(
        &Sphere::from_density(radius, density).unwrap(),
        &Sphere::from_density(radius2, density).unwrap(),
    )
}

#[test]
fn linear_damping_gives_the_restitution_at_every_speed() {
    let materials = [
        (2000.0, pair(0.1, 0.1, 1140.0)),
        (1e5, pair(0.005, 0.01, 2500.0)),
        (5000.0, pair(0.02, 0.02, 7800.0)),
    ];
    for (k, p) in materials {
        let elastic = ForceLaw::Linear(LinearDashpot::new(k, 0.0).unwrap());
        for e in RESTITUTIONS {
            let law = with_restitution(&elastic, &p, 1.0, e).unwrap();
            let ForceLaw::Linear(l) = law else {
                panic!("the model changed")
            };
            assert_eq!(l.stiffness, k);
            // Schwager & Pöschel 2007, closed form, no ODE: an independent reference.
            let analytic = l.central_impact(p.m_eff).unwrap().restitution;
            assert!(
                (analytic - e).abs() <= 1e-10 * e.max(1e-2),
                "k = {k}, ε = {e}: Schwager & Pöschel give {analytic}"
            );
            // The linear dashpot's ε_n does not depend on the speed.
            for v in [0.01, 0.5, 3.0] {
                let got = forward(&law, &p, v);
                assert!(
                    (got - e).abs() <= 1e-10,
                    "k = {k}, ε = {e}, v = {v}: forward solve gives {got}"
                );
            }
            // The speed given to the inverse does not matter either.
            assert_eq!(with_restitution(&elastic, &p, 30.0, e).unwrap(), law);
        }
    }
}

#[test]
fn hertz_dissipation_gives_the_restitution_at_the_speed_it_was_asked_for() {
    let materials = [
        (1e9, 0.4, pair(0.1, 0.1, 1140.0)),
        (7e10, 0.22, pair(0.001, 0.003, 2500.0)),
        (1e7, 0.45, pair(0.01, 0.01, 1000.0)),
    ];
    for (young, poisson, p) in materials {
        let elastic = ForceLaw::Hertz(ViscoelasticHertz::new(young, poisson, 0.0).unwrap());
        for e in RESTITUTIONS {
            let mut dissipation_at = Vec::new();
            for v in [0.05, 1.0, 20.0] {
                let law = with_restitution(&elastic, &p, v, e).unwrap();
                let ForceLaw::Hertz(h) = law else {
                    panic!("the model changed")
                };
                assert_eq!((h.young, h.poisson), (young, poisson));
                let got = forward(&law, &p, v);
                assert!(
                    (got - e).abs() <= 1e-10,
                    "Y = {young}, ε = {e}, v = {v}: forward solve gives {got}"
                );
                dissipation_at.push((v, law));
            }
            // ε_n of viscoelastic spheres falls with the impact speed: the A chosen for a
            // slow impact is too dissipative for a fast one.
            if e < 1.0 {
                let (slow, fast) = (&dissipation_at[0], &dissipation_at[2]);
                assert!(forward(&slow.1, &p, fast.0) < e);
                assert!(forward(&fast.1, &p, slow.0) > e);
            }
        }
    }
}

#[test]
fn hertz_c_dis_matches_the_published_restitution_table() {
    for (delta, eps) in HERTZ_RESTITUTION {
        let c = central_c_dis(Model::Hertz, eps).unwrap();
        // dε/dδ is about −1 here, so six digits of ε fix δ to about 1e-6.
        assert!(
            (c - delta).abs() < 2e-6,
            "ε = {eps}: c_dis = {c}, expected {delta}"
        );
    }
    // Small δ: the series, within its tolerance in ε (|dε/dδ| ≈ 1.15 > 1, so the same
    // bound holds for δ).
    for delta in [1e-5, 1e-4, 1e-3] {
        let c = central_c_dis(Model::Hertz, hertz_restitution_series(delta)).unwrap();
        assert!(
            (c - delta).abs() < hertz_series_tolerance(delta),
            "δ = {delta}: c_dis = {c}"
        );
    }
}

#[test]
fn refusals_say_what_is_wrong() {
    let p = pair(0.1, 0.1, 1140.0);
    let linear = ForceLaw::Linear(LinearDashpot::new(2000.0, 0.0).unwrap());
    let hertz = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, 0.0).unwrap());
    for law in [linear, hertz] {
        for bad in [0.0, 1.5, -0.2, f64::NAN] {
            let err = with_restitution(&law, &p, 1.0, bad).unwrap_err();
            assert!(matches!(err, InverseError::OutOfRange(_)), "{err:?}");
            assert!(err.to_string().contains("outside (0, 1]"), "{err}");
        }
        let err = with_restitution(&law, &p, 1.0, 1e-12).unwrap_err();
        assert!(matches!(err, InverseError::Unreachable { .. }), "{err:?}");
        assert!(err.to_string().contains(&format!("{MAX_C_DIS:e}")), "{err}");
        for v in [0.0, -1.0, f64::INFINITY] {
            let err = with_restitution(&law, &p, v, 0.5).unwrap_err();
            assert!(err.to_string().contains("speed"), "{err}");
        }
        // ε = 1 is an elastic material.
        let elastic = with_restitution(&law, &p, 1.0, 1.0).unwrap();
        assert_eq!(elastic, law);
    }
}
