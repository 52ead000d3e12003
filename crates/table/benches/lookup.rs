//! Table lookup from physical parameters (two spheres and the impact: scaling,
//! rectangular coordinates and interpolation of all four components) against an exact
//! solve of the same impacts (the solver is a dev-dependency only).
//!
//! `cargo bench -p emdstar-table --bench lookup` (set EMDSTAR_TABLE_DIR to time other
//! tables than the shipped ones of `tables/`)
//!
//! Times are CPU time of the benchmark thread (on Linux; wall time elsewhere), so that
//! other processes on a shared machine do not inflate them.
//!
//! The impacts are drawn log-uniformly from the table's own box (its Tab. I or II
//! ranges), as `emdstar table check` does, and cycled through, so the lookups touch
//! scattered parts of the table as a polydisperse gas would.

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{Criterion, criterion_group, criterion_main};
use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, ScaledParams, Sphere,
    ViscoelasticHertz, scale,
};
use emdstar_table::Table;
use std::hint::black_box;

mod support;

use support::{Case, Draw, impacts, thread_cpu_ns};

/// Criterion measurement of thread CPU time.
struct CpuTime;

static WALL: WallTime = WallTime;

impl Measurement for CpuTime {
    type Intermediate = u64;
    type Value = u64;
    fn start(&self) -> u64 {
        thread_cpu_ns()
    }
    fn end(&self, start: u64) -> u64 {
        thread_cpu_ns() - start
    }
    fn add(&self, a: &u64, b: &u64) -> u64 {
        a + b
    }
    fn zero(&self) -> u64 {
        0
    }
    fn to_f64(&self, v: &u64) -> f64 {
        *v as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        WALL.formatter()
    }
}

/// Impacts of a monodisperse gas of one material: speeds log-uniform over a factor of
/// ten, eccentricities distributed as in a gas (e = √U, so P(e) ∝ e), inside the box.
/// `elastic`: no dissipation (A = 0 or γ = 0, as in the gas of `emdstar bench edmd`).
fn gas(table: &Table, n: usize, elastic: bool) -> Vec<Case> {
    let damping = if elastic { 0.0 } else { 1.0 };
    let (law, s, speeds) = match table.model() {
        // The eMD* gas of `emdstar bench edmd` (Y = 1 GPa, R = 0.1 m), with A = 10 µs.
        Model::Hertz => (
            ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, 1e-5 * damping).unwrap()),
            Sphere::from_density(0.1, 1140.0).unwrap(),
            [0.3, 3.0],
        ),
        Model::Linear => (
            ForceLaw::Linear(LinearDashpot::new(1e5, 0.5 * damping).unwrap()),
            Sphere::from_density(0.01, 2500.0).unwrap(),
            [0.1, 1.0],
        ),
    };
    let pair = PairProperties::spheres(&s, &s);
    let law = PairLaw::same_material(&law, pair.r_eff).unwrap();
    let mut d = Draw(0x2545_f491_4f6c_dd1d);
    let mut out = Vec::new();
    while out.len() < n {
        let impact =
            Impact::from_speed_eccentricity(d.log_uniform(speeds), d.next().sqrt()).unwrap();
        if table.lookup(&law, &pair, &impact).is_ok() {
            out.push((law, pair, impact));
        }
    }
    out
}

fn bench(c: &mut Criterion<CpuTime>) {
    let dir = std::env::var("EMDSTAR_TABLE_DIR")
        .unwrap_or_else(|_| concat!(env!("CARGO_MANIFEST_DIR"), "/../../tables").to_string());
    for model in [Model::Linear, Model::Hertz] {
        let table = Table::open(format!("{dir}/{model}.npz")).unwrap();
        for (label, cases) in [
            ("_box", impacts(&table, 1024, false)),
            ("_box_elastic", impacts(&table, 1024, true)),
            ("_gas", gas(&table, 1024, false)),
            ("_gas_elastic", gas(&table, 1024, true)),
            ("_one_impact", gas(&table, 1, false)),
        ] {
            let mut i = 0;
            c.bench_function(&format!("{model}/table_lookup_physical{label}"), |b| {
                b.iter(|| {
                    i = (i + 1) % cases.len();
                    let (law, pair, impact) = &cases[i];
                    black_box(table.lookup(black_box(law), pair, impact).unwrap())
                })
            });
            // The same impacts through pair handles built beforehand.
            let handles: Vec<_> = cases
                .iter()
                .map(|(law, pair, impact)| (table.pair(law, pair).unwrap(), *impact))
                .collect();
            let mut h = 0;
            c.bench_function(&format!("{model}/table_lookup_pair{label}"), |b| {
                b.iter(|| {
                    h = (h + 1) % handles.len();
                    let (handle, impact) = &handles[h];
                    black_box(handle.lookup(black_box(impact)).unwrap())
                })
            });
        }
        // One pair's impacts (the gas) through its own table, built beforehand.
        let cases = gas(&table, 1024, false);
        let own = table.pair_table(&cases[0].0, &cases[0].1).unwrap();
        let mut g = 0;
        c.bench_function(&format!("{model}/table_lookup_pair_table_gas"), |b| {
            b.iter(|| {
                g = (g + 1) % cases.len();
                black_box(own.lookup(black_box(&cases[g].2)).unwrap())
            })
        });
        let cases = impacts(&table, 1024, false);
        let scaled: Vec<ScaledParams> = cases
            .iter()
            .map(|(l, p, im)| scale(l, p, im).unwrap().params)
            .collect();
        let mut j = 0;
        c.bench_function(&format!("{model}/table_lookup_scaled"), |b| {
            b.iter(|| {
                j = (j + 1) % scaled.len();
                black_box(table.lookup_scaled(black_box(&scaled[j])).unwrap())
            })
        });
        let mut k = 0;
        c.bench_function(&format!("{model}/exact_solve"), |b| {
            b.iter(|| {
                k = (k + 1) % scaled.len();
                black_box(emdstar_mor::solve(model, black_box(&scaled[k])).unwrap())
            })
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(CpuTime);
    targets = bench
}
criterion_main!(benches);
