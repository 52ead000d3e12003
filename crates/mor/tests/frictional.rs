//! The exact frictional contact against independent references: the frictionless
//! solver for µ = 0, conservation of linear and angular momentum (about the centre of
//! mass, spins included) and no energy created.

use emdstar_contact::vec3::{add, add_scaled, cross, dot, norm, scale, sub};
use emdstar_contact::{
    HistorySpring, Impact, PairLaw, PairProperties, SOLID_SPHERE_INERTIA, Sphere, Vec3,
    scale as scale_impact,
};
use emdstar_mor::frictional::{FrictionalEnd, Spinning, solve_frictional};
use emdstar_mor::{SolverOptions, solve};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const DENSITY: f64 = 1140.0;

fn linear(damping: f64) -> PairLaw {
    PairLaw::Linear {
        stiffness: 2000.0,
        damping,
    }
}

fn hertz(dissipation: f64, r_eff: f64) -> PairLaw {
    // Y = 1e7 Pa, ν = 0.3 for both: E* = Y/(2(1 − ν²)).
    let e_star = 1e7 / (2.0 * (1.0 - 0.09));
    PairLaw::Hertz {
        rho_el: 4.0 / 3.0 * e_star * r_eff.sqrt(),
        dissipation,
    }
}

fn history(mu: f64, k_t: f64, gamma_t: f64) -> HistorySpring {
    HistorySpring::new(mu, k_t, gamma_t).unwrap()
}

/// A random oblique impact: radii, spins, r at touch and an approaching v.
struct Impactor {
    bodies: [Spinning; 2],
    r: [f64; 3],
    v: [f64; 3],
}

fn unit(rng: &mut ChaCha8Rng) -> [f64; 3] {
    loop {
        let x: [f64; 3] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let n = norm(x);
        if n > 0.1 && n <= 1.0 {
            return scale(1.0 / n, x);
        }
    }
}

fn impactor(rng: &mut ChaCha8Rng, unequal: bool) -> Impactor {
    let r1 = 0.1;
    let r2 = if unequal {
        rng.random_range(0.05..0.2)
    } else {
        0.1
    };
    let bodies = [r1, r2].map(|radius| {
        let mass = Sphere::from_density(radius, DENSITY).unwrap().mass;
        let spin = scale(rng.random_range(0.0..3.0) / radius, unit(rng));
        Spinning { radius, mass, spin }
    });
    let n = unit(rng);
    let e: f64 = rng.random_range(0.0..0.9);
    let t = {
        let a = unit(rng);
        let t = add_scaled(a, -dot(a, n), n);
        scale(1.0 / norm(t), t)
    };
    let speed: f64 = rng.random_range(0.5..3.0);
    let v = scale(speed, add_scaled(scale(e, t), -(1.0 - e * e).sqrt(), n));
    Impactor {
        bodies,
        r: scale(r1 + r2, n),
        v,
    }
}

fn m_eff(b: &[Spinning; 2]) -> f64 {
    b[0].mass * b[1].mass / (b[0].mass + b[1].mass)
}

fn inertia(s: &Spinning) -> f64 {
    SOLID_SPHERE_INERTIA * s.mass * s.radius * s.radius
}

/// Angular momentum about the centre of mass: m_eff r × v + I₁ω₁ + I₂ω₂.
fn angular_momentum(b: &[Spinning; 2], r: [f64; 3], v: [f64; 3], w: [[f64; 3]; 2]) -> [f64; 3] {
    let orbital = scale(m_eff(b), cross(r, v));
    add(
        orbital,
        add(scale(inertia(&b[0]), w[0]), scale(inertia(&b[1]), w[1])),
    )
}

fn energy(b: &[Spinning; 2], v: [f64; 3], w: [[f64; 3]; 2]) -> f64 {
    0.5 * m_eff(b) * dot(v, v)
        + 0.5 * inertia(&b[0]) * dot(w[0], w[0])
        + 0.5 * inertia(&b[1]) * dot(w[1], w[1])
}

fn solve_one(law: &PairLaw, f: &HistorySpring, i: &Impactor) -> FrictionalEnd {
    let out = solve_frictional(law, f, &i.bodies, i.r, i.v, &SolverOptions::default());
    out.unwrap_or_else(|e| panic!("{law:?} {f:?}: {e}"))
}

fn r_eff(b: &[Spinning; 2]) -> f64 {
    b[0].radius * b[1].radius / (b[0].radius + b[1].radius)
}

#[test]
fn without_friction_it_is_the_frictionless_solver() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for k in 0..8 {
        let imp = impactor(&mut rng, k % 2 == 1);
        let law = if k < 4 {
            linear(0.5)
        } else {
            hertz(1e-4, r_eff(&imp.bodies))
        };
        let out = solve_one(&law, &history(0.0, 1000.0, 0.3), &imp);
        let pair = PairProperties {
            l: imp.bodies[0].radius + imp.bodies[1].radius,
            m_eff: m_eff(&imp.bodies),
            r_eff: r_eff(&imp.bodies),
        };
        let impact = Impact::from_relative(
            &Vec3::new(imp.r[0], imp.r[1], imp.r[2]),
            &Vec3::new(imp.v[0], imp.v[1], imp.v[2]),
        )
        .unwrap();
        let scaled = scale_impact(&law, &pair, &impact).unwrap();
        let mor = solve(law.model(), &scaled.params).unwrap();
        let tau = mor.eps_t * scaled.time;
        assert!(
            (out.duration - tau).abs() < 1e-8 * tau,
            "{k}: τ {} vs {tau}",
            out.duration
        );
        let l = pair.l;
        assert!((norm(out.separation) - l * mor.eps_r).abs() < 1e-9 * l);
        let turned = dot(out.separation, imp.r) / (norm(out.separation) * l);
        assert!((turned - mor.eps_phi.cos()).abs() < 1e-8, "{k}: ε_φ");
        let rdot0 = dot(imp.v, imp.r) / l;
        let rdot1 = dot(out.velocity, out.separation) / norm(out.separation);
        assert!((rdot1 - mor.eps_rdot * rdot0).abs() < 1e-8 * norm(imp.v));
        for s in 0..2 {
            assert_eq!(out.spins[s], imp.bodies[s].spin, "µ = 0 keeps the spins");
        }
    }
}

#[test]
fn momenta_are_conserved_and_no_energy_is_created() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    for k in 0..16 {
        let imp = impactor(&mut rng, k % 2 == 1);
        let mu = [0.05, 0.2, 0.5, 1.0][k % 4];
        let law = if k < 8 {
            linear(0.3 * (k % 3) as f64)
        } else {
            hertz(2e-4 * (k % 3) as f64, r_eff(&imp.bodies))
        };
        let f = history(mu, 1500.0, 0.2 * (k % 2) as f64);
        let out = solve_one(&law, &f, &imp);
        let b = &imp.bodies;
        let w0 = [b[0].spin, b[1].spin];
        let l0 = angular_momentum(b, imp.r, imp.v, w0);
        let l1 = angular_momentum(b, out.separation, out.velocity, out.spins);
        let scale_l = m_eff(b) * norm(imp.r) * norm(imp.v);
        assert!(
            norm(sub(l1, l0)) < 1e-8 * scale_l,
            "{k}: ΔL/L = {:e}",
            norm(sub(l1, l0)) / scale_l
        );
        let (e0, e1) = (energy(b, imp.v, w0), energy(b, out.velocity, out.spins));
        assert!(e1 <= e0 * (1.0 + 1e-10), "{k}: energy {e0} -> {e1}");
        let spin_change = norm(sub(out.spins[0], w0[0])) * inertia(&b[0]);
        assert!(spin_change > 0.0 || mu == 0.0, "{k}: the spins must change");
    }
}

/// Found by fuzzing: a linear law of subnormal stiffness (1.2e-310 N/m) makes the first
/// step infinite, and an infinite step stayed infinite through every rejection (a hang).
/// The solve must end, with an answer or an error, within seconds.
#[test]
fn a_contact_too_soft_for_a_finite_step_ends_with_an_error() {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let law = PairLaw::Linear {
            stiffness: 1.168e-310,
            damping: 0.0,
        };
        let bodies = [
            Spinning {
                radius: 55.0,
                mass: 3.8e14,
                spin: [0.0; 3],
            },
            Spinning {
                radius: 5.1e4,
                mass: 5.7e10,
                spin: [0.0, 5.7e10, 5.7e10],
            },
        ];
        let result = solve_frictional(
            &law,
            &history(56.0, 119.0, 0.0),
            &bodies,
            [55.0 + 5.1e4, 0.0, 0.0],
            [-5.7e10, -5.7e10, -5.7e10],
            &SolverOptions::default(),
        );
        let _ = tx.send(result.is_err());
    });
    let failed = rx
        .recv_timeout(std::time::Duration::from_secs(20))
        .expect("the solve ended");
    assert!(failed, "an infinite step cannot give an answer");
}
