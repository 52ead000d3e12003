//! The one interface of every engine: advance to a time, read the thermo quantities
//! and the state, save the whole state and restore it.

use crate::domain::Domain;
use crate::state::Particles;
use crate::stress::{StressMark, StressSums};
use crate::writers::Thermo;

/// Why an engine could not go on: its own error, boxed (each message says what was
/// wrong and how to fix it).
pub type SimulationError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// What [`Simulation::change_velocities`] applies: the velocities in config order, to
/// change in place, and the masses.
pub type VelocityChange<'a> = dyn FnMut(&mut [[f64; 3]], &[f64]) + 'a;

/// A simulation run by any engine of the workspace (force-based MD, the event engines,
/// the hybrid), as the command line and the cross-validation harness drive it.
///
/// # Contract
/// - **Lazy state, exact trajectories.** An engine may keep part of its state behind
///   the present (event engines move a particle on only when it takes part in an
///   event; MD keeps its velocities half a kick behind between steps). Readouts
///   ([`Simulation::thermo`], [`Simulation::particles`]) bring nothing forward: where
///   a caller stops and reads does not change the trajectory, so a run advanced in any
///   number of pieces is bitwise the run advanced at once.
/// - **Restarts.** [`Simulation::save_state`] holds everything the engine needs to go
///   on (no wall clock, no host data): an engine built from the same config and
///   options, given those bytes by [`Simulation::restore_state`], continues bitwise as
///   the saved one would have. The same state saves to the same bytes however it was
///   reached.
pub trait Simulation {
    /// The engine's name in reports: "md", "emd", "emdstar" or "hybrid".
    fn engine(&self) -> &'static str;

    /// Simulated time in s.
    fn time(&self) -> f64;

    /// The fixed time step of an engine that takes steps: [`Simulation::advance_to`]
    /// then ends on the step boundary nearest its target. `None` for event engines,
    /// which reach any time exactly.
    fn time_step(&self) -> Option<f64>;

    /// Steps or events done so far (the `step` column of the thermo log).
    fn steps_done(&self) -> u64;

    /// Advances to time `t` (no earlier than now). Stops earlier, between two events
    /// or steps, when a stop is requested ([`crate::stop`]): the engine checks at each
    /// event or step, and its time is then that of the last one.
    fn advance_to(&mut self, t: f64) -> Result<(), SimulationError>;

    /// Brings the stored state to the present (delayed updates, pending half kicks).
    /// Nothing physical changes, only the rounding of what follows; callers that must
    /// reproduce a computation which did so at the same points call it.
    fn synchronise(&mut self) -> Result<(), SimulationError> {
        Ok(())
    }

    /// Energies, granular temperature, momentum and contacts now.
    fn thermo(&self) -> Thermo;

    /// The sums behind the pressure tensor and the collision rate, from the start of
    /// the run to now (see [`StressSums`]).
    fn stress_sums(&self) -> StressSums;

    /// The sums and time [`Simulation::mark_stress`] kept last (none before).
    fn stress_mark(&self) -> Option<StressMark>;

    /// Keeps the sums now and the time as the mark (saved with the state): where the
    /// thermo log's next interval starts.
    fn mark_stress(&mut self);

    /// Changes the velocities now: `change` gets them in config order (in step with the
    /// positions) with the masses, and the engine goes on from what it left (a thermostat's
    /// tick, [`crate::Drive`]). Engines that cannot say why.
    fn change_velocities(&mut self, change: &mut VelocityChange<'_>)
    -> Result<(), SimulationError>;

    /// The particles now, in config order; a particle inside an eMD* collision shows
    /// the velocity it will leave with.
    fn particles(&self) -> Particles;

    /// The box, walls and gravity.
    fn domain(&self) -> &Domain;

    /// The whole state, for a checkpoint (see the contract).
    fn save_state(&self) -> Vec<u8>;

    /// Replaces the state by one [`Simulation::save_state`] gave (see the contract).
    fn restore_state(&mut self, state: &[u8]) -> Result<(), SimulationError>;
}
