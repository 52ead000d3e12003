//! Solves per second of the exact frictional contact (`cargo bench -p emdstar-mor --bench
//! frictional`) on impacts drawn as in the dilute frictional Hertz gas of the speed goals:
//! spheres of R = 0.01 m, ρ = 1140 kg/m³, Y = 1 GPa, ν = 0.4, restitution 0.8 at 1 m/s,
//! µ = 0.3, k_t = 10⁵ N/m, γ_t = 0; relative velocities of a gas of rms speed 1 m/s,
//! impact parameters uniform over the disc, spins of about |v|/R (none in one impact of
//! four, as at the start of a run). Cases: the reference solver at its default 1e-11,
//! the fast solver at eMD*'s `CONTACT_OPTIONS`, and the fast solver at a wall. The work
//! per solve (steps, right-hand-side evaluations, stick–slip switches) and the fast
//! solver's distance from the reference at 1e-12 are printed once.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use emdstar_contact::PairLaw;
use emdstar_contact::vec3::{add_scaled, cross, dot, norm, scale, sub};
use emdstar_mor::SolverOptions;
use emdstar_mor::frictional::{
    CONTACT_OPTIONS, FrictionalEnd, HistorySpring, Spinning, solve_contact, solve_frictional,
    solve_wall_contact,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Duration;

const RADIUS: f64 = 0.01;
const DENSITY: f64 = 1140.0;
/// A of restitution 0.8 at 1 m/s for this material (`emdstar run` prints it).
const DISSIPATION: f64 = 9.5266362041e-6;

struct Impact {
    bodies: [Spinning; 2],
    r: [f64; 3],
    v: [f64; 3],
}

fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    // Box–Muller.
    let (u, w): (f64, f64) = (rng.random_range(1e-300..1.0), rng.random_range(0.0..1.0));
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * w).cos()
}

fn impacts(count: usize, seed: u64) -> Vec<Impact> {
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

fn law() -> PairLaw {
    let e_star = 1e9 / (2.0 * (1.0 - 0.4 * 0.4));
    PairLaw::Hertz {
        rho_el: 4.0 / 3.0 * e_star * (0.5 * RADIUS).sqrt(),
        dissipation: DISSIPATION,
    }
}

/// The sphere–wall law of the same material (E* = Y/(1 − ν²), R_eff = R).
fn wall_law() -> PairLaw {
    let e_star = 1e9 / (1.0 - 0.4 * 0.4);
    PairLaw::Hertz {
        rho_el: 4.0 / 3.0 * e_star * RADIUS.sqrt(),
        dissipation: DISSIPATION,
    }
}

fn report(name: &str, ends: &[FrictionalEnd]) {
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

fn bench(c: &mut Criterion) {
    let law = law();
    let spring = HistorySpring::new(0.3, 1e5, 0.0).unwrap();
    let friction = spring;
    let o = SolverOptions::default();
    let points = impacts(256, 7);
    let reference: Vec<_> = points
        .iter()
        .map(|i| solve_frictional(&law, &friction, &i.bodies, i.r, i.v, &o).unwrap())
        .collect();
    report("reference (1e-11)", &reference);
    let fast: Vec<_> = points
        .iter()
        .map(|i| solve_contact(&law, &spring, &i.bodies, i.r, i.v, &CONTACT_OPTIONS).unwrap())
        .collect();
    report("fast (CONTACT_OPTIONS)", &fast);
    let tight = SolverOptions {
        rtol: 1e-12,
        atol: 1e-12,
        ..o
    };
    let worst = points
        .iter()
        .zip(&fast)
        .map(|(i, a)| {
            let b = solve_frictional(&law, &friction, &i.bodies, i.r, i.v, &tight).unwrap();
            let speed = norm(i.v);
            let d = |x: [f64; 3], y: [f64; 3]| norm(sub(x, y));
            (d(a.separation, b.separation) / (2.0 * RADIUS))
                .max(d(a.velocity, b.velocity) / speed)
                .max(d(a.spins[0], b.spins[0]) * RADIUS / speed)
                .max(d(a.spins[1], b.spins[1]) * RADIUS / speed)
        })
        .fold(0.0, f64::max);
    eprintln!(
        "fast against the reference at 1e-12: worst {worst:.2e} (positions/l, velocities and \
         spins·R over |v|)"
    );
    // The same impacts against a wall: the first sphere, its normal and velocity.
    let wall_law = wall_law();
    let walls: Vec<_> = points
        .iter()
        .map(|i| (i.bodies[0], scale(1.0 / norm(i.r), i.r), i.v))
        .filter(|(_, n, v)| dot(*n, *v) < 0.0)
        .collect();
    let at_walls: Vec<_> = walls
        .iter()
        .map(|(b, n, v)| {
            solve_wall_contact(&wall_law, &spring, b, *n, *v, &CONTACT_OPTIONS).unwrap()
        })
        .collect();
    report("fast, at a wall", &at_walls);

    let mut group = c.benchmark_group("frictional");
    group.throughput(Throughput::Elements(points.len() as u64));
    group.bench_function("reference/gas", |b| {
        b.iter(|| {
            for i in &points {
                black_box(
                    solve_frictional(&law, &friction, &i.bodies, i.r, black_box(i.v), &o).unwrap(),
                );
            }
        })
    });
    group.bench_function("fast/gas", |b| {
        b.iter(|| {
            for i in &points {
                let v = black_box(i.v);
                black_box(
                    solve_contact(&law, &spring, &i.bodies, i.r, v, &CONTACT_OPTIONS).unwrap(),
                );
            }
        })
    });
    group.throughput(Throughput::Elements(walls.len() as u64));
    group.bench_function("fast/wall", |b| {
        b.iter(|| {
            for (body, n, v) in &walls {
                let v = black_box(*v);
                black_box(
                    solve_wall_contact(&wall_law, &spring, body, *n, v, &CONTACT_OPTIONS).unwrap(),
                );
            }
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(20);
    targets = bench
}
criterion_main!(benches);
