use emdstar_contact::{ForceLaw, ViscoelasticHertz};
use emdstar_edmd::rules::TableMorSource;
use emdstar_edmd::*;
use emdstar_harness::engines::{EventKind, event_engine, lattice_gas};
use std::time::Instant;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let (eta, young, n, secs) = (args[0], args[1], args[2] as usize, args[3]);
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(young, 0.4, 0.0).unwrap());
    let system = lattice_gas(&law, 1140.0, 0.1, n, eta, 2.0, 1).unwrap();
    let width: f64 = std::env::var("W")
        .ok()
        .map(|v| v.parse().unwrap())
        .unwrap_or(0.0);
    let mut e = if width > 0.0 {
        let materials = Materials::from_system(&system).unwrap();
        let physics = Physics::EmdStar {
            materials,
            mor: Box::new(TableMorSource::default_for(system.material.model(), true).unwrap()),
            interference: Interference::HitOnly,
        };
        Engine::with_cell_width(Setup::from_system(&system), physics, width).unwrap()
    } else {
        event_engine(&system, EventKind::EmdStarTable).unwrap()
    };
    if let Ok(r) = std::env::var("RESORT") {
        e.set_resort_interval(r.parse().unwrap());
    }
    e.run_collisions((n / 10) as u64).unwrap();
    let (t0, ev0, c0) = (e.time(), e.stats().events, e.stats().pair_collisions);
    let start = Instant::now();
    if secs < 0.0 {
        e.run_collisions((-secs) as u64).unwrap();
    }
    while start.elapsed().as_secs_f64() < secs {
        e.run_collisions((n / 10) as u64).unwrap();
    }
    let w = start.elapsed().as_secs_f64();
    let s = e.stats();
    println!(
        "sim {:.3} wall {:.3} cost {:.3e} events {} coll {} cross {} ns/event {:.1} wall/sim {:.3e}",
        e.time() - t0,
        w,
        w / (e.time() - t0),
        s.events - ev0,
        s.pair_collisions - c0,
        s.crossings,
        w * 1e9 / (s.events - ev0) as f64,
        w / (e.time() - t0)
    );
    println!("{:?}", s);
}
