//! Impacts drawn as in the dilute frictional Hertz gas of the speed goals (shared by the
//! `frictional` bench and the `frictional_probe` example): spheres of R = 0.01 m,
//! ρ = 1140 kg/m³, Y = 1 GPa, ν = 0.4, restitution 0.8 at 1 m/s; relative velocities of a
//! gas of rms speed 1 m/s, impact parameters uniform over the disc, spins of about |v|/R
//! (none in one impact of four, as at the start of a run).

use emdstar_contact::PairLaw;
use emdstar_contact::vec3::sub;
use emdstar_contact::vec3::{add_scaled, cross, norm, scale};
use emdstar_mor::SolverOptions;
use emdstar_mor::frictional::{FrictionalEnd, HistorySpring, Spinning, solve_frictional};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub const RADIUS: f64 = 0.01;
const DENSITY: f64 = 1140.0;
/// A of restitution 0.8 at 1 m/s for this material (`emdstar run` prints it).
const DISSIPATION: f64 = 9.5266362041e-6;

pub struct Impact {
    pub bodies: [Spinning; 2],
    pub r: [f64; 3],
    pub v: [f64; 3],
}

fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    // Box–Muller.
    let (u, w): (f64, f64) = (rng.random_range(1e-300..1.0), rng.random_range(0.0..1.0));
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * w).cos()
}

pub fn impacts(count: usize, seed: u64) -> Vec<Impact> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mass = DENSITY * 4.0 / 3.0 * std::f64::consts::PI * RADIUS.powi(3);
    (0..count)
        .map(|k| {
            let sigma = (2.0f64 / 3.0).sqrt();
            let v: [f64; 3] = std::array::from_fn(|_| sigma * gaussian(&mut rng));
            let speed = norm(v);
            // The normal at touch: against v, off-centre by b uniform over the disc.
            let axis = scale(-1.0 / speed, v);
            let helper = if axis[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            let e1 = {
                let c = cross(axis, helper);
                scale(1.0 / norm(c), c)
            };
            let e2 = cross(axis, e1);
            let b = rng.random_range(0.0f64..0.999).sqrt();
            let turn = rng.random_range(0.0..std::f64::consts::TAU);
            let side = add_scaled(scale(turn.cos(), e1), turn.sin(), e2);
            let n = add_scaled(scale((1.0 - b * b).sqrt(), axis), b, side);
            let spin_scale = if k % 4 == 3 {
                0.0
            } else {
                0.5 * speed / RADIUS
            };
            let spins = [0, 1].map(|_| std::array::from_fn(|_| spin_scale * gaussian(&mut rng)));
            Impact {
                bodies: spins.map(|spin| Spinning {
                    radius: RADIUS,
                    mass,
                    spin,
                }),
                r: scale(2.0 * RADIUS, n),
                v,
            }
        })
        .collect()
}

pub fn law() -> PairLaw {
    let e_star = 1e9 / (2.0 * (1.0 - 0.4 * 0.4));
    PairLaw::Hertz {
        rho_el: 4.0 / 3.0 * e_star * (0.5 * RADIUS).sqrt(),
        dissipation: DISSIPATION,
    }
}

/// The sphere–wall law of the same material (E* = Y/(1 − ν²), R_eff = R).
pub fn wall_law() -> PairLaw {
    let e_star = 1e9 / (1.0 - 0.4 * 0.4);
    PairLaw::Hertz {
        rho_el: 4.0 / 3.0 * e_star * RADIUS.sqrt(),
        dissipation: DISSIPATION,
    }
}

/// Prints the work per solve: steps, right-hand-side evaluations, switches.
pub fn report(name: &str, ends: &[FrictionalEnd]) {
    let n = ends.len() as f64;
    let sum = |f: &dyn Fn(&FrictionalEnd) -> usize| ends.iter().map(f).sum::<usize>() as f64 / n;
    eprintln!(
        "{name}: {:.1} accepted, {:.2} rejected steps, {:.0} rhs evaluations, {:.2} switches \
         per solve",
        sum(&|e| e.stats.accepted_steps),
        sum(&|e| e.stats.rejected_steps),
        sum(&|e| e.stats.rhs_evaluations),
        sum(&|e| e.switches),
    );
}

/// The distance of each of `ends` from the reference at 1e-12 over `points` (positions in
/// units of l, velocities and spins·R in units of |v|).
pub fn errors(
    law: &PairLaw,
    spring: &HistorySpring,
    points: &[Impact],
    ends: &[FrictionalEnd],
) -> Vec<f64> {
    let tight = SolverOptions {
        rtol: 1e-12,
        atol: 1e-12,
        ..SolverOptions::default()
    };
    points
        .iter()
        .zip(ends)
        .map(|(i, a)| {
            let b = solve_frictional(law, spring, &i.bodies, i.r, i.v, &tight).unwrap();
            let speed = norm(i.v);
            let d = |x: [f64; 3], y: [f64; 3]| norm(sub(x, y));
            (d(a.separation, b.separation) / (2.0 * RADIUS))
                .max(d(a.velocity, b.velocity) / speed)
                .max(d(a.spins[0], b.spins[0]) * RADIUS / speed)
                .max(d(a.spins[1], b.spins[1]) * RADIUS / speed)
        })
        .collect()
}
