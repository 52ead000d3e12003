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
use emdstar_contact::vec3::{dot, norm, scale};
use emdstar_mor::SolverOptions;
use emdstar_mor::frictional::{
    CONTACT_OPTIONS, HistorySpring, solve_contact, solve_frictional, solve_wall_contact,
};
use std::hint::black_box;
use std::time::Duration;

#[path = "shared/gas_impacts.rs"]
mod gas_impacts;

use gas_impacts::{errors, impacts, law, report, wall_law};

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
    let worst = errors(&law, &friction, &points, &fast)
        .into_iter()
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
