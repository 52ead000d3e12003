//! A run driven by a thermostat (`[driving]`, [`Drive`]): the engine advanced from
//! tick to tick, each tick applied through [`Simulation::change_velocities`] when the
//! engine reaches it.

use emdstar_system::{Drive, Simulation, SimulationError, stop};

/// Advances `sim` to `t` (as [`Simulation::advance_to`]), applying every tick of
/// `drive` up to and at `t` on the way. A step engine reaches a tick at its nearest
/// step; ticks within half a step of where it stands count as passed. Stops early,
/// between ticks, when a stop is requested.
pub fn advance(
    sim: &mut dyn Simulation,
    drive: Option<&Drive>,
    t: f64,
) -> Result<(), SimulationError> {
    let Some(drive) = drive else {
        return sim.advance_to(t);
    };
    let tolerance = sim.time_step().map_or(0.0, |dt| 0.5 * dt);
    loop {
        let k = drive.ticks_until(sim.time() + tolerance) + 1;
        let tick = drive.tick_time(k);
        if tick > t + tolerance {
            return sim.advance_to(t);
        }
        sim.advance_to(tick)?;
        if sim.time() + tolerance < tick || stop::is_requested() {
            return Ok(());
        }
        sim.change_velocities(&mut |v, m| drive.apply(k, v, m))?;
    }
}
