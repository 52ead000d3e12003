//! Solves per second of the exact frictional contact (`cargo bench -p emdstar-mor --bench
//! frictional`) on impacts drawn as in a dilute frictional Hertz gas: spheres of
//! R = 0.01 m, ρ = 1140 kg/m³, Y = 1 GPa, ν = 0.4, restitution 0.8 at 1 m/s, µ = 0.3,
//! k_t = 10⁵ N/m, γ_t = 0; relative velocities of a gas of rms speed 1 m/s, impact
//! parameters uniform over the disc, spins of about |v|/R. The work per solve (steps,
//! right-hand-side evaluations, stick–slip switches) is printed once per case.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use emdstar_contact::vec3::{add_scaled, cross, dot, norm, scale};
use emdstar_contact::{Friction, PairLaw, TangentialModel};
use emdstar_mor::SolverOptions;
use emdstar_mor::frictional::{HistorySpring, Spinning, solve_contact, solve_frictional};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::{Duration, Instant};

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
        .map(|_| {
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
            let spins =
                [0, 1].map(|_| std::array::from_fn(|_| 0.5 * speed / RADIUS * gaussian(&mut rng)));
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
        .filter(|i| dot(i.v, i.r) < 0.0)
        .collect()
}

fn law() -> PairLaw {
    let e_star = 1e9 / (2.0 * (1.0 - 0.4 * 0.4));
    PairLaw::Hertz {
        rho_el: 4.0 / 3.0 * e_star * (0.5 * RADIUS).sqrt(),
        dissipation: DISSIPATION,
    }
}

fn bench(c: &mut Criterion) {
    let law = law();
    let friction = Friction::new(0.3, 1e5, 0.0, TangentialModel::History).unwrap();
    let o = SolverOptions::default();
    let points = impacts(256, 7);
    let (mut acc, mut rej, mut ev, mut sw) = (0, 0, 0, 0);
    let start = Instant::now();
    for i in &points {
        let end = solve_frictional(&law, &friction, &i.bodies, i.r, i.v, &o).unwrap();
        acc += end.stats.accepted_steps;
        rej += end.stats.rejected_steps;
        ev += end.stats.rhs_evaluations;
        sw += end.switches;
    }
    let n = points.len() as f64;
    eprintln!(
        "gas impacts: {:.1} accepted, {:.2} rejected steps, {:.0} rhs evaluations, {:.2} \
         switches per solve; {:.2} µs per solve (one pass)",
        acc as f64 / n,
        rej as f64 / n,
        ev as f64 / n,
        sw as f64 / n,
        start.elapsed().as_secs_f64() / n * 1e6
    );
    let reference = SolverOptions {
        rtol: 1e-13,
        atol: 1e-13,
        ..o
    };
    for tol in [1e-7, 1e-8, 1e-9, 1e-10, 1e-11] {
        let opts = SolverOptions {
            rtol: tol,
            atol: tol,
            ..o
        };
        let (mut ev, mut acc, mut rej, mut worst) = (0, 0, 0, 0.0f64);
        let spring = HistorySpring::of(&friction).unwrap();
        let start = Instant::now();
        for i in &points {
            let a = solve_contact(&law, &spring, &i.bodies, i.r, i.v, &opts).unwrap();
            ev += a.stats.rhs_evaluations;
            acc += a.stats.accepted_steps;
            rej += a.stats.rejected_steps;
            let b = solve_frictional(&law, &friction, &i.bodies, i.r, i.v, &reference).unwrap();
            let speed = norm(i.v);
            let d = |x: [f64; 3], y: [f64; 3]| norm(emdstar_contact::vec3::sub(x, y));
            let e = (d(a.separation, b.separation) / (2.0 * RADIUS))
                .max(d(a.velocity, b.velocity) / speed)
                .max(d(a.spins[0], b.spins[0]) * RADIUS / speed)
                .max(d(a.spins[1], b.spins[1]) * RADIUS / speed);
            worst = worst.max(e);
        }
        let el = start.elapsed().as_secs_f64();
        let t0 = Instant::now();
        for i in &points {
            black_box(solve_contact(&law, &spring, &i.bodies, i.r, i.v, &opts).unwrap());
        }
        let fast = t0.elapsed().as_secs_f64() / n * 1e6;
        eprintln!(
            "tol {tol:e}: {:.0} evaluations, {:.1} accepted, {:.1} rejected, worst error {worst:.2e}, {:.1} µs per pair of solves, {fast:.2} µs per fast solve",
            ev as f64 / n,
            acc as f64 / n,
            rej as f64 / n,
            el / n * 1e6
        );
    }
    let mut group = c.benchmark_group("frictional");
    group.throughput(Throughput::Elements(points.len() as u64));
    group.bench_function("solve_frictional/gas", |b| {
        b.iter(|| {
            for i in &points {
                black_box(
                    solve_frictional(&law, &friction, &i.bodies, i.r, black_box(i.v), &o).unwrap(),
                );
            }
        })
    });
    let spring = HistorySpring::of(&friction).unwrap();
    group.bench_function("solve_contact/gas", |b| {
        b.iter(|| {
            for i in &points {
                black_box(
                    solve_contact(
                        &law,
                        &spring,
                        &i.bodies,
                        i.r,
                        black_box(i.v),
                        &emdstar_mor::frictional::CONTACT_OPTIONS,
                    )
                    .unwrap(),
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
