//! An independent oracle: `ode_solvers`' DOP853 integrating the two-body problem in
//! Cartesian coordinates of the collision plane, r⃗ = (l̃ + X, Y), with Newton's law
//! r⃗'' = F·r̂ (the centrifugal term arises by itself), F = g(ξ)·(ξ + c_dis·u).
//!
//! X and Y are offsets from the contact point, so the overlap keeps its digits:
//! ξ = l̃ − r = −(2l̃X + X² + Y²)/(l̃ + r). The oracle runs to the solver's τ̃ and is then
//! carried to its own end (F = 0) by one Newton step Δ = −h/h'; the solver's MoR is
//! compared with the oracle's state there.

use crate::common::*;
use emdstar_contact::{Model, ScaledParams};
use emdstar_mor::{Mor, solve};
use ode_solvers::{Dop853, System, Vector3, Vector5};

struct Cartesian {
    model: Model,
    p: ScaledParams,
    /// Unit of time and length of the state (the solver's τ̃), so that it is O(1).
    unit: f64,
}

/// (ξ, u, r) of a state in physical scaled units.
fn overlap(p: &ScaledParams, unit: f64, y: &Vector5<f64>) -> (f64, f64, f64) {
    let (x, yy) = (y[0] * unit, y[1] * unit);
    let (rx, ry) = (p.l_tilde + x, yy);
    let r = rx.hypot(ry);
    let xi = -(2.0 * p.l_tilde * x + x * x + yy * yy) / (p.l_tilde + r);
    let u = -(rx * y[2] + ry * y[3]) / r;
    (xi, u, r)
}

impl Cartesian {
    /// Scaled normal force F = g(ξ)·h and h.
    fn force(&self, xi: f64, u: f64) -> (f64, f64) {
        let h = xi + self.p.c_dis * u;
        let g = match self.model {
            Model::Linear => 1.0,
            Model::Hertz => xi.max(0.0).sqrt(),
        };
        (g * h, h)
    }
}

impl System<f64, Vector5<f64>> for Cartesian {
    fn system(&self, _t: f64, y: &Vector5<f64>, dy: &mut Vector5<f64>) {
        let (xi, u, r) = overlap(&self.p, self.unit, y);
        let (f, _) = self.force(xi, u);
        let (rx, ry) = (self.p.l_tilde + y[0] * self.unit, y[1] * self.unit);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = self.unit * f * rx / r;
        dy[3] = self.unit * f * ry / r;
        dy[4] = self.unit * (rx * y[3] - ry * y[2]) / (r * r);
    }
}

/// Relative differences (1−ε_r, ε_ṙ, ε_φ, ε_t) between the solver and the oracle.
pub fn oracle_errors(model: Model, p: &ScaledParams, m: &Mor) -> [f64; 4] {
    let unit = m.eps_t;
    let sys = Cartesian { model, p: *p, unit };
    let y0 = Vector5::new(0.0, 0.0, -1.0, p.c_phi / p.l_tilde, 0.0);
    let mut ode = Dop853::new(sys, 0.0, 1.0, 0.0, y0, 1e-13, 1e-15);
    ode.integrate().expect("oracle integrates");
    let y = *ode.y_out().last().unwrap();
    let sys = Cartesian { model, p: *p, unit };
    let (xi, u, r) = overlap(p, unit, &y);
    let (_, h) = sys.force(xi, u);
    let centrifugal = (p.c_phi / r).powi(2) / r;
    let g = match model {
        Model::Linear => 1.0,
        Model::Hertz => xi.max(0.0).sqrt(),
    };
    // u' = −c_φ²/r³ − g·h; h' = u + c_dis·u' (for c_dis = 0 the end is ξ = 0, h = ξ).
    let du = -centrifugal - g * h;
    let dh = u + p.c_dis * du;
    let delta = -h / dh;
    let xi_end = if p.c_dis == 0.0 { 0.0 } else { xi + u * delta };
    let u_end = u + du * delta;
    let phi_end = y[4] + p.c_phi / (r * r) * delta;
    [
        rel(m.one_minus_eps_r * p.l_tilde, xi_end),
        rel(m.eps_rdot, u_end),
        rel(m.eps_phi, phi_end),
        (delta / m.eps_t).abs(),
    ]
}

/// The second oracle: `ode_solvers`' DOP853 on the overlap form (ξ, u, φ) in plain time t,
/// without the solver's regularisation of the Hertz law, with pure relative error control
/// (so it resolves u down to the ~Ξ/c_dis it reaches in the stiff corner). It runs to the
/// solver's τ̃ and is carried to its own end by one Newton step, as above.
struct OverlapForm {
    model: Model,
    p: ScaledParams,
}

impl OverlapForm {
    fn derivative(&self, y: &Vector3<f64>) -> (f64, [f64; 3]) {
        let (xi, u) = (y[0], y[1]);
        let h = xi + self.p.c_dis * u;
        let g = match self.model {
            Model::Linear => 1.0,
            Model::Hertz => xi.max(0.0).sqrt(),
        };
        let r = self.p.l_tilde - xi;
        let phi_dot = self.p.c_phi / (r * r);
        (h, [u, -phi_dot * self.p.c_phi / r - g * h, phi_dot])
    }
}

impl System<f64, Vector3<f64>> for OverlapForm {
    fn system(&self, _t: f64, y: &Vector3<f64>, dy: &mut Vector3<f64>) {
        let (_, d) = self.derivative(y);
        dy.copy_from_slice(&d);
    }
}

pub fn overlap_form_errors(model: Model, p: &ScaledParams, m: &Mor) -> [f64; 4] {
    let sys = OverlapForm { model, p: *p };
    let y0 = Vector3::new(0.0, 1.0, 0.0);
    let mut ode = Dop853::from_param(
        sys,
        0.0,
        m.eps_t,
        0.0,
        y0,
        1e-13,
        1e-300,
        0.9,
        0.0,
        0.333,
        6.0,
        m.eps_t,
        1e-5 * m.eps_t,
        1_000_000,
        1_000_000,
        ode_solvers::OutputType::Dense,
    );
    ode.integrate().expect("oracle integrates");
    let y = *ode.y_out().last().unwrap();
    let (h, d) = OverlapForm { model, p: *p }.derivative(&y);
    let dh = d[0] + p.c_dis * d[1];
    let delta = -h / dh;
    let xi_end = if p.c_dis == 0.0 {
        0.0
    } else {
        y[0] + d[0] * delta
    };
    [
        rel(m.one_minus_eps_r * p.l_tilde, xi_end),
        rel(m.eps_rdot, y[1] + d[1] * delta),
        rel(m.eps_phi, y[2] + d[2] * delta),
        (delta / m.eps_t).abs(),
    ]
}

/// What the Cartesian oracle can resolve in τ̃ (and ε_φ): its u is a difference of
/// velocity components of size √(1+s²), s = c_φ/l̃, known to ~1e-13 of that, and an error δh
/// = c_dis·δu of the bracket moves its end by δh/|h'|, h' = u + c_dis·u' = ε_ṙ − c_dis·c_φ²/r³.
pub fn cartesian_time_resolution(p: &ScaledParams, m: &Mor) -> f64 {
    let s = p.c_phi / p.l_tilde;
    let r = p.l_tilde * m.eps_r;
    let slope = m.eps_rdot.abs() + p.c_dis * (p.c_phi / r).powi(2) / r;
    1e-12 * p.c_dis * (1.0 + s * s).sqrt() / (slope * m.eps_t)
}

#[test]
fn solver_agrees_with_both_oracles_on_both_rectangles() {
    const GOAL: f64 = 1e-9;
    for model in [Model::Linear, Model::Hertz] {
        let mut points = corners(model);
        points.extend(uniform_in_rect(model, 300, 11));
        for p in &points {
            let m = solve(model, p).unwrap();
            let o = overlap_form_errors(model, p, &m);
            assert!(
                o.iter().all(|&e| e <= GOAL),
                "{model} {p:?}: overlap-form oracle {o:?}"
            );
            let c = oracle_errors(model, p, &m);
            let t_res = cartesian_time_resolution(p, &m);
            assert!(
                c[0] <= GOAL && c[1] <= GOAL && c[2] <= GOAL + t_res && c[3] <= GOAL + t_res,
                "{model} {p:?}: Cartesian oracle {c:?} (time resolution {t_res:e})"
            );
        }
    }
}
