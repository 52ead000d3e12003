//! eMD* (default table) alone on the speed check's elastic Hertz gas, for profiling:
//! events, crossings and cost per simulated second at any packing fraction, Young's
//! modulus and size (`emdstar validate --only speed` measures MD against it).
//!
//! ```text
//! cargo run --release -p emdstar-harness --example speed_probe -- ETA YOUNG N SECONDS
//! ```
//!
//! SECONDS > 0 runs for that many wall seconds; SECONDS < 0 runs for −SECONDS pair
//! collisions (a fixed amount of work, e.g. under `valgrind --tool=callgrind`).
//! `BROAD=auto|crossings|epochs` chooses the broad phase (default auto, as `emdstar`
//! does), `CELL_WIDTH=m` the cell width of crossings (default automatic),
//! `RESORT=events` the re-sorting interval (0: never).

use emdstar_contact::{ForceLaw, ViscoelasticHertz};
use emdstar_edmd::rules::TableMorSource;
use emdstar_edmd::{BroadPhaseKind, Engine, Interference, Physics};
use emdstar_harness::engines::lattice_gas;
use emdstar_harness::exceptions::{DENSITY, POISSON, RADIUS, RMS_SPEED};
use std::time::Instant;

fn env_number(name: &str) -> Result<Option<f64>, String> {
    match std::env::var(name) {
        Ok(v) => v
            .parse()
            .map(Some)
            .map_err(|_| format!("{name} = {v:?} is not a number")),
        Err(_) => Ok(None),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{e}; usage: speed_probe ETA YOUNG N SECONDS"))?;
    let [eta, young, n, seconds] = args[..] else {
        return Err("usage: speed_probe ETA YOUNG N SECONDS".into());
    };
    let n = n as usize;
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(young, POISSON, 0.0)?);
    let system = lattice_gas(&law, DENSITY, RADIUS, n, eta, RMS_SPEED, 1)?;
    let physics = Physics::EmdStar {
        interactions: system.interactions().clone(),
        mor: Box::new(TableMorSource::new(
            emdstar_table::default_table(law.model())?,
            true,
        )),
        interference: Interference::HitOnly,
    };
    let width = env_number("CELL_WIDTH")?.unwrap_or(0.0);
    let (p, d) = (&system.particles, &system.domain);
    let mut e: Engine = match std::env::var("BROAD").as_deref() {
        Ok("crossings") => Engine::with_cell_width(p, d, physics, width)?,
        Ok("epochs") => Engine::with_broad_phase(p, d, physics, BroadPhaseKind::Epochs)?,
        Ok("auto") | Err(_) => Engine::with_broad_phase(p, d, physics, BroadPhaseKind::Auto)?,
        Ok(other) => return Err(format!("BROAD = {other:?}: use auto, crossings or epochs").into()),
    };
    if let Some(r) = env_number("RESORT")? {
        e.set_resort_interval(r as u64);
    }
    e.run_collisions((n / 10) as u64)?;
    let (t0, ev0, c0, x0) = (
        e.time(),
        e.stats().events,
        e.stats().pair_collisions,
        e.stats().crossings,
    );
    let start = Instant::now();
    if seconds < 0.0 {
        e.run_collisions(-seconds as u64)?;
    }
    while start.elapsed().as_secs_f64() < seconds {
        e.run_collisions((n / 10).max(1) as u64)?;
    }
    let wall = start.elapsed().as_secs_f64();
    let s = e.stats();
    let events = s.events - ev0;
    println!(
        "simulated {:.4} s in {wall:.3} s: {:.4e} wall s per simulated s; {events} events \
         ({} crossings, {} pair collisions, {} epochs), {:.1} ns per event",
        e.time() - t0,
        wall / (e.time() - t0),
        s.crossings - x0,
        s.pair_collisions - c0,
        s.epochs,
        wall * 1e9 / events as f64
    );
    println!(
        "over the whole run: {} E^v events, {} stale events, {} exceptions",
        s.velocity_events,
        s.stale,
        s.exceptions()
    );
    Ok(())
}
