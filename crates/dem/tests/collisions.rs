//! Two-sphere collisions converge to the exact solution (the eMD* rule with the exact
//! MoR, crates/mor) as dt → 0, for both laws, central and oblique.

mod common;

use common::*;
use emdstar_dem::ContactEnd;

/// Errors for 25·τ_steps … halving dt five times; prints them and the orders.
fn study(name: &str, c: &Collision) -> (Vec<f64>, Vec<f64>) {
    let errors: Vec<f64> = (0..6)
        .map(|k| c.error(25 << k, ContactEnd::ForceZero))
        .collect();
    let orders = orders(&errors);
    let e: Vec<String> = errors.iter().map(|x| format!("{x:.3e}")).collect();
    let o: Vec<String> = orders.iter().map(|x| format!("{x:.2}")).collect();
    println!("{name}: steps per contact 25..800, errors {e:?}, orders {o:?}");
    (errors, orders)
}

#[test]
fn linear_dashpot_converges_at_first_order_or_better() {
    // c_dis ≈ 0.25; the damping force jumps to γ·v_n at first touch, which the step
    // resolves to O(dt): first order is what the integrator can give here.
    for (name, e) in [("linear central", 0.0), ("linear oblique", 0.6)] {
        let (errors, orders) = study(name, &Collision::new(linear(15.0), 5.0, e));
        assert!(
            errors[5] < 1e-3,
            "{name}: error {:e} at 800 steps per contact",
            errors[5]
        );
        let mean = orders[2..].iter().sum::<f64>() / 3.0;
        assert!(mean > 0.9, "{name}: observed order {mean}");
    }
}

#[test]
fn elastic_linear_converges_at_second_order() {
    for (name, e) in [
        ("linear elastic central", 0.0),
        ("linear elastic oblique", 0.6),
    ] {
        let (errors, orders) = study(name, &Collision::new(linear(0.0), 5.0, e));
        assert!(errors[5] < 1e-4, "{name}: error {:e}", errors[5]);
        let mean = orders[2..].iter().sum::<f64>() / 3.0;
        assert!(mean > 1.8, "{name}: observed order {mean}");
    }
}

#[test]
fn hertz_converges() {
    for (name, a, e) in [
        ("hertz central", 1e-4, 0.0),
        ("hertz oblique", 1e-4, 0.6),
        ("hertz elastic oblique", 0.0, 0.6),
    ] {
        let (errors, orders) = study(name, &Collision::new(hertz(a), 1.0, e));
        assert!(errors[5] < 1e-3, "{name}: error {:e}", errors[5]);
        let mean = orders[2..].iter().sum::<f64>() / 3.0;
        assert!(mean > 0.9, "{name}: observed order {mean}");
    }
}
