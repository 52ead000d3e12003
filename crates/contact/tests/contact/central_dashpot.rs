//! Central linear-dashpot impacts with the force-zero end (Schwager & Pöschel,
//! Granular Matter 9, 465, 2007), in all four damping regimes, against the regime-wise
//! table of docs/physics.md ("Reference values") and against a plain RK4 integration of m ξ̈ = −(kξ + γξ̇).

use emdstar_contact::LinearDashpot;
use std::f64::consts::PI;

/// The table of docs/physics.md, "Reference values", regime by regime.
fn table(k: f64, gamma: f64, m: f64) -> (f64, f64) {
    let w0 = (k / m).sqrt();
    let beta = gamma / (2.0 * m);
    let tc = if beta < w0 / 2f64.sqrt() {
        let w = (w0 * w0 - beta * beta).sqrt();
        (PI - (2.0 * beta * w / (w * w - beta * beta)).atan()) / w
    } else if beta == w0 / 2f64.sqrt() {
        let w = (w0 * w0 - beta * beta).sqrt();
        PI / (2.0 * w)
    } else if beta < w0 {
        let w = (w0 * w0 - beta * beta).sqrt();
        -(2.0 * beta * w / (w * w - beta * beta)).atan() / w
    } else {
        let big = (beta * beta - w0 * w0).sqrt();
        ((beta + big) / (beta - big)).ln() / big
    };
    (tc, (-beta * tc).exp())
}

/// RK4 until the force kξ + γξ̇ changes sign with ξ̇ < 0; linear interpolation of the
/// crossing. Returns (duration, −ξ̇/v₀).
fn integrate(k: f64, gamma: f64, m: f64, t_guess: f64) -> (f64, f64) {
    let v0 = 1.0;
    let acc = |x: f64, v: f64| -(k * x + gamma * v) / m;
    let dt = t_guess * 2e-6;
    let (mut t, mut x, mut v) = (0.0, 0.0, v0);
    loop {
        let (k1x, k1v) = (v, acc(x, v));
        let (k2x, k2v) = (
            v + 0.5 * dt * k1v,
            acc(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v),
        );
        let (k3x, k3v) = (
            v + 0.5 * dt * k2v,
            acc(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v),
        );
        let (k4x, k4v) = (v + dt * k3v, acc(x + dt * k3x, v + dt * k3v));
        let xn = x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        let vn = v + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        let (f0, f1) = (k * x + gamma * v, k * xn + gamma * vn);
        if t > 0.0 && f1 <= 0.0 && vn < 0.0 {
            let s = f0 / (f0 - f1);
            return (t + s * dt, -(v + s * (vn - v)) / v0);
        }
        (t, x, v) = (t + dt, xn, vn);
    }
}

#[test]
fn all_damping_regimes_agree_with_the_table_and_with_rk4() {
    let (k, m) = (2000.0f64, 0.5f64);
    let w0 = (k / m).sqrt();
    // β/ω0: under-damped (two sub-regimes), the boundary 1/√2, between, critical, over.
    for ratio in [0.0f64, 0.05, 0.3, 1.0 / 2f64.sqrt(), 0.85, 1.0, 1.7, 6.0] {
        let gamma = 2.0 * m * w0 * ratio;
        let got = LinearDashpot::new(k, gamma)
            .unwrap()
            .central_impact(m)
            .unwrap();
        if ratio != 1.0 {
            let (tc, eps) = table(k, gamma, m);
            assert!(
                (got.duration / tc - 1.0).abs() < 1e-12,
                "β/ω0 = {ratio}: {} vs {tc}",
                got.duration
            );
            assert!(
                (got.restitution / eps - 1.0).abs() < 1e-12,
                "β/ω0 = {ratio}"
            );
        }
        let (tc, eps) = integrate(k, gamma, m, got.duration);
        assert!(
            (got.duration / tc - 1.0).abs() < 1e-7,
            "β/ω0 = {ratio}: {} vs RK4 {tc}",
            got.duration
        );
        assert!(
            (got.restitution - eps).abs() < 1e-7,
            "β/ω0 = {ratio}: {} vs RK4 {eps}",
            got.restitution
        );
    }
}

#[test]
fn elastic_limit() {
    let got = LinearDashpot::new(1.0, 0.0)
        .unwrap()
        .central_impact(1.0)
        .unwrap();
    assert!((got.duration - PI).abs() < 1e-15);
    assert_eq!(got.restitution, 1.0);
}
