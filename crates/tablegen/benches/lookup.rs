//! Table lookup from physical parameters (scaling, rectangular coordinates and
//! interpolation of all four components) against one exact solve.
//!
//! `cargo bench -p emdstar-tablegen --bench lookup`

use criterion::{Criterion, criterion_group, criterion_main};
use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, Sphere, ViscoelasticHertz,
    scale,
};
use emdstar_table::default_table;
use std::hint::black_box;

/// Impacts inside the paper's boxes: (law, pair, impact), cycled through by the bench.
fn impacts(model: Model) -> Vec<(PairLaw, PairProperties, Impact)> {
    let mut out = Vec::new();
    for (i, radius) in [0.002, 0.01, 0.05].into_iter().enumerate() {
        let s = Sphere::from_density(radius, 1500.0 + 500.0 * i as f64).unwrap();
        let pair = PairProperties::spheres(&s, &s);
        let law = match model {
            Model::Linear => {
                ForceLaw::Linear(LinearDashpot::new(2e4 * (i + 1) as f64, 0.05).unwrap())
            }
            Model::Hertz => ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, 1e-5).unwrap()),
        };
        let law = PairLaw::same_material(&law, pair.r_eff).unwrap();
        for v in [0.1, 1.0, 5.0] {
            for e in [0.05, 0.3, 0.7, 0.95] {
                out.push((law, pair, Impact::from_speed_eccentricity(v, e).unwrap()));
            }
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    for model in [Model::Linear, Model::Hertz] {
        let table = default_table(model).unwrap();
        let cases = impacts(model);
        for (law, pair, impact) in &cases {
            table
                .lookup(law, pair, impact)
                .expect("bench impacts lie in the box");
        }
        let mut i = 0;
        c.bench_function(&format!("{model}/table_lookup_physical"), |b| {
            b.iter(|| {
                i = (i + 1) % cases.len();
                let (law, pair, impact) = &cases[i];
                black_box(table.lookup(black_box(law), pair, impact).unwrap())
            })
        });
        let scaled: Vec<_> = cases
            .iter()
            .map(|(l, p, im)| scale(l, p, im).unwrap().params)
            .collect();
        let mut j = 0;
        c.bench_function(&format!("{model}/exact_solve"), |b| {
            b.iter(|| {
                j = (j + 1) % scaled.len();
                black_box(emdstar_mor::solve(model, black_box(&scaled[j])).unwrap())
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
