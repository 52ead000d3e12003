//! The fast frictional contact solver (`solve_contact`, the carried frame) against the
//! reference solver (`solve_frictional`, the world frame, both spins, tight tolerance):
//! two formulations of the same equations that share no code but the force laws.

use emdstar_contact::vec3::{add_scaled, cross, dot, norm, scale, sub};
use emdstar_contact::{PairLaw, SOLID_SPHERE_INERTIA, Sphere};
use emdstar_mor::SolverOptions;
use emdstar_mor::frictional::{
    CONTACT_OPTIONS, FrictionalEnd, HistorySpring, Spinning, solve_contact, solve_frictional,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const DENSITY: f64 = 1140.0;

fn unit(rng: &mut ChaCha8Rng) -> [f64; 3] {
    loop {
        let x: [f64; 3] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let n = norm(x);
        if n > 0.1 && n <= 1.0 {
            return scale(1.0 / n, x);
        }
    }
}

/// A random impact as validate's frictional impacts draw them: linear or Hertz, damped
/// or not, µ log-uniform in [0.05, 1], a damped or undamped spring, spins up to
/// 3|v|/R (none in one impact of four: a planar contact), equal or unequal radii.
struct Case {
    law: PairLaw,
    spring: HistorySpring,
    bodies: [Spinning; 2],
    r: [f64; 3],
    v: [f64; 3],
}

fn case(rng: &mut ChaCha8Rng, k: usize) -> Case {
    let hertz = k % 2 == 1;
    let radii = [
        0.1,
        if k % 4 >= 2 {
            rng.random_range(0.05..0.2)
        } else {
            0.1
        },
    ];
    let masses = radii.map(|r| Sphere::from_density(r, DENSITY).unwrap().mass);
    let m_eff = masses[0] * masses[1] / (masses[0] + masses[1]);
    let r_eff = radii[0] * radii[1] / (radii[0] + radii[1]);
    let damped = rng.random_range(0.0..1.0) < 0.7;
    let (law, k_n) = if hertz {
        let e_star = 1e7 / (2.0 * (1.0 - 0.09));
        let rho_el = 4.0 / 3.0 * e_star * r_eff.sqrt();
        let peak = (1.25 * m_eff / rho_el).powf(0.4);
        let dissipation = if damped { 2e-4 } else { 0.0 };
        let law = PairLaw::Hertz {
            rho_el,
            dissipation,
        };
        (law, 1.5 * rho_el * peak.sqrt())
    } else {
        let damping = if damped { 2.0 } else { 0.0 };
        let law = PairLaw::Linear {
            stiffness: 2000.0,
            damping,
        };
        (law, 2000.0)
    };
    let k_t = 2.0 / 7.0 * k_n * rng.random_range(0.5..1.5);
    let spring = HistorySpring {
        friction: 0.05 * 20f64.powf(rng.random_range(0.0..1.0)),
        stiffness: k_t,
        damping: if rng.random_range(0.0..1.0) < 0.5 {
            0.0
        } else {
            0.2 * (k_t * m_eff).sqrt()
        },
    };
    let speed: f64 = rng.random_range(0.5..3.0);
    let spinning = k % 4 != 3;
    let bodies = [0, 1].map(|i| Spinning {
        radius: radii[i],
        mass: masses[i],
        spin: if spinning {
            scale(rng.random_range(0.0..3.0) * speed / radii[i], unit(rng))
        } else {
            [0.0; 3]
        },
    });
    let n = unit(rng);
    let e: f64 = rng.random_range(0.0..0.9);
    let side = {
        let a = unit(rng);
        let t = add_scaled(a, -dot(a, n), n);
        scale(1.0 / norm(t), t)
    };
    let v = scale(speed, add_scaled(scale(e, side), -(1.0 - e * e).sqrt(), n));
    Case {
        law,
        spring,
        bodies,
        r: scale(radii[0] + radii[1], n),
        v,
    }
}

fn reference(c: &Case) -> FrictionalEnd {
    let opts = SolverOptions {
        rtol: 1e-12,
        atol: 1e-12,
        max_steps: 1_000_000,
    };
    solve_frictional(&c.law, &c.spring, &c.bodies, c.r, c.v, &opts).unwrap()
}

/// Positions in units of l, velocities and spins (times R) in units of |v|.
fn distance(c: &Case, a: &FrictionalEnd, b: &FrictionalEnd) -> f64 {
    let l = c.bodies[0].radius + c.bodies[1].radius;
    let speed = norm(c.v);
    let spin = (0..2)
        .map(|i| norm(sub(a.spins[i], b.spins[i])) * c.bodies[i].radius / speed)
        .fold(0.0, f64::max);
    (norm(sub(a.separation, b.separation)) / l)
        .max(norm(sub(a.velocity, b.velocity)) / speed)
        .max(spin)
        .max((a.duration - b.duration).abs() * speed / l)
}

#[test]
fn the_fast_solver_is_the_reference_to_its_accuracy() {
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let mut worst: f64 = 0.0;
    for k in 0..96 {
        let c = case(&mut rng, k);
        let fast = solve_contact(&c.law, &c.spring, &c.bodies, c.r, c.v, &CONTACT_OPTIONS)
            .unwrap_or_else(|e| panic!("impact {k}: {e}"));
        let d = distance(&c, &fast, &reference(&c));
        assert!(d < 1e-7, "impact {k}: {d:e}");
        worst = worst.max(d);
    }
    // The accuracy asked (1e-9 per step) shows in the worst outcome.
    assert!(worst < 3e-8, "worst {worst:e}");
}

#[test]
fn the_total_angular_momentum_is_kept() {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    for k in 0..24 {
        let c = case(&mut rng, k);
        let end = solve_contact(&c.law, &c.spring, &c.bodies, c.r, c.v, &CONTACT_OPTIONS).unwrap();
        let m_eff = c.bodies[0].mass * c.bodies[1].mass / (c.bodies[0].mass + c.bodies[1].mass);
        let total = |r: [f64; 3], v: [f64; 3], w: [[f64; 3]; 2]| {
            let mut l = scale(m_eff, cross(r, v));
            for (i, b) in c.bodies.iter().enumerate() {
                l = add_scaled(l, SOLID_SPHERE_INERTIA * b.mass * b.radius * b.radius, w[i]);
            }
            l
        };
        let before = total(c.r, c.v, [c.bodies[0].spin, c.bodies[1].spin]);
        let after = total(end.separation, end.velocity, end.spins);
        let size = m_eff * norm(c.r) * norm(c.v);
        let drift = norm(sub(after, before)) / size;
        assert!(drift < 1e-8, "impact {k}: ΔL/L = {drift:e}");
    }
}

#[test]
fn without_friction_the_spins_are_untouched_and_the_contact_is_the_references() {
    let mut rng = ChaCha8Rng::seed_from_u64(43);
    for k in 0..8 {
        let mut c = case(&mut rng, k);
        c.spring.friction = 0.0;
        let end = solve_contact(&c.law, &c.spring, &c.bodies, c.r, c.v, &CONTACT_OPTIONS).unwrap();
        for i in 0..2 {
            assert_eq!(end.spins[i], c.bodies[i].spin);
        }
        assert!(distance(&c, &end, &reference(&c)) < 1e-8);
    }
}

#[test]
fn a_central_impact_without_spin_is_solved_with_and_without_friction() {
    // No slip at all: the tail of a frictionless contact has no direction to take.
    let mut rng = ChaCha8Rng::seed_from_u64(45);
    for k in 0..4 {
        let mut c = case(&mut rng, k);
        c.v = scale(-norm(c.v) / norm(c.r), c.r);
        for body in &mut c.bodies {
            body.spin = [0.0; 3];
        }
        for friction in [0.0, 0.3] {
            c.spring.friction = friction;
            let end =
                solve_contact(&c.law, &c.spring, &c.bodies, c.r, c.v, &CONTACT_OPTIONS).unwrap();
            assert!(
                distance(&c, &end, &reference(&c)) < 1e-8,
                "impact {k}, µ = {friction}"
            );
            // Nothing turns the pair: the spheres leave along the line of centres.
            assert!(norm(cross(end.velocity, c.r)) <= 1e-12 * norm(c.v) * norm(c.r));
        }
    }
}

#[test]
fn bad_springs_and_non_touching_bodies_are_errors() {
    let mut rng = ChaCha8Rng::seed_from_u64(44);
    let c = case(&mut rng, 0);
    let mut soft = c.spring;
    soft.stiffness = 0.0;
    assert!(solve_contact(&c.law, &soft, &c.bodies, c.r, c.v, &CONTACT_OPTIONS).is_err());
    let mut negative = c.spring;
    negative.friction = -0.1;
    assert!(solve_contact(&c.law, &negative, &c.bodies, c.r, c.v, &CONTACT_OPTIONS).is_err());
    let receding = scale(-1.0, c.v);
    assert!(
        solve_contact(
            &c.law,
            &c.spring,
            &c.bodies,
            c.r,
            receding,
            &CONTACT_OPTIONS
        )
        .is_err()
    );
    let apart = scale(1.1, c.r);
    assert!(solve_contact(&c.law, &c.spring, &c.bodies, apart, c.v, &CONTACT_OPTIONS).is_err());
}
