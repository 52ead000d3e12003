//! Solves per second of the MoR solver at the default options (`cargo bench -p emdstar-mor`):
//! averaged over random points of each paper rectangle, and at single corners — the stiff
//! Hertz corner (largest c_dis) and the largest-l̃ corner of each rectangle. The work per
//! solve (accepted/rejected steps, right-hand-side evaluations) is printed once per case.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use emdstar_contact::{Model, ParameterBox, RectCoords, ScaledParams};
use emdstar_mor::{SolverOptions, solve_with};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Duration;

fn rect_points(model: Model, n: usize) -> Vec<ScaledParams> {
    let bounds = ParameterBox::paper(model).bounds().unwrap();
    let [a, b, c] = bounds.axes();
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    (0..n)
        .map(|_| {
            bounds.from_rect(&RectCoords {
                a: rng.random_range(a.min..=a.max),
                b: rng.random_range(b.min..=b.max),
                c: rng.random_range(c.min..=c.max),
            })
        })
        .collect()
}

/// The rectangle corner maximising `key`.
fn corner_by(model: Model, key: impl Fn(&ScaledParams) -> f64) -> ScaledParams {
    let bounds = ParameterBox::paper(model).bounds().unwrap();
    let [a, b, c] = bounds.axes();
    (0..8)
        .map(|m| {
            let pick = |r: emdstar_contact::Range, bit: u32| {
                if m & (1 << bit) == 0 { r.min } else { r.max }
            };
            bounds.from_rect(&RectCoords {
                a: pick(a, 0),
                b: pick(b, 1),
                c: pick(c, 2),
            })
        })
        .max_by(|p, q| key(p).total_cmp(&key(q)))
        .unwrap()
}

fn report(name: &str, model: Model, points: &[ScaledParams]) {
    let o = SolverOptions::default();
    let (mut acc, mut rej, mut ev) = (0, 0, 0);
    for p in points {
        let (_, s) = solve_with(model, p, &o).unwrap();
        acc += s.accepted_steps;
        rej += s.rejected_steps;
        ev += s.rhs_evaluations;
    }
    let n = points.len() as f64;
    eprintln!(
        "{name}: {:.1} accepted, {:.2} rejected steps, {:.0} rhs evaluations per solve",
        acc as f64 / n,
        rej as f64 / n,
        ev as f64 / n
    );
}

fn bench(c: &mut Criterion) {
    let o = SolverOptions::default();
    let mut cases = Vec::new();
    for model in [Model::Linear, Model::Hertz] {
        cases.push((
            format!("{model}/random_rectangle"),
            model,
            rect_points(model, 256),
        ));
        cases.push((
            format!("{model}/largest_l_corner"),
            model,
            vec![corner_by(model, |p| p.l_tilde)],
        ));
    }
    cases.push((
        "hertz/stiff_corner".into(),
        Model::Hertz,
        vec![corner_by(Model::Hertz, |p| p.c_dis)],
    ));
    let mut group = c.benchmark_group("mor_solve");
    for (name, model, points) in &cases {
        report(name, *model, points);
        group.throughput(Throughput::Elements(points.len() as u64));
        group.bench_function(name.as_str(), |b| {
            b.iter(|| {
                for p in points {
                    black_box(solve_with(*model, black_box(p), &o).unwrap());
                }
            })
        });
    }
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
