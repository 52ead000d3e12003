//! Two-sphere collisions converge to the exact solution (the eMD* rule with the exact
//! MoR, crates/mor) as dt → 0, for both laws, central and oblique. Run with
//! `--nocapture` to see the errors and the observed orders.

mod common;

use common::*;
use emdstar_contact::Vec3;
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

/// Spheres 10⁴ m apart along every axis in free space: the list's grid widens its cells
/// instead of asking for one cell per contact distance over the whole span (10¹³ cells,
/// found by fuzzing), and a pair there still collides as a lone pair would.
#[test]
fn far_apart_spheres_in_free_space_get_a_small_grid() {
    let far = 1e4;
    let system = free_system(
        linear(0.0),
        &[
            (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.0)),
            (Vec3::new(far, far, far), Vec3::new(0.0, 0.0, 0.0)),
            (Vec3::new(far + 0.3, far, far), Vec3::new(-1.0, 0.0, 0.0)),
        ],
    );
    let start = std::time::Instant::now();
    let mut md = engine(system, 1e-4, 1.0);
    md.advance(4000).unwrap();
    assert!(start.elapsed().as_secs_f64() < 10.0);
    // Equal masses, elastic, head-on: the moving sphere stops, the one it hit moves on.
    let v = md.particles_in_config_order().velocity;
    assert!(
        v[2][0].abs() < 1e-3 && (v[1][0] + 1.0).abs() < 1e-3,
        "{v:?}"
    );
}
