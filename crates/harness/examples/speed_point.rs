use emdstar_contact::{ForceLaw, ViscoelasticHertz};
use emdstar_harness::engines::{EventKind, event_engine, lattice_gas};
fn main() {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(a[1], 0.4, 0.0).unwrap());
    let system = lattice_gas(&law, 1140.0, 0.1, a[2] as usize, a[0], 2.0, 1).unwrap();
    let mut e = event_engine(&system, EventKind::EmdStarTable).unwrap();
    let t = std::time::Instant::now();
    e.run_until(a[3]).unwrap();
    let w = t.elapsed().as_secs_f64();
    println!(
        "wall {w:.3} cost {:.3e} coll {} {:?}",
        w / a[3],
        e.stats().pair_collisions,
        e.stats()
    );
}
