//! The exact frictional contact of a sphere with a flat wall (`solve_wall_contact`,
//! `rule::frictional_wall_collision`) against independent references: the reference
//! pair solver with a partner 10⁷ times larger and 10²⁰ times heavier that does not
//! spin; without friction, the frictionless MoR of the central impact (`resolve_wall`);
//! a sphere that rolls (no slip) keeps its tangential velocity and spin; and the
//! sticking elastic limit, a tangential oscillator of mass m/(1 + mR²/I) over the
//! contact time π√(m/k) of a stiff linear spring.

use emdstar_contact::vec3::{add_scaled, cross, dot, from_na, norm, scale, sub, to_na};
use emdstar_contact::{
    Impact, PairLaw, PairProperties, SOLID_SPHERE_INERTIA, scale as scale_impact,
};
use emdstar_mor::frictional::{
    CONTACT_OPTIONS, HistorySpring, Spinning, solve_frictional, solve_wall_contact,
};
use emdstar_mor::rule::{Body, frictional_wall_collision, resolve_wall};
use emdstar_mor::{SolverOptions, solve};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const RADIUS: f64 = 0.01;
const MASS: f64 = 4.775e-3;

fn unit(rng: &mut ChaCha8Rng) -> [f64; 3] {
    loop {
        let x: [f64; 3] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let n = norm(x);
        if n > 0.1 && n <= 1.0 {
            return scale(1.0 / n, x);
        }
    }
}

fn hertz(damped: bool) -> PairLaw {
    // Y = 1 GPa, ν = 0.4 against a rigid wall: E* = Y/(1 − ν²), R_eff = R.
    let e_star = 1e9 / (1.0 - 0.16);
    PairLaw::Hertz {
        rho_el: 4.0 / 3.0 * e_star * RADIUS.sqrt(),
        dissipation: if damped { 1e-5 } else { 0.0 },
    }
}

fn linear(damped: bool) -> PairLaw {
    PairLaw::Linear {
        stiffness: 1e4,
        damping: if damped { 0.2 } else { 0.0 },
    }
}

/// A sphere touching the wall of normal `n` and moving against it.
fn approach(rng: &mut ChaCha8Rng, n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let side = {
        let a = unit(rng);
        let t = add_scaled(a, -dot(a, n), n);
        scale(1.0 / norm(t), t)
    };
    let e: f64 = rng.random_range(0.0..0.9);
    let speed = rng.random_range(0.5..2.0);
    let v = scale(speed, add_scaled(scale(e, side), -(1.0 - e * e).sqrt(), n));
    let spin = scale(rng.random_range(0.0..2.0) * speed / RADIUS, unit(rng));
    (v, spin)
}

#[test]
fn a_wall_is_a_huge_heavy_partner_that_does_not_spin() {
    let mut rng = ChaCha8Rng::seed_from_u64(51);
    let mut worst: f64 = 0.0;
    for k in 0..24 {
        let n = unit(&mut rng);
        let (v, spin) = approach(&mut rng, n);
        let law = if k % 2 == 0 {
            hertz(k % 4 == 0)
        } else {
            linear(k % 4 == 1)
        };
        let spring = HistorySpring {
            friction: [0.1, 0.3, 1.0][k % 3],
            stiffness: if k % 2 == 0 { 2e5 } else { 3e3 },
            damping: if k % 5 == 0 { 0.05 } else { 0.0 },
        };
        let sphere = Spinning {
            radius: RADIUS,
            mass: MASS,
            spin,
        };
        let wall = solve_wall_contact(&law, &spring, &sphere, n, v, &CONTACT_OPTIONS)
            .unwrap_or_else(|e| panic!("{k}: {e}"));
        // The partner: radius 10⁷ R, mass 10²⁰ m, at rest and without spin; the normal
        // law is the pair's as given (ρ_el already holds R_eff = R).
        let big = Spinning {
            radius: 1e7 * RADIUS,
            mass: 1e20 * MASS,
            spin: [0.0; 3],
        };
        let touch = scale(RADIUS + big.radius, n);
        let opts = SolverOptions {
            rtol: 1e-12,
            atol: 1e-12,
            max_steps: 1_000_000,
        };
        let pair = solve_frictional(&law, &spring, &[sphere, big], touch, v, &opts).unwrap();
        let speed = norm(v);
        // The sphere's way from touch, its velocity and spin.
        let moved_wall = sub(wall.separation, scale(RADIUS, n));
        let moved_pair = sub(pair.separation, touch);
        let d = (norm(sub(moved_wall, moved_pair)) / RADIUS)
            .max(norm(sub(wall.velocity, pair.velocity)) / speed)
            .max(norm(sub(wall.spins[0], pair.spins[0])) * RADIUS / speed)
            .max((wall.duration - pair.duration).abs() * speed / RADIUS);
        assert!(d < 1e-7, "{k}: {d:e}");
        assert_eq!(wall.spins[1], [0.0; 3]);
        worst = worst.max(d);
    }
    eprintln!("wall against the huge partner: worst {worst:.2e}");
}

#[test]
fn without_friction_it_is_the_frictionless_wall_rule() {
    let mut rng = ChaCha8Rng::seed_from_u64(52);
    for k in 0..8 {
        let n = unit(&mut rng);
        let (v, spin) = approach(&mut rng, n);
        let law = if k % 2 == 0 {
            hertz(k % 4 == 0)
        } else {
            linear(k % 4 == 1)
        };
        let spring = HistorySpring {
            friction: 0.0,
            stiffness: 1e4,
            damping: 0.0,
        };
        // `resolve_wall`'s plane passes through the origin.
        let along = unit(&mut rng);
        let in_plane = add_scaled(along, -dot(along, n), n);
        let body = Body {
            position: to_na(add_scaled(scale(0.5, in_plane), RADIUS, n)),
            velocity: to_na(v),
            mass: MASS,
        };
        let normal = to_na(n);
        let (out, spin_after) = frictional_wall_collision(
            &law,
            &spring,
            &body,
            RADIUS,
            spin,
            &normal,
            &CONTACT_OPTIONS,
        )
        .unwrap();
        assert_eq!(spin_after, spin, "µ = 0 keeps the spin");
        // The central impact along n: the normal speed alone (c_φ = 0).
        let pair = PairProperties {
            l: RADIUS,
            m_eff: MASS,
            r_eff: RADIUS,
        };
        let impact = Impact::from_relative(&(normal * RADIUS), &(normal * dot(v, n))).unwrap();
        let scaled = scale_impact(&law, &pair, &impact).unwrap();
        let mor = solve(law.model(), &scaled.params).unwrap();
        let exact = resolve_wall(&body, &normal, RADIUS, &mor, scaled.time);
        let speed = norm(v);
        let of = |b: &Body| (from_na(&b.position), from_na(&b.velocity));
        let (x, u) = of(&out.after[0]);
        let (x0, u0) = of(&exact.after[0]);
        assert!(
            norm(sub(x, x0)) < 1e-8 * RADIUS,
            "{k}: position {x:?} {x0:?}"
        );
        assert!(
            norm(sub(u, u0)) < 1e-8 * speed,
            "{k}: velocity {u:?} {u0:?}"
        );
        assert!((out.duration - exact.duration).abs() < 1e-8 * exact.duration);
        // The E^φ state: above the touched point at the end's height, moving along.
        let rotated = from_na(&out.rotated_positions[0]);
        let transient = from_na(&out.transient_velocity);
        let arrives = add_scaled(rotated, out.duration, transient);
        assert!(norm(sub(arrives, x)) < 1e-12);
        assert!(dot(transient, n).abs() < 1e-9 * speed);
        assert!(norm(sub(rotated, from_na(&exact.rotated_positions[0]))) < 1e-8 * RADIUS);
    }
}

#[test]
fn a_rolling_sphere_keeps_its_tangential_velocity_and_spin() {
    let mut rng = ChaCha8Rng::seed_from_u64(53);
    for k in 0..6 {
        let n = unit(&mut rng);
        let (v, _) = approach(&mut rng, n);
        // R ω × n = v_t: no slip.
        let v_t = add_scaled(v, -dot(v, n), n);
        let spin = scale(1.0 / RADIUS, cross(n, v_t));
        let law = if k % 2 == 0 {
            hertz(true)
        } else {
            linear(true)
        };
        let spring = HistorySpring {
            friction: 0.5,
            stiffness: 1e4,
            damping: 0.1,
        };
        let sphere = Spinning {
            radius: RADIUS,
            mass: MASS,
            spin,
        };
        let end = solve_wall_contact(&law, &spring, &sphere, n, v, &CONTACT_OPTIONS).unwrap();
        let speed = norm(v);
        let after_t = add_scaled(end.velocity, -dot(end.velocity, n), n);
        assert!(norm(sub(after_t, v_t)) < 1e-9 * speed, "{k}");
        assert!(norm(sub(end.spins[0], spin)) * RADIUS < 1e-9 * speed, "{k}");
    }
}

#[test]
fn a_sticking_elastic_contact_is_a_tangential_oscillator() {
    // A stiff undamped linear spring (ξ/R ≈ 7e-5: the lever arm is R), µ so large that
    // the contact never slides: the slip s obeys s'' = −k_t s/m_t, 1/m_t = 1/m + R²/I,
    // over τ = π√(m/k), and keeps its direction (the wall's normal does not turn).
    let k = 1e10;
    let law = PairLaw::Linear {
        stiffness: k,
        damping: 0.0,
    };
    let inertia = SOLID_SPHERE_INERTIA * MASS * RADIUS * RADIUS;
    let m_t = 1.0 / (1.0 / MASS + RADIUS * RADIUS / inertia);
    let tau = std::f64::consts::PI * (MASS / k).sqrt();
    let mut rng = ChaCha8Rng::seed_from_u64(54);
    for j in 0..6 {
        let n = unit(&mut rng);
        let (v, spin) = approach(&mut rng, n);
        // Tangential periods over the contact: 0.3 to 1.3.
        let periods = 0.3 + 0.2 * j as f64;
        let omega_t = periods * std::f64::consts::TAU / tau;
        let spring = HistorySpring {
            friction: 1e6,
            stiffness: omega_t * omega_t * m_t,
            damping: 0.0,
        };
        let sphere = Spinning {
            radius: RADIUS,
            mass: MASS,
            spin,
        };
        let end = solve_wall_contact(&law, &spring, &sphere, n, v, &CONTACT_OPTIONS).unwrap();
        // It sticks until F_n has all but vanished (the cap µF_n falls below the spring
        // only there).
        assert!(end.switches <= 1, "{} switches", end.switches);
        let slip = |u: [f64; 3], w: [f64; 3]| {
            sub(add_scaled(u, -dot(u, n), n), scale(RADIUS, cross(w, n)))
        };
        let before = slip(v, spin);
        let after = slip(end.velocity, end.spins[0]);
        let expected = scale((omega_t * tau).cos(), before);
        let d = norm(sub(after, expected)) / norm(v);
        assert!(d < 5e-5, "{periods} periods: {d:e}");
        assert!((end.duration - tau).abs() < 1e-8 * tau);
    }
}
