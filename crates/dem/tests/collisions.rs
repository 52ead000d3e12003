//! Two-sphere collisions converge to the exact solution (the eMD* rule with the exact
//! MoR, crates/mor) as dt → 0, for both laws, central and oblique. Run with
//! `--nocapture` to see the errors and the observed orders.

mod common;

use common::*;
use emdstar_dem::ContactEnd;

/// Errors for 25 … 800 steps per contact (dt halved five times) and the fitted order.
fn study(name: &str, c: &Collision) -> (Vec<f64>, f64) {
    let errors: Vec<f64> = (0..6)
        .map(|k| c.error(25 << k, ContactEnd::ForceZero))
        .collect();
    let e: Vec<String> = errors.iter().map(|x| format!("{x:.2e}")).collect();
    let o: Vec<String> = orders(&errors).iter().map(|x| format!("{x:.2}")).collect();
    let fitted = fitted_order(&errors);
    println!(
        "{name}: errors {e:?} for 25..800 steps per contact; ratios {o:?}; fitted order {fitted:.2}"
    );
    (errors, fitted)
}

#[test]
fn linear_dashpot_converges_at_second_order() {
    // The damped cases rely on the touch correction (forces.rs): without it the force
    // jump γ·v_n at first touch makes them first order.
    for (name, gamma, e) in [
        ("linear damped central", 15.0, 0.0),
        ("linear damped oblique", 15.0, 0.6),
        ("linear elastic central", 0.0, 0.0),
        ("linear elastic oblique", 0.0, 0.6),
    ] {
        let (errors, order) = study(name, &Collision::new(linear(gamma), 5.0, e));
        assert!(
            errors[5] < 2e-6,
            "{name}: error {:e} at 800 steps per contact",
            errors[5]
        );
        assert!(order > 1.8, "{name}: observed order {order}");
    }
}

#[test]
fn hertz_converges_faster_than_first_order() {
    // F ∝ ξ^{3/2} (elastic) and √ξ·ξ̇ (damping) are not smooth at first touch, which
    // limits the order below 2.
    for (name, a, e) in [
        ("hertz damped central", 1e-4, 0.0),
        ("hertz damped oblique", 1e-4, 0.6),
        ("hertz elastic oblique", 0.0, 0.6),
    ] {
        let (errors, order) = study(name, &Collision::new(hertz(a), 1.0, e));
        assert!(errors[5] < 5e-6, "{name}: error {:e}", errors[5]);
        assert!(order > 1.4, "{name}: observed order {order}");
    }
}
