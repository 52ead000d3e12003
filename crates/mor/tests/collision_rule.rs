//! The eMD* rule with the exact MoR against an independent integration of Newton's
//! equations for two spheres in three dimensions, in physical units.
//!
//! The reference integrates both bodies' positions and velocities with `ode_solvers`'
//! DOP853 (an independent implementation) under the clipped normal force, well past
//! the end of the contact; the rule's state at t* + τ is moved on ballistically to the
//! same time and compared. Errors are normalised by l and |v_rel|.

use emdstar_contact::{
    ForceLaw, LinearDashpot, PairLaw, PairProperties, Sphere, Vec3, ViscoelasticHertz,
};
use emdstar_mor::rule::{Body, exact_collision};
use ode_solvers::{Dop853, OutputType, SVector, System};

type State = SVector<f64, 12>;

struct TwoSpheres {
    law: PairLaw,
    l: f64,
    m1: f64,
    m2: f64,
}

impl System<f64, State> for TwoSpheres {
    fn system(&self, _t: f64, y: &State, dy: &mut State) {
        let r = [y[0] - y[6], y[1] - y[7], y[2] - y[8]];
        let v = [y[3] - y[9], y[4] - y[10], y[5] - y[11]];
        let dist = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let n = r.map(|x| x / dist);
        let rdot = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
        // Overlap ξ = l − |r|, ξ̇ = −ṙ; the force pushes particle 1 along +n.
        let f = self.law.normal_force(self.l - dist, -rdot);
        for k in 0..3 {
            dy[k] = y[3 + k];
            dy[6 + k] = y[9 + k];
            dy[3 + k] = f * n[k] / self.m1;
            dy[9 + k] = -f * n[k] / self.m2;
        }
    }
}

/// Runs one impact both ways and returns (position error / l, velocity error / |v|).
fn compare(law_of: &ForceLaw, s1: Sphere, s2: Sphere, bodies: [Body; 2]) -> (f64, f64) {
    let pair = PairProperties::spheres(&s1, &s2);
    let law = PairLaw::same_material(law_of, pair.r_eff).unwrap();
    let (out, _mor) = exact_collision(&law, &pair, &bodies).unwrap();
    let t_end = 1.5 * out.duration;

    let mut y0 = State::zeros();
    for (i, b) in bodies.iter().enumerate() {
        for k in 0..3 {
            y0[6 * i + k] = b.position[k];
            y0[6 * i + 3 + k] = b.velocity[k];
        }
    }
    let system = TwoSpheres {
        law,
        l: pair.l,
        m1: s1.mass,
        m2: s2.mass,
    };
    // Steps no longer than 1/40 of the contact, so that the first step cannot jump over
    // the contact (the force is zero at the first touch); output at the steps only.
    let h_max = out.duration / 40.0;
    let mut stepper = Dop853::from_param(
        system,
        0.0,
        t_end,
        t_end,
        y0,
        1e-13,
        1e-15,
        0.9,
        0.0,
        0.333,
        6.0,
        h_max,
        h_max / 100.0,
        1_000_000,
        1000,
        OutputType::Sparse,
    );
    stepper.integrate().expect("reference integration");
    assert_eq!(*stepper.x_out().last().unwrap(), t_end);
    let y = *stepper.y_out().last().unwrap();

    let v_rel = (bodies[0].velocity - bodies[1].velocity).norm();
    let (mut dx, mut dv) = (0.0f64, 0.0f64);
    for (i, b) in out.after.iter().enumerate() {
        let x = b.position + b.velocity * (t_end - out.duration);
        for k in 0..3 {
            dx = dx.max((x[k] - y[6 * i + k]).abs() / pair.l);
            dv = dv.max((b.velocity[k] - y[6 * i + 3 + k]).abs() / v_rel);
        }
    }
    eprintln!("position error / l = {dx:.2e}, velocity error / |v| = {dv:.2e}");
    (dx, dv)
}

/// Bodies at first touch: distance l along a tilted axis, relative speed `v` with
/// eccentricity `e`, and a drifting centre of mass.
fn touching(s1: &Sphere, s2: &Sphere, v: f64, e: f64) -> [Body; 2] {
    let l = s1.radius + s2.radius;
    let n = Vec3::new(0.6, -0.3, 0.2).normalize();
    let t = n.cross(&Vec3::new(0.1, 0.4, 1.0)).normalize();
    let v_rel = (-n * (1.0 - e * e).sqrt() + t * e) * v;
    let drift = Vec3::new(0.2, 0.1, -0.3);
    let total = s1.mass + s2.mass;
    let x1 = Vec3::new(1.0, -2.0, 0.5);
    [
        Body {
            position: x1,
            velocity: drift + v_rel * (s2.mass / total),
            mass: s1.mass,
        },
        Body {
            position: x1 - n * l,
            velocity: drift - v_rel * (s1.mass / total),
            mass: s2.mass,
        },
    ]
}

const TOLERANCE: f64 = 1e-8;

#[test]
fn paper_fig6_linear_elastic() {
    // Müller & Pöschel 2013, Fig. 6: k = 2 kN/m, R = 0.1 m, ρ = 1140 kg/m³, v = 5 m/s,
    // e = 0.3, γ = 0, v₁ = (v/4, v/2, 0), v₂ = (v/4, −v/2, 0).
    let s = Sphere::from_density(0.1, 1140.0).unwrap();
    let v = 5.0;
    let e: f64 = 0.3;
    let dir = Vec3::new(e, -(1.0 - e * e).sqrt(), 0.0);
    let bodies = [
        Body {
            position: dir * 0.2,
            velocity: Vec3::new(v / 4.0, v / 2.0, 0.0),
            mass: s.mass,
        },
        Body {
            position: Vec3::zeros(),
            velocity: Vec3::new(v / 4.0, -v / 2.0, 0.0),
            mass: s.mass,
        },
    ];
    let law = ForceLaw::Linear(LinearDashpot::new(2000.0, 0.0).unwrap());
    let (dx, dv) = compare(&law, s, s, bodies);
    assert!(dx < TOLERANCE && dv < TOLERANCE, "dx = {dx:e}, dv = {dv:e}");
}

#[test]
fn linear_dashpot_oblique_equal_and_unequal() {
    let law = ForceLaw::Linear(LinearDashpot::new(5000.0, 2.0).unwrap());
    let big = Sphere::from_density(0.05, 2500.0).unwrap();
    let small = Sphere::from_density(0.02, 7800.0).unwrap();
    for (s1, s2) in [(big, big), (big, small)] {
        for e in [0.0, 0.2, 0.7, 0.95] {
            let (dx, dv) = compare(&law, s1, s2, touching(&s1, &s2, 3.0, e));
            assert!(
                dx < TOLERANCE && dv < TOLERANCE,
                "e = {e}: dx = {dx:e}, dv = {dv:e}"
            );
        }
    }
}

#[test]
fn viscoelastic_hertz_oblique_equal_and_unequal() {
    // Soft rubber-like spheres so that the contact rotates the normal visibly.
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e7, 0.45, 2e-4).unwrap());
    let big = Sphere::from_density(0.05, 1100.0).unwrap();
    let small = Sphere::from_density(0.02, 3000.0).unwrap();
    for (s1, s2) in [(big, big), (small, big)] {
        for e in [0.0, 0.3, 0.8, 0.98] {
            let (dx, dv) = compare(&law, s1, s2, touching(&s1, &s2, 2.0, e));
            assert!(
                dx < TOLERANCE && dv < TOLERANCE,
                "e = {e}: dx = {dx:e}, dv = {dv:e}"
            );
        }
    }
}

#[test]
fn viscoelastic_hertz_elastic() {
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e8, 0.3, 0.0).unwrap());
    let s = Sphere::from_density(0.1, 1140.0).unwrap();
    let (dx, dv) = compare(&law, s, s, touching(&s, &s, 2.0, 0.6));
    assert!(dx < TOLERANCE && dv < TOLERANCE, "dx = {dx:e}, dv = {dv:e}");
}
