//! The observables of the thermo log and the run summary, read from any engine: the
//! pressure tensor and the collision rate over an interval from two readings of the
//! engine's [`emdstar_system::StressSums`], the Sonine coefficient a₂ now.

use emdstar_system::{Observables, Simulation, StressMark, sonine_a2};

/// `sim`'s sums now, as a mark.
pub fn reading(sim: &dyn Simulation) -> StressMark {
    StressMark {
        t: sim.time(),
        sums: sim.stress_sums(),
    }
}

/// The observables of `sim` between `from` and now (pressure and collision rate NaN
/// without an interval or without a box), a₂ now.
pub fn since(sim: &dyn Simulation, from: Option<&StressMark>) -> Observables {
    let mut particles = sim.particles();
    if let Some(le) = sim.domain().lees_edwards() {
        // Under shear a₂ is that of the velocities relative to the streaming profile.
        le.peculiar(&mut particles);
    }
    let a2 = sonine_a2(&particles);
    let now = reading(sim);
    let volume = sim
        .domain()
        .sim_box
        .as_ref()
        .map_or(f64::NAN, |b| b.volume());
    match from {
        Some(from) if now.t > from.t => Observables::between(
            &from.sums,
            &now.sums,
            now.t - from.t,
            volume,
            particles.len(),
            a2,
        ),
        _ => Observables {
            sonine_a2: a2,
            ..Observables::UNKNOWN
        },
    }
}
